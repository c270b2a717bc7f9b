#include "http_brick_server.h"

#include <spdlog/spdlog.h>

#include <boost/asio/ip/address.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <memory>
#include <optional>
#include <stdexcept>
#include <type_traits>

#include "http_message_checks.h"

namespace soltex::server {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace net = boost::asio;
using tcp = net::ip::tcp;

using TlsStream = beast::ssl_stream<beast::tcp_stream>;

// One connection: (a TLS handshake,) read a request, answer it, and again while the client
// keeps it alive. Stream is beast::tcp_stream or TlsStream.
template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
  static constexpr bool kTls = std::is_same_v<Stream, TlsStream>;
  using std::enable_shared_from_this<HttpSession<Stream>>::shared_from_this;

 public:
  template <class... TlsContext>
  HttpSession(tcp::socket connection, const HttpLimits& limits, HttpRequestHandler& handler,
              ServerMetrics& metrics, TlsContext&... context)
      : stream_(std::move(connection), context...),
        read_deadline_(stream_.get_executor()),
        limits_(limits),
        handler_(handler),
        metrics_(metrics) {
    metrics_.http.connections_opened.fetch_add(1, std::memory_order_relaxed);
    metrics_.http.connections_open.fetch_add(1, std::memory_order_relaxed);
    beast::error_code ec;
    const tcp::endpoint peer = socket().remote_endpoint(ec);
    peer_host_ = ec ? std::string("unknown") : peer.address().to_string();
  }
  ~HttpSession() { metrics_.http.connections_open.fetch_sub(1, std::memory_order_relaxed); }

  // The peer's connection slot, given back when the session ends.
  void hold(PeerConnections::Slot slot) { slot_ = std::move(slot); }
  const std::string& peer_host() const { return peer_host_; }

  void start() {
    net::dispatch(stream_.get_executor(), [self = shared_from_this()] { self->begin(); });
  }

  // TLS: the session holds the context it was made with (a reload replaces the server's).
  void start_with(std::shared_ptr<net::ssl::context> context) {
    context_ = std::move(context);
    start();
  }

  // Too many connections, over TLS: no answer is possible before a handshake, so closed.
  void close_now() {
    metrics_.http.connections_refused.fetch_add(1, std::memory_order_relaxed);
    handler_.log_refusal(peer_host_,
                         "too many HTTPS connections open; closed before its handshake");
    net::dispatch(stream_.get_executor(), [self = shared_from_this()] { self->close(); });
  }

  // Too many connections (the server's, or this peer's: `why`): one 503, then closed.
  void refuse(const std::string& why) {
    metrics_.http.connections_refused.fetch_add(1, std::memory_order_relaxed);
    handler_.log_refusal(peer_host_, why);
    metrics_.http.count(HttpMetrics::Route::other, 503);
    HttpResponse response = handler_.error(11, 503, why + "; try again later");
    net::dispatch(stream_.get_executor(),
                  [self = shared_from_this(), response = std::move(response)]() mutable {
                    self->send(std::move(response), /*close=*/true);
                  });
  }

 private:
  tcp::socket& socket() { return beast::get_lowest_layer(stream_).socket(); }

  void begin() {
    if constexpr (kTls) {
      beast::get_lowest_layer(stream_).expires_after(limits_.timeout);
      stream_.async_handshake(net::ssl::stream_base::server,
                              [self = shared_from_this()](beast::error_code ec) {
                                // No HTTP answer is possible without TLS: count and close.
                                if (ec == beast::error::timeout) {
                                  self->metrics_.http.timeouts.fetch_add(1);
                                }
                                if (ec) return self->close();
                                self->read();
                              });
    } else {
      read();
    }
  }

  // The next request. A keep-alive connection may idle up to the timeout before its first
  // byte; the request then gets the whole timeout to arrive, from that byte on.
  void read() {
    parser_.emplace();
    parser_->header_limit(static_cast<std::uint32_t>(limits_.max_header_bytes));
    parser_->body_limit(limits_.max_body_bytes);
    // Our own deadline, not the stream's: the stream's closes the socket when it expires, and
    // a client whose request is cut short should hear a 408 first.
    beast::get_lowest_layer(stream_).expires_never();
    if (buffer_.size() > 0) return read_request();  // pipelined: it has begun already
    arm_read_deadline();
    stream_.async_read_some(buffer_.prepare(kFirstRead),
                            [self = shared_from_this()](beast::error_code ec, std::size_t n) {
                              self->read_deadline_.cancel();
                              // Idle past the timeout, closed by the client, or broken: nothing to
                              // answer.
                              if (ec || self->read_timed_out_) return self->close();
                              self->buffer_.commit(n);
                              self->read_request();
                            });
  }

  void read_request() {
    arm_read_deadline();
    http::async_read_header(
        stream_, buffer_, *parser_,
        [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_header(ec); });
  }

