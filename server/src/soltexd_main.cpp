// soltexd: evaluates procedural texture bricks on request and streams them over gRPC.
#include <spdlog/spdlog.h>
#include <sys/resource.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <stdexcept>

#include "daemon.h"
#include "grpc_log_bridge.h"
#include "ready_file.h"
#include "signal_wait.h"
#include "soltex/cli/tool_cli.h"
#include "soltexd_options.h"

namespace {

using soltex::server::claim_ready_file;
using soltex::server::remove_ready_file;
using soltex::server::ServerConfig;
using soltex::server::write_ready_file;

// What clients dial for gRPC: the port bound, or the socket of a unix: address (which has no
// port; gRPC reports 1 for it).
std::string grpc_endpoint(const ServerConfig& config, int port) {
  return soltex::server::is_unix_socket_address(config.listen) ? config.listen
                                                               : std::to_string(port);
}

// Every connection is a file descriptor, and the soft limit (often 1024) would run out long
// before the hard one that the administrator set (systemd's LimitNOFILE sets both).
void raise_descriptor_limit() {
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) != 0) return;
  const rlim_t soft = limit.rlim_cur;
  if (soft < limit.rlim_max) {
    limit.rlim_cur = limit.rlim_max;
    // An unlimited hard limit is over what the kernel allows (fs.nr_open): the soft one stays.
    if (setrlimit(RLIMIT_NOFILE, &limit) != 0) limit.rlim_cur = soft;
  }
  spdlog::debug("file descriptor limit {} (was {}, hard limit {})", limit.rlim_cur, soft,
                limit.rlim_max);
}

// `address` (HOST:PORT) with the port the daemon bound, which port 0 leaves to the system.
std::string bound_address(const std::string& address, int port) {
  return soltex::server::host_port_text(soltex::server::parse_host_port(address).host, port);
}

}  // namespace

int main(int argc, char** argv) {
  ServerConfig config;
  CLI::App app{"soltexd: procedural solid-texture brick server (gRPC)"};
  app.set_config("--config", "", "read options from a TOML or INI file");
  // A key soltexd does not know (a misspelt option, a section) is an error, as on the command
  // line, not a setting silently left at its default.
  app.allow_config_extras(CLI::config_extras_mode::error);
  soltex::cli::add_common_options(app, "soltexd", config.log_level);
  soltex::server::add_soltexd_options(app, config);

  // SOLTEXD_LISTEN and SOLTEXD_TOKEN were the only variables before every option had one.
  if (const auto exit_code = soltex::cli::parse(
          app, "soltexd", argc, argv,
          {{"SOLTEXD_LISTEN", "SOLTEX_LISTEN"}, {"SOLTEXD_TOKEN", "SOLTEX_TOKEN"}})) {
    return *exit_code;
  }
  if (const std::string problem = soltex::server::usage_problem(config); !problem.empty()) {
    std::fprintf(stderr, "soltexd: %s\n",
                 soltex::cli::with_value_source(app, problem, argc, argv).c_str());
    return soltex::cli::kExitUsage;
  }
  soltex::cli::start_logging("soltexd", config.log_level, soltex::cli::LogStyle::timestamped);
  soltex::server::route_grpc_logs_to_spdlog();
  soltex::cli::prepare_for_grpc_streams();
  // A log reader that goes away (a pipe to a restarted shipper) must not stop the service: its
  // lines are lost, and a write to the closed pipe fails instead of killing soltexd.
  std::signal(SIGPIPE, SIG_IGN);
  raise_descriptor_limit();

  std::unique_ptr<soltex::server::Daemon> daemon;
  try {
    // A ready file says "serving now": one left by an earlier run that is gone must not say so
    // for this one before it listens, nor after a failed start; one a live soltexd holds is
    // that one's.
    claim_ready_file(config.ready_file);
    daemon = std::make_unique<soltex::server::Daemon>(config);
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return soltex::cli::kExitFailure;
  }
  const std::string grpc = grpc_endpoint(config, daemon->grpc_port());
  spdlog::info("soltexd {} listening on {}, metrics on http://{}/metrics", SOLTEX_VERSION,
               grpc == config.listen ? grpc : bound_address(config.listen, daemon->grpc_port()),
               bound_address(config.metrics_listen, daemon->metrics_port()));
  if (daemon->http_port() != 0) {
    spdlog::info("HTTP bricks on {}://{}", config.tls_cert_file.empty() ? "http" : "https",
                 bound_address(config.http_listen, daemon->http_port()));
  }
  if (!config.ready_file.empty()) {
    try {
      write_ready_file(config.ready_file, grpc, daemon->metrics_port(), daemon->http_port());
    } catch (const std::runtime_error& e) {
      spdlog::critical("{}", e.what());
      daemon->shut_down();
      return soltex::cli::kExitFailure;
    }
  }

  // SIGHUP reloads; SIGINT, SIGTERM or a failure (--listen-watchdog-s) returns.
  soltex::server::wait_for_signals(*daemon);
  remove_ready_file(config.ready_file);  // not ready any more from the moment shutdown begins
  daemon->shut_down();
  return daemon->failed() ? soltex::cli::kExitFailure : soltex::cli::kExitOk;
}
