#include "http_test_client.h"

#include <boost/asio/connect.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/http.hpp>
#include <cctype>

namespace soltex::testing {

namespace beast = boost::beast;
namespace http = beast::http;
using tcp = boost::asio::ip::tcp;

HttpConnection::HttpConnection(int port) : socket_(io_) {
  socket_.connect(
      tcp::endpoint(boost::asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)));
}

HttpReply HttpConnection::send(const std::string& method, const std::string& target,
                               const HttpHeaders& headers, const std::string& body) {
  http::request<http::string_body> request{http::string_to_verb(method), target, 11};
  if (request.method() == http::verb::unknown) request.method_string(method);
  request.set(http::field::host, "127.0.0.1");
  // Inserted, not set: a header given twice is sent twice, as two lines.
  for (const auto& [name, value] : headers) request.insert(name, value);
  request.body() = body;
  request.prepare_payload();
  http::write(socket_, request);
  return read(method == "HEAD");
}

void HttpConnection::write_raw(const std::string& bytes) {
  boost::asio::write(socket_, boost::asio::buffer(bytes));
}

HttpReply HttpConnection::read(bool head) {
  http::response_parser<http::string_body> parser;
  parser.skip(head);  // a response to HEAD has a Content-Length but no body
  parser.body_limit(64u << 20);
  beast::error_code ec;
  http::read(socket_, buffer_, parser, ec);
  HttpReply reply;
  if (ec) return reply;
  const auto& response = parser.get();
  reply.status = response.result_int();
  for (const auto& field : response) {
    std::string name(field.name_string());
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    reply.headers[name] = std::string(field.value());
  }
  reply.body = response.body();
  reply.keep_alive = response.keep_alive();
  return reply;
}

bool HttpConnection::closed_by_server() {
  char byte;
  beast::error_code ec;
  socket_.read_some(boost::asio::buffer(&byte, 1), ec);
  return ec == boost::asio::error::eof || ec == boost::asio::error::connection_reset;
}

std::string HttpConnection::read_until_closed() {
  std::string bytes(static_cast<const char*>(buffer_.data().data()), buffer_.data().size());
  buffer_.consume(buffer_.size());
  char chunk[4096];
  beast::error_code ec;
  while (!ec) {
    const std::size_t n = socket_.read_some(boost::asio::buffer(chunk), ec);
    bytes.append(chunk, n);
  }
  return bytes;
}

HttpReply http_request(int port, const std::string& method, const std::string& target,
                       const HttpHeaders& headers, const std::string& body) {
  HttpConnection connection(port);
  return connection.send(method, target, headers, body);
}

}  // namespace soltex::testing
