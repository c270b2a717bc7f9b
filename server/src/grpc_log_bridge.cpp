#include "grpc_log_bridge.h"

#include <grpc/support/log.h>
#include <spdlog/spdlog.h>

#include <memory>
#include <string_view>

namespace soltex::server {
namespace {

// The logger as it was when the bridge was set, kept alive for good: gRPC threads may log
// while static destructors run at exit, after spdlog's registry has let go of its loggers.
std::shared_ptr<spdlog::logger>* g_logger = nullptr;

void log_to_spdlog(gpr_log_func_args* args) {
  const std::string_view file = args->file != nullptr ? args->file : "";
  const std::string_view base = file.substr(file.find_last_of('/') + 1);
  const spdlog::level::level_enum level =
      args->severity == GPR_LOG_SEVERITY_ERROR  ? spdlog::level::err
      : args->severity == GPR_LOG_SEVERITY_INFO ? spdlog::level::info
                                                : spdlog::level::debug;
  (*g_logger)->log(level, "gRPC: {} ({}:{})", args->message != nullptr ? args->message : "", base,
                   args->line);
}

}  // namespace

void route_grpc_logs_to_spdlog() {
  if (g_logger == nullptr) g_logger = new std::shared_ptr<spdlog::logger>(spdlog::default_logger());
  gpr_set_log_function(log_to_spdlog);
}

}  // namespace soltex::server