  void arm_read_deadline() {
    read_timed_out_ = false;
    read_deadline_.expires_after(limits_.timeout);
    // A wait that expired just as its read finished may run after the next one is armed:
    // cancel() cannot take back a handler already queued, so each wait knows its read.
    read_deadline_.async_wait(
        [self = shared_from_this(), armed = ++deadlines_armed_](beast::error_code ec) {
          if (ec || armed != self->deadlines_armed_) return;  // cancelled, or an earlier read's
          self->read_timed_out_ = true;
          beast::error_code ignored;
          self->socket().cancel(ignored);
        });
  }

  // A client that sent "Expect: 100-continue" waits for a word before sending its body.
  void on_header(beast::error_code ec) {
    if (ec || parser_->is_done() || !expects_continue(parser_->get())) return read_body(ec);
    continue_ = {http::status::continue_, 11};
    http::async_write(stream_, continue_,
                      [self = shared_from_this()](beast::error_code ec, std::size_t) {
                        if (ec) return self->close();
                        self->read_body({});
                      });
  }

  void read_body(beast::error_code ec) {
    if (ec || parser_->is_done()) return on_read(ec);
    http::async_read(
        stream_, buffer_, *parser_,
        [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
  }

  void on_read(beast::error_code ec) {
    read_deadline_.cancel();
    if (read_timed_out_) ec = beast::error::timeout;
    if (ec == http::error::end_of_stream || ec == net::error::connection_reset ||
        ec == net::error::eof) {
      return close();
    }
    if (ec == beast::error::timeout) {
      metrics_.http.timeouts.fetch_add(1, std::memory_order_relaxed);
      return refuse_request(408, "the request did not arrive whole within " +
                                     std::to_string(limits_.timeout.count()) + " ms");
    }
    if (ec == http::error::body_limit) {
      return refuse_request(413, "the request body is over " +
                                     std::to_string(limits_.max_body_bytes) +
                                     " bytes (--max-message-bytes)");
    }
    if (ec == http::error::header_limit) {
      // The request line not read whole: it alone is too long, which is the target's doing
      // (RFC 9112 3: 414). The parser sets the method once it has read the line, but may also
      // wait for the whole header block first, leaving it all in the buffer.
      const std::string_view unread = unread_bytes();
      if (parser_->get().method_string().empty() &&
          unread.substr(0, limits_.max_header_bytes).find('\n') == std::string_view::npos) {
        return refuse_request(
            414, "the request line is over " + std::to_string(limits_.max_header_bytes) + " bytes");
      }
      return refuse_request(431, "the request line and headers are over " +
                                     std::to_string(limits_.max_header_bytes) + " bytes");
    }
    if (ec) return refuse_request(400, "malformed HTTP request: " + ec.message());
    if (const auto problem = framing_problem(parser_->get())) return refuse_request(400, *problem);
    // While a worker makes the brick; the write sets its own deadline.
    beast::get_lowest_layer(stream_).expires_never();
    handler_.handle(parser_->get(), peer_host_, [self = shared_from_this()](HttpResponse response) {
      net::post(self->stream_.get_executor(), [self, response = std::move(response)]() mutable {
        const bool close = !response.keep_alive();
        self->send(std::move(response), close);
      });
    });
  }

  void refuse_request(unsigned status, const std::string& message) {
    metrics_.http.count(HttpMetrics::Route::other, status);
    HttpResponse response = handler_.error(11, status, message);
    if (is_head_request()) without_content(response);
    send(std::move(response), /*close=*/true);
  }

  // What has arrived and is not parsed yet.
  std::string_view unread_bytes() const {
    return {static_cast<const char*>(buffer_.data().data()), buffer_.data().size()};
  }

  // Whether the request being refused is a HEAD: its parsed method, or where the request
  // line was not read whole (414), the word it starts with.
  bool is_head_request() const {
    if (parser_ && parser_->get().method() == http::verb::head) return true;
    if (parser_ && !parser_->get().method_string().empty()) return false;
    const std::string_view unread = unread_bytes();
    return unread.starts_with("HEAD ");
  }

  void send(HttpResponse response, bool close) {
    if (close) response.keep_alive(false);
    response_ = std::move(response);
    beast::get_lowest_layer(stream_).expires_after(limits_.timeout);
    http::async_write(stream_, response_,
                      [self = shared_from_this(), close](beast::error_code ec, std::size_t) {
                        if (ec == beast::error::timeout) {
                          self->metrics_.http.timeouts.fetch_add(1, std::memory_order_relaxed);
                        }
                        if (ec || close) return self->close();
                        self->read();
                      });
  }

  void close() {
    beast::error_code ignored;
    socket().shutdown(tcp::socket::shutdown_send, ignored);
    beast::get_lowest_layer(stream_).close();
  }

  std::shared_ptr<net::ssl::context> context_;  // TLS only; outlives stream_
  Stream stream_;
  static constexpr std::size_t kFirstRead = 4096;  // a request's first bytes, or all of it
  net::steady_timer read_deadline_;
  uint64_t deadlines_armed_ = 0;  // read_deadline_'s waits so far
  bool read_timed_out_ = false;
  const HttpLimits& limits_;
  HttpRequestHandler& handler_;
  ServerMetrics& metrics_;
  std::string peer_host_;
  PeerConnections::Slot slot_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  HttpResponse response_;
  http::response<http::empty_body> continue_;
};

}  // namespace

HttpBrickServer::HttpBrickServer(const std::string& host, uint16_t port, HttpLimits limits,
                                 HttpRequestHandler::Context context, std::optional<TlsFiles> tls)
    : limits_(limits),
      metrics_(context.metrics),
      handler_(context),
      tls_(tls ? std::make_unique<HttpTls>(*tls) : nullptr),
      peers_(std::make_shared<PeerConnections>(limits.max_connections_per_client,
                                               limits.unbounded_peers)),
      // One strand for the acceptor, its retry timer and stop()'s close: the accept handlers
      // run on any of the server's threads, and none of the three may be touched by two
      // threads at once.
      acceptor_(net::make_strand(io_)),
      retry_(acceptor_.get_executor(), "HTTP") {
  beast::error_code ec;
  const auto address = net::ip::make_address(host, ec);
  if (ec) throw std::runtime_error("HTTP address '" + host + "' is not an IP address");
  const tcp::endpoint endpoint(address, port);
  acceptor_.open(endpoint.protocol(), ec);
  if (!ec) acceptor_.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) acceptor_.bind(endpoint, ec);
  if (!ec) acceptor_.listen(net::socket_base::max_listen_connections, ec);
  if (ec) {
    throw std::runtime_error("cannot listen for HTTP on " + host + ":" + std::to_string(port) +
                             ": " + ec.message());
  }
  port_ = acceptor_.local_endpoint().port();
  accept();
  for (int i = 0; i < std::max(1, limits_.threads); ++i) {
    threads_.emplace_back([this] { io_.run(); });
  }
}

