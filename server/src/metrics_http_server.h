#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>

namespace soltex::server {

// A small HTTP/1.1 server for Prometheus: GET /metrics answers with render(); anything else
// is 404 (or 405 for other methods). Runs on its own thread, never on gRPC's or the workers'.
class MetricsHttpServer {
 public:
  using Render = std::function<std::string()>;

  // Binds host:port (port 0 picks a free port); throws std::runtime_error naming the address.
  MetricsHttpServer(const std::string& host, uint16_t port, Render render);
  ~MetricsHttpServer();

  uint16_t port() const { return port_; }
  void stop();

 private:
  void accept();

  Render render_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  uint16_t port_ = 0;
  std::thread thread_;
};

}  // namespace soltex::server
