// The rules of HTTP/1.1 (RFC 9110, 9112) that soltexd's HTTP bricks keep beyond what its own
// clients exercise, written as raw requests where a well-behaved client library would not send
// them: a cache or proxy in front of soltexd, or a client that pipelines, relies on each.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "http_test_client.h"
#include "soltexd_process.h"

namespace soltex {
namespace {

using namespace testing;

class HttpConformance : public ::testing::Test {
 protected:
  void SetUp() override {
    const HttpReply reply = http_request(port(), "POST", "/v1/textures", {}, kMarbleJson);
    ASSERT_EQ(reply.status, 200) << reply.body;
    id_ = reply.body.substr(reply.body.find("\"id\":\"") + 6, 16);
  }
  int port() const { return server_.http_port(); }
  std::string texture() const { return "/v1/textures/" + id_; }
  std::string brick() const { return texture() + "/bricks/0/1/2/3"; }

  SoltexdProcess server_{{"--http-listen", "127.0.0.1:0", "--threads", "2"}};
  std::string id_;
};

TEST_F(HttpConformance, AHeadIsAnsweredWithoutContentWhateverItsStatus) {
  HttpConnection connection(port());
  const std::string full = http_request(port(), "GET", brick()).body;
  // Refused by the router, by the method check and by the path: no content after the headers,
  // or the next response on the connection would begin with it.
  for (const std::string& target : {std::string("/nope"), std::string("/v1/textures"),
                                    std::string("/v1/textures/XYZ/bricks/0/0/0/0")}) {
    const HttpReply head = connection.send("HEAD", target);
    EXPECT_GE(head.status, 400) << target;
    const HttpReply next = connection.send("GET", brick());
    EXPECT_EQ(next.status, 200) << "after HEAD " << target;
    EXPECT_EQ(next.body, full) << "after HEAD " << target;
  }
  // A request line too long to read whole is known for a HEAD by its first word: the 414 has
  // no content either.
  HttpConnection long_line(port());
  long_line.write_raw("HEAD /v1/textures/" + std::string(32768, 'a') + " HTTP/1.1\r\n");
  const std::string answer = long_line.read_until_closed();
  EXPECT_EQ(answer.rfind("HTTP/1.1 414", 0), 0u) << answer.substr(0, 200);
  ASSERT_NE(answer.find("\r\n\r\n"), std::string::npos);
  EXPECT_EQ(answer.substr(answer.find("\r\n\r\n") + 4), "") << "content after a HEAD's headers";
  // A 304 to HEAD has no Content-Length (RFC 9110 8.6: only the 200's length would be right).
  const HttpReply not_modified = connection.send("HEAD", brick(), {{"If-None-Match", "*"}});
  EXPECT_EQ(not_modified.status, 304);
  EXPECT_EQ(not_modified.header("content-length"), "");
}

TEST_F(HttpConformance, ABodyOfUnknownLengthIsRefusedAndItsConnectionClosed) {
  for (const std::string coding : {"gzip", "chunked, gzip", "identity"}) {
    HttpConnection connection(port());
    // Read on, the bytes after the headers would pass for a second request (smuggled).
    connection.write_raw("POST /v1/textures HTTP/1.1\r\nHost: a\r\nTransfer-Encoding: " + coding +
                         "\r\n\r\nGET /smuggled HTTP/1.1\r\nHost: a\r\n\r\n");
    const HttpReply reply = connection.read();
    EXPECT_EQ(reply.status, 400) << coding;
    EXPECT_NE(reply.body.find("Transfer-Encoding"), std::string::npos) << reply.body;
    EXPECT_TRUE(connection.closed_by_server()) << coding;
  }
}

TEST_F(HttpConformance, AnHttp11RequestNamesOneWellFormedHost) {
  const std::string line = "GET " + texture() + " HTTP/1.1\r\n";
  for (const std::string& headers :
       {std::string(""), std::string("Host: a\r\nHost: b\r\n"), std::string("Host: a b/c\r\n")}) {
    HttpConnection connection(port());
    connection.write_raw(line + headers + "\r\n");
    const HttpReply reply = connection.read();
    EXPECT_EQ(reply.status, 400) << headers;
    EXPECT_NE(reply.body.find("Host"), std::string::npos) << reply.body;
  }
  // HTTP/1.0 had no Host; an empty Host is what a client with no authority sends.
  for (const std::string& request :
       {"GET " + texture() + " HTTP/1.0\r\n\r\n", "GET " + texture() + " HTTP/1.1\r\nHost:\r\n\r\n",
        "GET " + texture() + " HTTP/1.1\r\nHost: [::1]:80\r\n\r\n"}) {
    HttpConnection connection(port());
    connection.write_raw(request);
    EXPECT_EQ(connection.read().status, 200) << request;
  }
}

TEST_F(HttpConformance, AbsoluteFormTargetsNameTheirPath) {
  HttpConnection connection(port());
  connection.write_raw("GET http://soltex.example" + brick() +
                       "?codec=raw HTTP/1.1\r\nHost: x\r\n\r\n");
  const HttpReply reply = connection.read();
  EXPECT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(reply.header("x-soltex-codec"), "raw");
}

TEST_F(HttpConformance, EveryAnswerIsDated) {
  const std::regex imf_fixdate(
      R"((Mon|Tue|Wed|Thu|Fri|Sat|Sun), \d\d (Jan|Feb|Mar|Apr|May|Jun|Jul|Aug|Sep|Oct|Nov|Dec) \d{4} \d\d:\d\d:\d\d GMT)");
  for (const auto& [method, target] :
       {std::pair{"GET", brick()}, std::pair{"GET", texture()},
        std::pair{"GET", std::string("/nope")}, std::pair{"POST", texture()}}) {
    const HttpReply reply = http_request(port(), method, target);
    EXPECT_TRUE(std::regex_match(reply.header("date"), imf_fixdate))
        << method << " " << target << ": '" << reply.header("date") << "'";
  }
}

TEST_F(HttpConformance, PreconditionsReadEveryLineAndIfMatchIsStrong) {
  const std::string etag = http_request(port(), "GET", brick()).header("etag");
  ASSERT_FALSE(etag.empty());
  HttpConnection connection(port());
  // Two lines of a list mean the same as one line of both (RFC 9110 5.3).
  EXPECT_EQ(connection.send("GET", brick(), {{"If-None-Match", "\"aaa\""}, {"If-None-Match", etag}})
                .status,
            304);
  EXPECT_EQ(connection.send("GET", brick(), {{"If-Match", etag}}).status, 200);
  EXPECT_EQ(connection.send("GET", brick(), {{"If-Match", "*"}}).status, 200);
  const HttpReply other = connection.send("GET", brick(), {{"If-Match", "\"zzz\""}});
  EXPECT_EQ(other.status, 412);
  EXPECT_NE(other.body.find(etag), std::string::npos) << other.body;
  EXPECT_EQ(connection.send("GET", brick(), {{"If-Match", "W/" + etag}}).status, 412);
  EXPECT_EQ(connection.send("GET", texture(), {{"If-Match", "\"zzz\""}}).status, 412);
  // A texture's JSON has no tag, but it exists: "*" matches it (RFC 9110 13.1.2).
  const HttpReply current = connection.send("GET", texture(), {{"If-None-Match", "*"}});
  EXPECT_EQ(current.status, 304);
  EXPECT_EQ(current.body, "");
  EXPECT_EQ(connection.send("GET", texture(), {{"If-None-Match", "\"zzz\""}}).status, 200);
}

TEST_F(HttpConformance, OneCredentialPerRequest) {
  HttpConnection connection(port());
  connection.write_raw("GET " + texture() +
                       " HTTP/1.1\r\nHost: a\r\nAuthorization: Bearer a\r\n"
                       "Authorization: Bearer b\r\n\r\n");
  const HttpReply twice = connection.read();
  EXPECT_EQ(twice.status, 400);
  EXPECT_NE(twice.body.find("Authorization is given 2 times"), std::string::npos) << twice.body;
}

TEST_F(HttpConformance, AClientExpectingContinueHearsItBeforeSendingItsBody) {
  HttpConnection connection(port());
  connection.write_raw(
      "POST /v1/textures HTTP/1.1\r\nHost: a\r\nExpect: 100-continue\r\n"
      "Content-Length: " +
      std::to_string(kMarbleJson.size()) + "\r\n\r\n");
  EXPECT_EQ(connection.read().status, 100);
  connection.write_raw(kMarbleJson);
  EXPECT_EQ(connection.read().status, 200);
}

TEST_F(HttpConformance, PreflightsAnswerForAnyTexturePathAndConnectIsNotImplemented) {
  // The real request is then refused with a message the page can read.
  const HttpReply preflight =
      http_request(port(), "OPTIONS", "/v1/textures/XYZ/bricks/0/0/0/0",
                   {{"Origin", "https://page.example"}, {"Access-Control-Request-Method", "GET"}});
  EXPECT_EQ(preflight.status, 204);
  EXPECT_EQ(preflight.header("access-control-allow-origin"), "*");
  EXPECT_NE(preflight.header("access-control-allow-headers").find("If-Match"), std::string::npos);
  EXPECT_EQ(http_request(port(), "GET", "/v1/textures/XYZ/bricks/0/0/0/0").status, 400);
  EXPECT_EQ(http_request(port(), "CONNECT", "soltex.example:443").status, 501);
}

TEST_F(HttpConformance, ASpecThatIsNotJsonIsNamed) {
  // Valid base64url ("AAAA" is three zero bytes), not a registration.
  const HttpReply reply = http_request(port(), "GET", "/v1/textures/0123456789abcdef?spec=AAAA");
  EXPECT_EQ(reply.status, 400);
  EXPECT_NE(reply.body.find("spec"), std::string::npos) << reply.body;
}

TEST(HttpTokens, TheBearerSchemeIsReadWithoutCase) {
  SoltexdProcess server({"--http-listen", "127.0.0.1:0", "--token", "s3cret-token"});
  for (const std::string scheme : {"Bearer", "bearer", "BEARER"}) {
    const HttpReply reply =
        http_request(server.http_port(), "POST", "/v1/textures",
                     {{"Authorization", scheme + " s3cret-token"}}, kMarbleJson);
    EXPECT_EQ(reply.status, 200) << scheme << ": " << reply.body;
  }
  EXPECT_EQ(http_request(server.http_port(), "POST", "/v1/textures",
                         {{"Authorization", "Basic s3cret-token"}}, kMarbleJson)
                .status,
            401);
}

}  // namespace
}  // namespace soltex
