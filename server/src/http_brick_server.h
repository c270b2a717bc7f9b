#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "accept_retry.h"
#include "http_request_handler.h"
#include "http_tls.h"
#include "peer_connections.h"

namespace soltex::server {

struct HttpLimits {
  std::size_t max_body_bytes = 4u << 20;  // a registration; the gRPC message bound
  std::size_t max_header_bytes = 16384;   // request line and headers (?spec= rides there)
  uint32_t max_connections = 1024;        // beyond: 503 and closed
  // Of them from one peer address, but for the balancers named here (trusted proxies).
  uint32_t max_connections_per_client = 64;
  std::vector<AddressRange> unbounded_peers;
  // A request must arrive whole, and a response be written, within this; an idle keep-alive
  // connection is closed after it.
  std::chrono::milliseconds timeout{15000};
  int threads = 2;  // I/O only: bricks are made on the workers
};

// The HTTP/1.1 brick endpoint (--http-listen): keep-alive connections, each request read
// whole (bounded header and body, with a deadline) and handed to HttpRequestHandler; the
// response goes out on the connection's strand when the handler (or a worker) answers.
class HttpBrickServer {
 public:
  // Binds host:port (port 0: a free port); throws std::runtime_error naming the address or
  // the TLS file that cannot be used. With `tls`, every connection is HTTPS.
  HttpBrickServer(const std::string& host, uint16_t port, HttpLimits limits,
                  HttpRequestHandler::Context context, std::optional<TlsFiles> tls = {});
  ~HttpBrickServer();

  uint16_t port() const { return port_; }
  // Shutdown's first step: new connections are refused from now on; open ones are served on.
  void stop_accepting();
  void stop();
  // SIGHUP: the TLS files read again for later connections; throws, keeping the old, on error.
  void reload_tls();

 private:
  void accept();
  // A new connection: a session, or refused when the server or its peer has too many.
  void serve(boost::asio::ip::tcp::socket socket);

  const HttpLimits limits_;
  ServerMetrics& metrics_;
  HttpRequestHandler handler_;
  std::unique_ptr<HttpTls> tls_;  // null: plain HTTP
  std::shared_ptr<PeerConnections> peers_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  AcceptRetry retry_;
  uint16_t port_ = 0;
  std::vector<std::thread> threads_;
};

}  // namespace soltex::server
