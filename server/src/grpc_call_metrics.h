#pragma once

#include <grpcpp/support/server_interceptor.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "metrics_exposition.h"

namespace soltex::server {

// Per-method counters of one gRPC method, in the labels of the go-grpc-prometheus convention
// (grpc_type, grpc_service, grpc_method, grpc_code).
struct MethodCallCounters {
  std::string type;     // unary, client_stream, server_stream, bidi_stream
  std::string service;  // soltex.v1.BrickService
  std::string method;   // StreamBricks
  std::atomic<uint64_t> started{0};
  std::atomic<uint64_t> messages_received{0};
  std::atomic<uint64_t> messages_sent{0};
  std::array<std::atomic<uint64_t>, 17> handled{};  // by grpc::StatusCode
  // Calls gRPC ended before the server's status reached the client: the client cancelled or
  // went away, its deadline passed, or gRPC refused a message over the size limit. These are
  // also counted in handled[CANCELLED]: the server cannot tell which happened.
  std::atomic<uint64_t> cut_short{0};
};

// Counts every call the server sees, with a server interceptor: calls of every service
// (health and reflection too), and calls that gRPC refused or cut short before a handler
// ran or its status was sent, which the handlers themselves never see.
class GrpcCallMetrics {
 public:
  // The counters of `full_method` ("/package.Service/Method"), created on first use; a
  // method the binary does not define shares one entry, service and method "unknown". The
  // reference stays valid for the life of this object.
  MethodCallCounters& counters(const std::string& full_method,
                               grpc::experimental::ServerRpcInfo::Type type);

  // grpc_server_started_total, _handled_total, _msg_received_total, _msg_sent_total and
  // soltex_grpc_calls_cut_short_total, with the families from the daemon's table.
  struct Families {
    const MetricFamily& started;
    const MetricFamily& handled;
    const MetricFamily& received;
    const MetricFamily& sent;
    const MetricFamily& cut_short;
  };
  void write(Exposition& exposition, const Families& families) const;

  // The interceptor factory to hand to grpc::ServerBuilder. Calls of `callback_services`
  // (callback API) are also checked for having been cut short by gRPC.
  std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface> interceptor_factory(
      std::vector<std::string> callback_services);

 private:
  mutable std::mutex mutex_;
  std::deque<MethodCallCounters> methods_;  // a deque: references stay valid as it grows
  std::unordered_map<std::string, MethodCallCounters*> by_name_;  // defined methods only
  MethodCallCounters* unknown_ = nullptr;  // every undefined method's calls, once one came

  static constexpr const char* kUnknownName = "unknown";
};

// The canonical name of a gRPC status code ("RESOURCE_EXHAUSTED"), "UNKNOWN" past 16.
const char* grpc_code_name(int code);

}  // namespace soltex::server
