#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <map>
#include <string>
#include <utility>
#include <vector>

// A plain HTTP/1.1 client over loopback (Boost.Beast), for the tests of soltexd's HTTP bricks.
namespace soltex::testing {

struct HttpReply {
  int status = 0;
  std::map<std::string, std::string> headers;  // names lower-case
  std::string body;
  bool keep_alive = false;

  std::string header(const std::string& name) const {
    const auto it = headers.find(name);
    return it == headers.end() ? std::string() : it->second;
  }
};

using HttpHeaders = std::vector<std::pair<std::string, std::string>>;

// One keep-alive connection: requests go out one after another on the same socket.
class HttpConnection {
 public:
  explicit HttpConnection(int port);
  HttpReply send(const std::string& method, const std::string& target,
                 const HttpHeaders& headers = {}, const std::string& body = "");
  // Raw bytes, for requests no well-behaved client writes.
  void write_raw(const std::string& bytes);
  // Reads one response; status 0 when the server closed the connection without one.
  HttpReply read(bool head = false);
  // Whether the server has closed its side (a read returns end of stream).
  bool closed_by_server();
  // Every byte the server sends until it closes the connection, unparsed.
  std::string read_until_closed();

 private:
  boost::asio::io_context io_;
  boost::asio::ip::tcp::socket socket_;
  boost::beast::flat_buffer buffer_;
};

// The texture marble_request(6, 8) (brick_test_client.h) describes, as HTTP clients write it.
inline const std::string kMarbleJson =
    R"({"texture": {"marble": {}}, "brick_size": 8,
        "volume": {"min": [-1, -1, -1], "max": [1, 1, 1], "finest_level_log2": 6}})";

// One request on a fresh connection.
HttpReply http_request(int port, const std::string& method, const std::string& target,
                       const HttpHeaders& headers = {}, const std::string& body = "");

}  // namespace soltex::testing
