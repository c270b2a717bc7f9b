#include "metrics_http_server.h"

#include <spdlog/spdlog.h>

#include <boost/asio/ip/address.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <memory>
#include <stdexcept>
#include <string_view>

namespace soltex::server {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
using tcp = boost::asio::ip::tcp;

class Session : public std::enable_shared_from_this<Session> {
 public:
  Session(tcp::socket socket, const MetricsHttpServer::Render& render, int& open_connections)
      : stream_(std::move(socket)), render_(render), open_connections_(open_connections) {
    ++open_connections_;
  }
  ~Session() { --open_connections_; }

  void start() {
    // The stream closes the socket when the deadline passes, ending the session.
    stream_.expires_after(MetricsHttpServer::kTimeout);
    http::async_read(stream_, buffer_, request_,
                     [self = shared_from_this()](beast::error_code ec, std::size_t) {
                       if (!ec) self->respond();
                     });
  }

 private:
  void respond() {
    response_.version(request_.version());
    response_.keep_alive(false);
    const bool head = request_.method() == http::verb::head;
    // The query is ignored: scrapers may add parameters (Prometheus' `params`).
    const std::string_view target(request_.target().data(), request_.target().size());
    const std::string_view path = target.substr(0, target.find('?'));
    if (request_.method() != http::verb::get && !head) {
      response_.result(http::status::method_not_allowed);
      response_.set(http::field::allow, "GET, HEAD");
      response_.set(http::field::content_type, "text/plain");
      response_.body() = "only GET and HEAD are supported\n";
    } else if (path != "/metrics") {
      response_.result(http::status::not_found);
      response_.set(http::field::content_type, "text/plain");
      response_.body() = "not found: try GET /metrics\n";
    } else {
      render_page();
    }
    response_.prepare_payload();
    if (head) response_.body().clear();  // the length stays the page's
    stream_.expires_after(MetricsHttpServer::kTimeout);
    http::async_write(stream_, response_,
                      [self = shared_from_this()](beast::error_code, std::size_t) {
                        beast::error_code ignored;
                        self->stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
                      });
  }

  // A page that cannot be made whole is a 500, never a partial page a scraper would misread.
  void render_page() {
    try {
      response_.body() = render_();
      response_.result(http::status::ok);
      response_.set(http::field::content_type, "text/plain; version=0.0.4; charset=utf-8");
    } catch (const std::exception& e) {
      spdlog::error("rendering /metrics failed: {}", e.what());
      response_.result(http::status::internal_server_error);
      response_.set(http::field::content_type, "text/plain");
      response_.body() = std::string("rendering metrics failed: ") + e.what() + "\n";
    }
  }

  beast::tcp_stream stream_;
  const MetricsHttpServer::Render& render_;
  int& open_connections_;
  beast::flat_buffer buffer_;
  http::request<http::string_body> request_;
  http::response<http::string_body> response_;
};

}  // namespace

MetricsHttpServer::MetricsHttpServer(const std::string& host, uint16_t port, Render render)
    : render_(std::move(render)), acceptor_(io_), retry_(io_.get_executor(), "metrics") {
  beast::error_code ec;
  const auto address = boost::asio::ip::make_address(host, ec);
  if (ec) throw std::runtime_error("metrics address '" + host + "' is not an IP address");
  const tcp::endpoint endpoint(address, port);
  acceptor_.open(endpoint.protocol(), ec);
  if (!ec) acceptor_.set_option(boost::asio::socket_base::reuse_address(true), ec);
  if (!ec) acceptor_.bind(endpoint, ec);
  if (!ec) acceptor_.listen(boost::asio::socket_base::max_listen_connections, ec);
  if (ec) {
    throw std::runtime_error("cannot listen for metrics on " + host + ":" + std::to_string(port) +
                             ": " + ec.message());
  }
  port_ = acceptor_.local_endpoint().port();
  accept();
  thread_ = std::thread([this] { io_.run(); });
}

MetricsHttpServer::~MetricsHttpServer() {
  stop();
}

void MetricsHttpServer::accept() {
  acceptor_.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (ec == boost::asio::error::operation_aborted || !acceptor_.is_open()) return;  // stopping
    if (ec) return retry_.failed(ec, [this] { accept(); });
    retry_.succeeded();
    if (open_connections_ >= kMaxConnections) {
      spdlog::debug("metrics: {} connections open, closing a new one", open_connections_);
    } else {
      std::make_shared<Session>(std::move(socket), render_, open_connections_)->start();
    }
    accept();
  });
}

void MetricsHttpServer::stop() {
  if (!thread_.joinable()) return;
  boost::asio::post(io_, [this] {
    beast::error_code ignored;
    acceptor_.close(ignored);
    retry_.cancel();
  });
  io_.stop();
  thread_.join();
}

}  // namespace soltex::server
