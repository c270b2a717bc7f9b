#include "signal_wait.h"

#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <functional>

namespace soltex::server {

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
  daemon.on_failure([&io] { io.stop(); });
  io.run();
  daemon.on_failure(nullptr);
}

}  // namespace soltex::server
