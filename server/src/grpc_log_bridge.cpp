#include "grpc_log_bridge.h"

#include <grpc/support/log.h>
#include <spdlog/spdlog.h>

#include <string_view>

namespace soltex::server {
namespace {

void log_to_spdlog(gpr_log_func_args* args) {
  const std::string_view file = args->file != nullptr ? args->file : "";
  const std::string_view base = file.substr(file.find_last_of('/') + 1);
  const spdlog::level::level_enum level =
      args->severity == GPR_LOG_SEVERITY_ERROR  ? spdlog::level::err
      : args->severity == GPR_LOG_SEVERITY_INFO ? spdlog::level::info
                                                : spdlog::level::debug;
  spdlog::log(level, "gRPC: {} ({}:{})", args->message != nullptr ? args->message : "", base,
              args->line);
}

}  // namespace

void route_grpc_logs_to_spdlog() {
  gpr_set_log_function(log_to_spdlog);
}

}  // namespace soltex::server