HttpBrickServer::~HttpBrickServer() {
  stop();
}

void HttpBrickServer::accept() {
  acceptor_.async_accept(net::make_strand(io_), [this](beast::error_code ec, tcp::socket socket) {
    // Closed (stopping, or no longer accepting): a connection accepted just before the close
    // is closed with it, and no further accept is started on a closed acceptor.
    if (ec == net::error::operation_aborted || !acceptor_.is_open()) return;
    if (ec) {
      return retry_.failed(ec, [this] {
        if (acceptor_.is_open()) accept();
      });
    }
    retry_.succeeded();
    serve(std::move(socket));
    accept();
  });
}

void HttpBrickServer::serve(tcp::socket socket) {
  const bool full = metrics_.http.connections_open.load(std::memory_order_relaxed) >=
                    static_cast<int64_t>(limits_.max_connections);
  if (tls_) {
    // The session keeps the context it was made with: a reload changes later ones only.
    const std::shared_ptr<net::ssl::context> context = tls_->context();
    auto session = std::make_shared<HttpSession<TlsStream>>(std::move(socket), limits_, handler_,
                                                            metrics_, *context);
    std::optional<PeerConnections::Slot> slot;
    if (!full) slot = peers_->open(session->peer_host());
    if (!slot) {
      session->close_now();
    } else {
      session->hold(std::move(*slot));
      session->start_with(context);
    }
  } else {
    auto session = std::make_shared<HttpSession<beast::tcp_stream>>(std::move(socket), limits_,
                                                                    handler_, metrics_);
    std::optional<PeerConnections::Slot> slot;
    if (!full) slot = peers_->open(session->peer_host());
    if (full) {
      session->refuse("this server has " + std::to_string(limits_.max_connections) +
                      " HTTP connections open (--http-max-connections)");
    } else if (!slot) {
      session->refuse("this client (" + session->peer_host() + ") has " +
                      std::to_string(limits_.max_connections_per_client) +
                      " HTTP connections open (--http-max-connections-per-client)");
    } else {
      session->hold(std::move(*slot));
      session->start();
    }
  }
}

void HttpBrickServer::reload_tls() {
  if (tls_) tls_->reload();
}

void HttpBrickServer::stop_accepting() {
  net::post(acceptor_.get_executor(), [this] {
    beast::error_code ignored;
    acceptor_.close(ignored);
    retry_.cancel();
  });
}

void HttpBrickServer::stop() {
  if (threads_.empty()) return;
  stop_accepting();
  io_.stop();
  for (std::thread& thread : threads_) thread.join();
  threads_.clear();
}

}  // namespace soltex::server
