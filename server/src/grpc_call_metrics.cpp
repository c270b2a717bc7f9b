#include "grpc_call_metrics.h"

#include <google/protobuf/descriptor.h>
#include <grpcpp/grpcpp.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <string_view>

namespace soltex::server {
namespace {

using grpc::experimental::InterceptionHookPoints;
using grpc::experimental::InterceptorBatchMethods;
using grpc::experimental::ServerRpcInfo;

const char* const kCodeNames[17] = {
    "OK",        "CANCELLED",      "UNKNOWN",           "INVALID_ARGUMENT",   "DEADLINE_EXCEEDED",
    "NOT_FOUND", "ALREADY_EXISTS", "PERMISSION_DENIED", "RESOURCE_EXHAUSTED", "FAILED_PRECONDITION",
    "ABORTED",   "OUT_OF_RANGE",   "UNIMPLEMENTED",     "INTERNAL",           "UNAVAILABLE",
    "DATA_LOSS", "UNAUTHENTICATED"};

const char* type_label(ServerRpcInfo::Type type) {
  switch (type) {
    case ServerRpcInfo::Type::UNARY:
      return "unary";
    case ServerRpcInfo::Type::CLIENT_STREAMING:
      return "client_stream";
    case ServerRpcInfo::Type::SERVER_STREAMING:
      return "server_stream";
    case ServerRpcInfo::Type::BIDI_STREAMING:
      return "bidi_stream";
  }
  return "unknown";
}

// One per call. Hooks of one call can run on different threads at once (a bidi stream reads
// and writes concurrently), hence the atomics.
class CallInterceptor final : public grpc::experimental::Interceptor {
 public:
  CallInterceptor(ServerRpcInfo* info, MethodCallCounters& counters, bool callback_api)
      : info_(info), counters_(counters), callback_api_(callback_api) {
    counters_.started.fetch_add(1, std::memory_order_relaxed);
  }

  void Intercept(InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::POST_RECV_MESSAGE) &&
        methods->GetRecvMessage() != nullptr) {
      counters_.messages_received.fetch_add(1, std::memory_order_relaxed);
    }
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::PRE_SEND_MESSAGE)) {
      counters_.messages_sent.fetch_add(1, std::memory_order_relaxed);
    }
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::PRE_SEND_STATUS)) {
      code_.store(static_cast<int>(methods->GetSendStatus().error_code()),
                  std::memory_order_relaxed);
    }
    // The call is over: whatever status it ended with is known now.
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::POST_RECV_CLOSE)) finish();
    methods->Proceed();
  }

 private:
  void finish() {
    int code = code_.load(std::memory_order_relaxed);
    // Cancelled: the status the handler gave (if any) never reached the client. Asked of
    // callback-API calls only: on a sync-API call IsCancelled() plucks the very completion
    // this hook runs inside, and re-enters it.
    if (callback_api_ && info_->server_context()->IsCancelled()) {
      counters_.cut_short.fetch_add(1, std::memory_order_relaxed);
      code = static_cast<int>(grpc::StatusCode::CANCELLED);
      spdlog::debug("{} call from {} ended before its status was sent", info_->method(),
                    info_->server_context()->peer());
    } else if (code < 0 || code >= static_cast<int>(counters_.handled.size())) {
      code = static_cast<int>(grpc::StatusCode::UNKNOWN);
    }
    counters_.handled[static_cast<std::size_t>(code)].fetch_add(1, std::memory_order_relaxed);
  }

  ServerRpcInfo* info_;
  MethodCallCounters& counters_;
  const bool callback_api_;
  std::atomic<int> code_{-1};  // the status the server sent; -1 before PRE_SEND_STATUS
};

class Factory final : public grpc::experimental::ServerInterceptorFactoryInterface {
 public:
  Factory(GrpcCallMetrics& metrics, std::vector<std::string> callback_services)
      : metrics_(metrics), callback_services_(std::move(callback_services)) {}
  grpc::experimental::Interceptor* CreateServerInterceptor(ServerRpcInfo* info) override {
    MethodCallCounters& counters = metrics_.counters(info->method(), info->type());
    const bool callback_api = std::find(callback_services_.begin(), callback_services_.end(),
                                        counters.service) != callback_services_.end();
    return new CallInterceptor(info, counters, callback_api);
  }

