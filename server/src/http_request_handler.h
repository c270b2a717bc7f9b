#pragma once

#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>
#include <functional>
#include <memory>
#include <string>

#include "brick_producer.h"
#include "brick_scheduler.h"
#include "client_access.h"
#include "fault_injection.h"
#include "http_brick_queue.h"
#include "http_router.h"
#include "refusal_log.h"
#include "server_metrics.h"
#include "texture_registry.h"

namespace soltex::server {

using HttpRequest = boost::beast::http::request<boost::beast::http::string_body>;
using HttpResponse = boost::beast::http::response<boost::beast::http::string_body>;

// Answers one HTTP request against the daemon's registry and brick store (docs/PROTOCOL.md,
// HTTP): routing, tokens, per-client limits, registration, brick production through the
// scheduler, ETags and CORS. Knows nothing of sockets.
class HttpRequestHandler {
 public:
  struct Context {
    TextureRegistry& registry;
    BrickScheduler& scheduler;
    BrickProducer& producer;
    ServerMetrics& metrics;
    ClientAccess& access;
    RefusalLog& refusals;              // a client refused is logged as gRPC's refusals are
    FaultInjection* faults = nullptr;  // --fault-corrupt-every applies to HTTP bricks too
  };
  // Called once with the response, on the calling thread or a worker's.
  using Respond = std::function<void(HttpResponse)>;

  explicit HttpRequestHandler(Context context);

  void handle(const HttpRequest& request, const std::string& peer_host, Respond respond);

  // A complete error response (text/plain, CORS, no-store), for the transport's own refusals
  // (malformed requests, bodies over the limit, timeouts, too many connections).
  HttpResponse error(unsigned version, unsigned status, const std::string& message) const;

  // Logs a refusal of `client` (at most a line a second for each client).
  void log_refusal(const std::string& client, const std::string& why) const;

 private:
  struct Call;
  void handle_brick(const Route& route, std::shared_ptr<Call> call);
  void answer_texture(const Route& route, Call& call);
  void answer_registration(Call& call, const std::string& body);
  TexturePin find_or_register(const Route& route, Call& call);
  void finish(Call& call, HttpResponse response);

  Context context_;
  std::shared_ptr<HttpBrickQueue> queue_;
};

}  // namespace soltex::server
