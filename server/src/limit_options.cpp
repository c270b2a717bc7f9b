#include "limit_options.h"

#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <functional>

namespace soltex::server {

void add_limit_options(CLI::Option_group& security, ServerConfig& config) {
  security
      .add_option("--registry-mb", config.registry_mb,
                  "memory bound of the texture registry in MiB; beyond it the least recently "
                  "used textures no open stream uses are evicted")
      ->check(CLI::Range(1u, 1u << 16))
      ->capture_default_str();
  security
      .add_option("--max-textures-per-client", config.max_textures_per_client,
                  "textures one client may have registered at once; beyond it its own least "
                  "recently used unused one is evicted")
      ->check(CLI::Range(1u, 1u << 20))
      ->capture_default_str();
  security
      .add_option("--trusted-proxies", config.trusted_proxies,
                  "balancers ADDRESS[/BITS],... whose x-forwarded-for header names the client "
                  "for the per-client limits (only they are believed)")
      ->delimiter(',');
}

void wait_for_signals(Daemon& daemon) {
  boost::asio::io_context io;
  boost::asio::signal_set signals(io, SIGINT, SIGTERM, SIGHUP);
  std::function<void(const boost::system::error_code&, int)> on_signal =
      [&](const boost::system::error_code& ec, int signal_number) {
        if (ec) return;
        spdlog::info("received signal {}", signal_number);
        if (signal_number != SIGHUP) return;  // io.run() returns: shut down
        daemon.reload();
        signals.async_wait(on_signal);
      };
  signals.async_wait(on_signal);
  io.run();
}

}  // namespace soltex::server