 private:
  GrpcCallMetrics& metrics_;
  const std::vector<std::string> callback_services_;
};

// "/package.Service/Method" split at its last slash; an empty service when there is none.
std::pair<std::string, std::string> split_method(const std::string& full_method) {
  const std::size_t slash = full_method.rfind('/');
  const std::size_t begin = full_method.starts_with('/') ? 1 : 0;
  if (slash == std::string::npos || slash < begin) return {std::string(), full_method};
  return {full_method.substr(begin, slash - begin), full_method.substr(slash + 1)};
}

// Whether the binary has the method's definition: its services' and reflection's are in the
// protobuf pool; gRPC's health service is built without it, so its two are named here. Every
// other name is a client's invention and would otherwise become series of its own.
bool defined_method(const std::string& service, const std::string& method) {
  if (service == "grpc.health.v1.Health") return method == "Check" || method == "Watch";
  return google::protobuf::DescriptorPool::generated_pool()->FindMethodByName(service + "." +
                                                                              method) != nullptr;
}

}  // namespace

const char* grpc_code_name(int code) {
  return code >= 0 && code < 17 ? kCodeNames[code] : "UNKNOWN";
}

MethodCallCounters& GrpcCallMetrics::counters(const std::string& full_method,
                                              ServerRpcInfo::Type type) {
  std::lock_guard lock(mutex_);
  if (auto it = by_name_.find(full_method); it != by_name_.end()) return *it->second;
  auto [service, method] = split_method(full_method);
  if (!defined_method(service, method)) {
    // One series for all of them, whatever the names: a client must not be able to grow the
    // page (and the server's memory) by calling methods that do not exist.
    if (unknown_ == nullptr) {
      unknown_ = &methods_.emplace_back();
      unknown_->type = type_label(type);
      unknown_->service = kUnknownName;
      unknown_->method = kUnknownName;
    }
    return *unknown_;
  }
  MethodCallCounters& added = methods_.emplace_back();
  added.type = type_label(type);
  added.service = std::move(service);
  added.method = std::move(method);
  by_name_.emplace(full_method, &added);
  return added;
}

void GrpcCallMetrics::write(Exposition& e, const Families& families) const {
  std::lock_guard lock(mutex_);
  const auto load = [](const std::atomic<uint64_t>& a) {
    return static_cast<double>(a.load(std::memory_order_relaxed));
  };
  // One sample per method of the counter `member`.
  const auto per_method = [&](const MetricFamily& family,
                              const std::atomic<uint64_t> MethodCallCounters::*member) {
    e.family(family);
    for (const MethodCallCounters& m : methods_) {
      e.sample(load(m.*member),
               {{"grpc_type", m.type}, {"grpc_service", m.service}, {"grpc_method", m.method}});
    }
  };
  per_method(families.started, &MethodCallCounters::started);
  e.family(families.handled);
  for (const MethodCallCounters& m : methods_) {
    for (std::size_t code = 0; code < m.handled.size(); ++code) {
      if (m.handled[code].load(std::memory_order_relaxed) == 0) continue;
      e.sample(load(m.handled[code]), {{"grpc_type", m.type},
                                       {"grpc_service", m.service},
                                       {"grpc_method", m.method},
                                       {"grpc_code", kCodeNames[code]}});
    }
  }
  per_method(families.received, &MethodCallCounters::messages_received);
  per_method(families.sent, &MethodCallCounters::messages_sent);
  per_method(families.cut_short, &MethodCallCounters::cut_short);
}

std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>
GrpcCallMetrics::interceptor_factory(std::vector<std::string> callback_services) {
  return std::make_unique<Factory>(*this, std::move(callback_services));
}

}  // namespace soltex::server
