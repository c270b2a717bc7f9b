#pragma once

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>

#include "brick_producer.h"
#include "brick_scheduler.h"
#include "brick_service.h"
#include "brick_store.h"
#include "client_access.h"
#include "fault_injection.h"
#include "http_brick_server.h"
#include "listener_watchdog.h"
#include "metrics_http_server.h"
#include "refusal_log.h"
#include "reloadable_tls.h"
#include "server_config.h"
#include "server_metrics.h"
#include "shared_brick_cache.h"
#include "texture_registry.h"

namespace soltex::server {

// soltexd assembled: registry, brick store, worker pool, gRPC service (with health and
// reflection) and the metrics endpoint. Construction starts serving.
class Daemon {
 public:
  explicit Daemon(const ServerConfig& config);
  ~Daemon();

  int grpc_port() const { return grpc_port_; }
  int metrics_port() const { return metrics_->port(); }
  int http_port() const { return http_ ? http_->port() : 0; }  // 0: no --http-listen

  // Graceful: health NOT_SERVING; open streams read no more requests and send the bricks
  // already asked for within the grace period (those still owing at its end finish
  // UNAVAILABLE); gRPC shut down; workers joined; metrics stopped. Idempotent.
  void shut_down();

  std::string render_metrics() const;

  // SIGHUP: reads the TLS files and the tokens file again. Open streams go on; calls and
  // connections after it use what was read. On an error (logged, counted) the old ones stay.
  void reload();

  // `stop` is called, from another thread, when the daemon can no longer serve and should
  // shut down and exit non-zero (failed() says so): its gRPC listener accepts no connection.
  // At once when that has already happened; nullptr: forget it (before `stop` goes stale).
  void on_failure(std::function<void()> stop);
  bool failed() const { return failed_.load(); }

 private:
  void finish_calls_within_grace();
  void start_watchdog();
  void fail(const std::string& why);

  ServerConfig config_;
  ServerMetrics metrics_state_;
  ClientAccess access_;
  RefusalLog refusals_;
  std::unique_ptr<ReloadableTls> tls_;  // null: plaintext
  FaultInjection faults_;
  std::unique_ptr<SharedBrickCache> shared_cache_;  // null: no memcached configured
  TextureRegistry registry_;
  BrickStore store_;
  BrickScheduler scheduler_;
  BrickProducer producer_;
  std::unique_ptr<BrickServiceImpl> service_;
  std::unique_ptr<grpc::Server> server_;
  std::unique_ptr<MetricsHttpServer> metrics_;
  std::unique_ptr<HttpBrickServer> http_;       // null: no --http-listen
  std::unique_ptr<ListenerWatchdog> watchdog_;  // null: --listen-watchdog-s 0
  std::mutex failure_mutex_;
  std::function<void()> on_failure_;
  std::atomic<bool> failed_{false};
  int grpc_port_ = 0;
  bool shut_down_ = false;
  std::atomic<uint64_t> reloads_ok_{0};
  std::atomic<uint64_t> reloads_failed_{0};
};

}  // namespace soltex::server
