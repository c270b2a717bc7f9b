#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>

#include "accept_retry.h"

namespace soltex::server {

// A small HTTP/1.1 server for Prometheus: GET /metrics answers with render(); anything else
// is 404 (or 405 for other methods). Runs on its own thread, never on gRPC's or the workers'.
// Each connection answers one request; idle or slow ones are closed after kTimeout, and beyond
// kMaxConnections open a new one is closed at once, so clients that connect and send nothing
// cannot hold the process's file descriptors.
class MetricsHttpServer {
 public:
  using Render = std::function<std::string()>;
  // A scrape is one small request: Prometheus' own scrape timeout is 10 s by default.
  static constexpr std::chrono::seconds kTimeout{10};
  // Scrapers are a few servers and the odd curl; each connection costs a descriptor.
  static constexpr int kMaxConnections = 64;

  // Binds host:port (port 0 picks a free port); throws std::runtime_error naming the address.
  MetricsHttpServer(const std::string& host, uint16_t port, Render render);
  ~MetricsHttpServer();

  uint16_t port() const { return port_; }
  void stop();

 private:
  void accept();

  Render render_;
  int open_connections_ = 0;  // on the server's thread only
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  AcceptRetry retry_;
  uint16_t port_ = 0;
  std::thread thread_;
};

}  // namespace soltex::server
