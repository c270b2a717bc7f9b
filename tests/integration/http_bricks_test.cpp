// soltexd's HTTP bricks (docs/PROTOCOL.md, HTTP) against a real soltexd on loopback: the same
// ids and brick bytes as gRPC, ETags and 304s, CORS, self-contained URLs another replica
// answers, and every kind of bad request refused while others are served.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>

#include "brick_test_client.h"
#include "http_test_client.h"
#include "soltex/common/brick_codec.h"
#include "soltex/common/texture_id.h"
#include "soltexd_process.h"
#include "test_certificates.h"

namespace soltex {
namespace {

using testing::http_request;
using testing::HttpConnection;
using testing::HttpReply;
using testing::kMarbleJson;
using testing::SoltexdProcess;

std::vector<std::string> http_args(std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {"--http-listen", "127.0.0.1:0", "--threads", "2"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

nlohmann::json register_over_http(int port, const std::string& body = kMarbleJson) {
  const HttpReply reply = http_request(port, "POST", "/v1/textures", {}, body);
  EXPECT_EQ(reply.status, 200) << reply.body;
  return nlohmann::json::parse(reply.body);
}

std::string brick_path(const std::string& id, int level, int x, int y, int z) {
  return "/v1/textures/" + id + "/bricks/" + std::to_string(level) + "/" + std::to_string(x) + "/" +
         std::to_string(y) + "/" + std::to_string(z);
}

TEST(HttpBricks, RegistrationGivesTheGrpcIdAndHandle) {
  SoltexdProcess server(http_args());
  const nlohmann::json handle = register_over_http(server.http_port());
  auto stub = testing::connect(server);
  const v1::TextureHandle grpc = testing::register_texture(*stub, testing::marble_request(6, 8));
  EXPECT_EQ(handle["id"], texture_id_hex(grpc.id()));
  EXPECT_EQ(handle["levels"], grpc.levels());
  EXPECT_EQ(handle["brick_size"], 8);
  EXPECT_EQ(handle["finest_level_log2"], 6);
  EXPECT_EQ(handle["channels"], nlohmann::json::array({"colour"}));

  // The canonical registration reads back as the same texture.
  const HttpReply canonical =
      http_request(server.http_port(), "GET", "/v1/textures/" + handle["id"].get<std::string>());
  ASSERT_EQ(canonical.status, 200) << canonical.body;
  EXPECT_EQ(canonical.header("cache-control"), "public, max-age=31536000, immutable");
  nlohmann::json again = nlohmann::json::parse(canonical.body);
  EXPECT_EQ(again["id"], handle["id"]);
  again.erase("id");
  EXPECT_EQ(register_over_http(server.http_port(), again.dump())["id"], handle["id"]);
}

TEST(HttpBricks, BricksEqualTheGrpcBricksByteForByte) {
  SoltexdProcess server(http_args());
  const std::string id = register_over_http(server.http_port())["id"];
  auto stub = testing::connect(server);
  const v1::TextureHandle handle = testing::register_texture(*stub, testing::marble_request(6, 8));
  const std::vector<v1::BrickKey> keys = {testing::key_of(handle.id(), 3, 0, 0, 0),
                                          testing::key_of(handle.id(), 1, 1, 2, 3),
                                          testing::key_of(handle.id(), 0, 7, 0, 5)};
  HttpConnection connection(server.http_port());  // every request on one keep-alive connection
  for (const auto& [codec, name] :
       {std::pair{v1::CODEC_ZSTD, "zstd"}, std::pair{v1::CODEC_LZ4, "lz4"},
        std::pair{v1::CODEC_RAW, "raw"}}) {
    const testing::StreamResult grpc = testing::stream_once(*stub, testing::want(keys, codec));
    ASSERT_EQ(grpc.bricks.size(), keys.size());
    for (const v1::Brick& brick : grpc.bricks) {
      const v1::BrickKey& k = brick.key();
      const HttpReply reply = connection.send(
          "GET", brick_path(id, static_cast<int>(k.level()), static_cast<int>(k.x()),
                            static_cast<int>(k.y()), static_cast<int>(k.z())) +
                     "?codec=" + name);
      ASSERT_EQ(reply.status, 200) << reply.body;
      EXPECT_TRUE(reply.keep_alive);
      EXPECT_EQ(reply.body, brick.payload()) << name << " level " << k.level();
      EXPECT_EQ(reply.header("x-soltex-codec"), name);
      EXPECT_EQ(reply.header("content-type"), "application/vnd.soltex.brick");
    }
  }
}

// --fault-corrupt-every flips a byte of HTTP bricks as of streamed ones: the body no longer
// matches its checksum, which a client checks.
TEST(HttpBricks, CorruptionFaultsReachHttpBricksToo) {
  SoltexdProcess server(http_args({"--fault-corrupt-every", "2"}));
  const std::string id = register_over_http(server.http_port())["id"];
  HttpConnection connection(server.http_port());
  int corrupt = 0;
  for (int x = 0; x < 4; ++x) {
    const HttpReply reply = connection.send("GET", brick_path(id, 1, x, 0, 0) + "?codec=raw");
    ASSERT_EQ(reply.status, 200) << reply.body;
    try {
      (void)decode_brick(
          std::span(reinterpret_cast<const uint8_t*>(reply.body.data()), reply.body.size()));
    } catch (const CodecError&) {
      ++corrupt;
    }
  }
  EXPECT_EQ(corrupt, 2);
  EXPECT_EQ(testing::metric_value(testing::http_get(server.metrics_port(), "/metrics"),
                                  "soltex_faults_corrupted_total"),
            2.0);
}

TEST(HttpBricks, StrongEtagsAnswerConditionalRequestsWith304) {
  SoltexdProcess server(http_args());
  const std::string id = register_over_http(server.http_port())["id"];
  const std::string path = brick_path(id, 2, 1, 0, 1);
  const HttpReply first = http_request(server.http_port(), "GET", path);
  ASSERT_EQ(first.status, 200);
  const std::string etag = first.header("etag");
  ASSERT_EQ(etag.size(), 18u) << etag;  // a quoted 64-bit hash, not weak
  EXPECT_EQ(etag.front(), '"');
  EXPECT_EQ(first.header("cache-control"), "public, max-age=31536000, immutable");

  const HttpReply again = http_request(server.http_port(), "GET", path);
  EXPECT_EQ(again.header("etag"), etag);
  EXPECT_EQ(again.body, first.body);

  const HttpReply not_modified =
      http_request(server.http_port(), "GET", path, {{"If-None-Match", "\"x\", " + etag}});
  EXPECT_EQ(not_modified.status, 304);
  EXPECT_EQ(not_modified.body, "");
  EXPECT_EQ(not_modified.header("etag"), etag);
  EXPECT_EQ(not_modified.header("cache-control"), "public, max-age=31536000, immutable");

  const HttpReply other =
      http_request(server.http_port(), "GET", path, {{"If-None-Match", "\"0000000000000000\""}});
  EXPECT_EQ(other.status, 200);
  EXPECT_EQ(other.body, first.body);

  // Another codec is another representation: another ETag.
  const HttpReply lz4 = http_request(server.http_port(), "GET", path + "?codec=lz4");
  EXPECT_NE(lz4.header("etag"), etag);

  const HttpReply head = http_request(server.http_port(), "HEAD", path);
  EXPECT_EQ(head.status, 200);
  EXPECT_EQ(head.header("content-length"), std::to_string(first.body.size()));
  EXPECT_EQ(head.header("etag"), etag);
}

TEST(HttpBricks, CorsHeadersAndPreflight) {
  SoltexdProcess server(http_args());
  const std::string id = register_over_http(server.http_port())["id"];
  const HttpReply preflight =
      http_request(server.http_port(), "OPTIONS", brick_path(id, 0, 0, 0, 0),
                   {{"Origin", "http://example.org"}, {"Access-Control-Request-Method", "GET"}});
  EXPECT_EQ(preflight.status, 204);
  EXPECT_EQ(preflight.header("access-control-allow-origin"), "*");
  EXPECT_EQ(preflight.header("access-control-allow-methods"), "GET, HEAD, OPTIONS");
  EXPECT_NE(preflight.header("access-control-allow-headers").find("If-None-Match"),
            std::string::npos);
  const HttpReply post_preflight = http_request(server.http_port(), "OPTIONS", "/v1/textures");
  EXPECT_EQ(post_preflight.header("access-control-allow-methods"), "POST, OPTIONS");

  const HttpReply brick = http_request(server.http_port(), "GET", brick_path(id, 0, 0, 0, 0),
                                       {{"Origin", "http://example.org"}});
  EXPECT_EQ(brick.header("access-control-allow-origin"), "*");
  EXPECT_NE(brick.header("access-control-expose-headers").find("ETag"), std::string::npos);
  // Errors carry CORS too, so a page can read why.
  const HttpReply error = http_request(server.http_port(), "GET", "/nowhere");
  EXPECT_EQ(error.status, 404);
  EXPECT_EQ(error.header("access-control-allow-origin"), "*");
}

TEST(HttpBricks, ErrorsAreExactAndWordedAsGrpcWordsThem) {
  SoltexdProcess server(http_args());
  const int port = server.http_port();
  const std::string id = register_over_http(port)["id"];
  auto stub = testing::connect(server);
  const v1::TextureHandle handle = testing::register_texture(*stub, testing::marble_request(6, 8));
  // Out of range: the gRPC per-brick error's message, as a 404.
  for (const auto& [level, x] : {std::pair{4, 0}, std::pair{1, 4}}) {
    const testing::StreamResult grpc =
        testing::stream_once(*stub, testing::want({testing::key_of(handle.id(), level, x, 0, 0)}));
    ASSERT_EQ(grpc.errors.size(), 1u);
    const HttpReply reply = http_request(port, "GET", brick_path(id, level, x, 0, 0));
    EXPECT_EQ(reply.status, 404);
    EXPECT_EQ(reply.body, grpc.errors[0].message() + "\n");
    EXPECT_EQ(reply.header("cache-control"), "no-store");
  }
  const HttpReply unknown = http_request(port, "GET", brick_path("0123456789abcdef", 0, 0, 0, 0));
  EXPECT_EQ(unknown.status, 404);
  EXPECT_NE(unknown.body.find("texture 0123456789abcdef is not registered"), std::string::npos);

  const std::vector<std::pair<std::string, std::string>> bad_paths = {
      {"/v1/textures/" + id + "/bricks/0/-1/0/0", "x = '-1'"},
      {"/v1/textures/" + id + "/bricks/0/99999999999999999999/0/0", "x = '9999999999999999"},
      {"/v1/textures/" + id + "/bricks/0/01/0/0", "leading zeros"},
      {"/v1/textures/" + id + "/bricks/a/0/0/0", "level = 'a'"},
      {"/v1/textures/XYZ/bricks/0/0/0/0", "texture id 'XYZ'"},
      {"/v1/textures/" + id + "/bricks/0/0/0/0?codec=brotli", "codec = 'brotli'"},
      {"/v1/textures/" + id + "/bricks/0/0/0/0?spec=%%%", "spec must be"},
      {"/v1/textures/" + id + "/bricks/0/0/0/0?v=2", "unknown query parameter 'v'"}};
  for (const auto& [path, expected] : bad_paths) {
    const HttpReply reply = http_request(port, "GET", path);
    EXPECT_EQ(reply.status, 400) << path;
    EXPECT_NE(reply.body.find(expected), std::string::npos) << path << ": " << reply.body;
  }
  EXPECT_EQ(http_request(port, "GET", "/v1/textures/" + id + "/bricks/0/0/0").status, 404);
  EXPECT_EQ(http_request(port, "GET", "/v2/anything").status, 404);
  const HttpReply wrong_method = http_request(port, "DELETE", "/v1/textures/" + id);
  EXPECT_EQ(wrong_method.status, 405);
  EXPECT_EQ(wrong_method.header("allow"), "GET, HEAD, OPTIONS");
  EXPECT_EQ(http_request(port, "GET", "/v1/textures").status, 405);

  // Registration errors: the gRPC wording for the request's own fields, the JSON path for
  // the spec's.
  const HttpReply size = http_request(port, "POST", "/v1/textures", {},
                                      R"({"texture": {"marble": {}}, "brick_size": 12})");
  EXPECT_EQ(size.status, 400);
  EXPECT_EQ(size.body, "brick_size = 12: must be 8 or 16 (0: the default, 16)\n");
  const HttpReply spec = http_request(port, "POST", "/v1/textures", {},
                                      R"({"texture": {"marble": {"frequency": -1}}})");
  EXPECT_EQ(spec.status, 400);
  EXPECT_NE(spec.body.find("texture.marble.frequency"), std::string::npos) << spec.body;
  EXPECT_EQ(http_request(port, "POST", "/v1/textures", {}, "{not json").status, 400);
  EXPECT_EQ(http_request(port, "POST", "/v1/textures", {}, R"({"volume": {}})").status, 400);
  // Still serving.
  EXPECT_EQ(http_request(port, "GET", brick_path(id, 0, 0, 0, 0)).status, 200);
}

TEST(HttpBricks, UrlsCarryTheirTextureToAnyReplica) {
  SoltexdProcess first(http_args());
  SoltexdProcess second(http_args());
  const nlohmann::json handle = register_over_http(first.http_port());
  const std::string id = handle["id"];
  const std::string spec = handle["spec"];
  const std::string path = brick_path(id, 1, 1, 1, 1);
  EXPECT_EQ(http_request(second.http_port(), "GET", path).status, 404);
  const HttpReply from_first = http_request(first.http_port(), "GET", path + "?spec=" + spec);
  const HttpReply from_second = http_request(second.http_port(), "GET", path + "?spec=" + spec);
  ASSERT_EQ(from_second.status, 200) << from_second.body;
  EXPECT_EQ(from_second.body, from_first.body);
  EXPECT_EQ(from_second.header("etag"), from_first.header("etag"));
  // Registered there now.
  EXPECT_EQ(http_request(second.http_port(), "GET", path).status, 200);
  // The handle's template is the same URL.
  std::string templated = handle["bricks"];
  templated.replace(templated.find("{level}/{x}/{y}/{z}"), 19, "1/1/1/1");
  EXPECT_EQ(templated, path + "?spec=" + spec);

  // A spec that registers another texture than the path names is refused.
  SoltexdProcess third(http_args());
  EXPECT_EQ(http_request(third.http_port(), "GET", brick_path(id, 0, 0, 0, 0) + "?spec=e30").status,
            400);  // "{}": no texture
  const std::string other = brick_path("0123456789abcdef", 0, 0, 0, 0) + "?spec=" + spec;
  const HttpReply mismatch = http_request(third.http_port(), "GET", other);
  EXPECT_EQ(mismatch.status, 400);
  EXPECT_NE(mismatch.body.find("not the texture 0123456789abcdef"), std::string::npos);
  // ... and registers nothing: the texture it would have made is still unknown there.
  EXPECT_EQ(http_request(third.http_port(), "GET", "/v1/textures/" + id).status, 404);
}

// A graph texture of about 2 * `leaves` nodes, every one distinct and used: a sum over
// `leaves` position components each offset by its own constant, added in a balanced tree.
std::string graph_registration(int leaves) {
  std::string list = R"({"name": "p", "category": "position"})";
  for (int axis = 0; axis < 3; ++axis) {
    list += R"(, {"name": "e)" + std::to_string(axis) +
            R"(", "category": "extract", "inputs": {"in": {"node": "p"}, "index": )" +
            std::to_string(axis) + "}}";
  }
  std::vector<std::string> level;
  for (int i = 0; i < leaves; ++i) {
    level.push_back("a" + std::to_string(i));
    list += R"(, {"name": ")" + level.back() +
            R"(", "category": "add", "inputs": {"in1": {"node": "e)" + std::to_string(i % 3) +
            R"("}, "in2": )" + std::to_string(0.001 * (i + 1)) + "}}";
  }
  for (int round = 0; level.size() > 1; ++round) {
    std::vector<std::string> next;
    for (std::size_t i = 0; i + 1 < level.size(); i += 2) {
      next.push_back("s" + std::to_string(round) + "_" + std::to_string(i / 2));
      list += R"(, {"name": ")" + next.back() +
              R"(", "category": "add", "inputs": {"in1": {"node": ")" + level[i] +
              R"("}, "in2": {"node": ")" + level[i + 1] + R"("}}})";
    }
    if (level.size() % 2 == 1) next.push_back(level.back());
    level = next;
  }
  list +=
      R"(, {"name": "c", "category": "combine3", "type": "color3", "inputs": {"in1": {"node": ")" +
      level.front() + R"("}, "in2": {"node": "e1"}, "in3": {"node": "e2"}}})";
  return R"({"texture": {"graph": {"nodes": [)" + list +
         R"(], "outputs": {"colour": "c"}}}, "brick_size": 8,
             "volume": {"min": [-1, -1, -1], "max": [1, 1, 1], "finest_level_log2": 6}})";
}

// Every handle POST /v1/textures gives out works on any replica: a graph whose spec fits the
// URL bound is served through its template by a replica that never saw it, and one whose spec
// would not fit is refused at the POST, naming both sizes.
TEST(HttpBricks, EveryHandleGivenOutFitsItsUrlBound) {
  SoltexdProcess first(http_args());
  SoltexdProcess second(http_args());
  const nlohmann::json handle = register_over_http(first.http_port(), graph_registration(40));
  const std::string spec = handle["spec"];
  EXPECT_GT(spec.size(), 6144u) << "the graph no longer tests a spec of several KB";
  std::string url = handle["bricks"];
  url.replace(url.find("{level}/{x}/{y}/{z}"), 19, "0/1/1/1");
  const HttpReply brick = http_request(second.http_port(), "GET", url);
  EXPECT_EQ(brick.status, 200) << brick.body;
  EXPECT_EQ(brick.body, http_request(first.http_port(), "GET", url).body);

  const auto registered = [&] {
    const std::string page = testing::metrics(first);
    const std::string name = "\nsoltex_textures_registered ";
    const std::size_t at = page.find(name);
    return at == std::string::npos ? -1 : std::stoi(page.substr(at + name.size()));
  };
  const int before = registered();
  const HttpReply large =
      http_request(first.http_port(), "POST", "/v1/textures", {}, graph_registration(120));
  EXPECT_EQ(large.status, 413) << large.body;
  EXPECT_NE(large.body.find("at most 12288"), std::string::npos) << large.body;
  EXPECT_NE(large.body.find("register it over gRPC"), std::string::npos) << large.body;
  EXPECT_EQ(registered(), before) << "the refused registration took a registry place";
  EXPECT_GE(before, 1);
}

TEST(HttpBricks, BodiesOverTheLimitAreRefused) {
  SoltexdProcess server(http_args({"--max-message-bytes", "2048"}));
  const std::string big =
      R"({"texture": {"marble": {}}, "pad": ")" + std::string(4096, 'x') + "\"}";
  const HttpReply reply = http_request(server.http_port(), "POST", "/v1/textures", {}, big);
  EXPECT_EQ(reply.status, 413);
  EXPECT_NE(reply.body.find("2048"), std::string::npos);
  EXPECT_EQ(register_over_http(server.http_port())["levels"], 4);
  const HttpReply headers =
      http_request(server.http_port(), "GET", "/v1/textures", {{"X-Big", std::string(32768, 'y')}});
  EXPECT_EQ(headers.status, 431);
  // A request line of 1 KB is not the one too long, though the first read ends inside it.
  const HttpReply cookie =
      http_request(server.http_port(), "GET", "/v1/textures/" + std::string(1000, 'a'),
                   {{"Cookie", std::string(32768, 'c')}});
  EXPECT_EQ(cookie.status, 431);
  // The request line alone too long: the target's doing.
  const HttpReply target =
      http_request(server.http_port(), "GET", "/v1/textures/" + std::string(32768, 'a'));
  EXPECT_EQ(target.status, 414);
  EXPECT_NE(target.body.find("request line"), std::string::npos) << target.body;
}

TEST(HttpBricks, SlowClientsTimeOutWhileOthersAreServed) {
  SoltexdProcess server(http_args({"--http-timeout-s", "0.5"}));
  const std::string id = register_over_http(server.http_port())["id"];
  HttpConnection slow(server.http_port());
  slow.write_raw("GET /v1/textures/" + id + " HTTP/1.1\r\nHost: x\r\n");  // never finished
  EXPECT_EQ(http_request(server.http_port(), "GET", brick_path(id, 0, 0, 0, 0)).status, 200);
  const HttpReply timed_out = slow.read();
  EXPECT_EQ(timed_out.status, 408);
  EXPECT_TRUE(slow.closed_by_server());
  HttpConnection idle(server.http_port());
  std::this_thread::sleep_for(std::chrono::milliseconds(900));
  EXPECT_TRUE(idle.closed_by_server());  // an idle keep-alive connection is closed quietly
  const std::string page = testing::metrics(server);
  // Only the request cut short timed out; an idle connection's close is not a timeout.
  EXPECT_EQ(testing::metric_value(page, "soltex_http_timeouts_total"), 1);
  EXPECT_EQ(
      testing::metric_value(page, "soltex_http_responses_total{route=\"other\",code=\"408\"}"), 1);
}

// A request's time runs from its first byte: idle time before it on a kept-alive connection
// does not count. 1.2 s idle and a request that takes 1.2 s to arrive: 2.4 s in all, past the
// 2 s, each part well within it.
TEST(HttpBricks, IdleTimeBeforeARequestIsNotItsTime) {
  SoltexdProcess server(http_args({"--http-timeout-s", "2"}));
  const std::string id = register_over_http(server.http_port())["id"];
  HttpConnection reused(server.http_port());
  const std::string request = "GET /v1/textures/" + id + " HTTP/1.1\r\nHost: x\r\n\r\n";
  reused.write_raw(request);
  EXPECT_EQ(reused.read().status, 200);
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));
  reused.write_raw(request.substr(0, 20));
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));
  reused.write_raw(request.substr(20));
  EXPECT_EQ(reused.read().status, 200);
  EXPECT_EQ(testing::metric_value(testing::metrics(server), "soltex_http_timeouts_total"), 0);
}

// `count` keep-alive connections, each with one brick answered: they hold their slots.
std::vector<std::unique_ptr<HttpConnection>> hold_connections(int port, const std::string& id,
                                                              int count) {
  std::vector<std::unique_ptr<HttpConnection>> held;
  for (int i = 0; i < count; ++i) {
    // A connection closed just before (a registration's) holds its slot until the server has
    // read the close: 503 until then.
    int status = 0;
    for (int attempt = 0; attempt < 50; ++attempt) {
      auto connection = std::make_unique<HttpConnection>(port);
      status = connection->send("GET", brick_path(id, 0, 0, 0, 0)).status;
      if (status != 503) {
        held.push_back(std::move(connection));
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    EXPECT_EQ(status, 200) << i;
  }
  return held;
}

// A brick's status once a freed slot is reused: the server must first see the close.
int status_when_a_slot_frees(int port, const std::string& id) {
  int status = 0;
  for (int attempt = 0; attempt < 50 && status != 200; ++attempt) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    status = http_request(port, "GET", brick_path(id, 0, 0, 0, 0)).status;
  }
  return status;
}

TEST(HttpBricks, ConnectionsBeyondTheLimitGet503) {
  SoltexdProcess server(http_args({"--http-max-connections", "3"}));
  const std::string id = register_over_http(server.http_port())["id"];
  std::vector<std::unique_ptr<HttpConnection>> held = hold_connections(server.http_port(), id, 3);
  HttpConnection extra(server.http_port());
  const HttpReply refused = extra.read();
  EXPECT_EQ(refused.status, 503);
  EXPECT_EQ(refused.header("retry-after"), "1");
  // A page on another origin reads it only if it is exposed.
  EXPECT_NE(refused.header("access-control-expose-headers").find("Retry-After"), std::string::npos);
  EXPECT_NE(refused.body.find("--http-max-connections"), std::string::npos);
  held.pop_back();
  EXPECT_EQ(status_when_a_slot_frees(server.http_port(), id), 200);
  EXPECT_GE(
      testing::metric_value(testing::metrics(server), "soltex_http_connections_refused_total"), 1);
}

TEST(HttpBricks, OneClientCannotHoldEveryConnection) {
  // Every connection of this test comes from 127.0.0.1: one client, two slots.
  SoltexdProcess server(
      http_args({"--http-max-connections", "8", "--http-max-connections-per-client", "2"}));
  const std::string id = register_over_http(server.http_port())["id"];
  std::vector<std::unique_ptr<HttpConnection>> held = hold_connections(server.http_port(), id, 2);
  HttpConnection extra(server.http_port());
  const HttpReply refused = extra.read();
  EXPECT_EQ(refused.status, 503);
  EXPECT_NE(refused.body.find("--http-max-connections-per-client"), std::string::npos)
      << refused.body;
  // Logged as gRPC's refusals are, naming the client and the bound.
  EXPECT_NE(server.log().find("HTTP request from 127.0.0.1 refused: this client (127.0.0.1) has 2"),
            std::string::npos)
      << server.log();
  held.pop_back();
  EXPECT_EQ(status_when_a_slot_frees(server.http_port(), id), 200);

  // A balancer named as a trusted proxy carries many clients: it is not bounded per client.
  SoltexdProcess behind_proxy(
      http_args({"--http-max-connections-per-client", "2", "--trusted-proxies", "127.0.0.1"}));
  const std::string proxied = register_over_http(behind_proxy.http_port())["id"];
  const auto balancer = hold_connections(behind_proxy.http_port(), proxied, 4);
}

TEST(HttpBricks, TokensAreCheckedAsForGrpc) {
  SoltexdProcess server(http_args({"--token", "s3cret"}));
  const int port = server.http_port();
  const HttpReply none = http_request(port, "POST", "/v1/textures", {}, kMarbleJson);
  EXPECT_EQ(none.status, 401);
  EXPECT_EQ(none.header("www-authenticate"), "Bearer");
  EXPECT_NE(none.body.find("requires a bearer token"), std::string::npos);
  EXPECT_NE(server.log().find("HTTP request from 127.0.0.1 refused:"), std::string::npos)
      << server.log();
  EXPECT_EQ(
      http_request(port, "POST", "/v1/textures", {{"Authorization", "Bearer nope"}}, kMarbleJson)
          .status,
      401);
  const HttpReply ok =
      http_request(port, "POST", "/v1/textures", {{"Authorization", "Bearer s3cret"}}, kMarbleJson);
  ASSERT_EQ(ok.status, 200);
  const std::string id = nlohmann::json::parse(ok.body)["id"];
  const HttpReply brick =
      http_request(port, "GET", brick_path(id, 0, 0, 0, 0), {{"Authorization", "Bearer s3cret"}});
  EXPECT_EQ(brick.status, 200);
  // A shared cache must not hand these to callers nobody checked.
  EXPECT_EQ(brick.header("cache-control"), "private, max-age=31536000, immutable");
  EXPECT_EQ(http_request(port, "OPTIONS", brick_path(id, 0, 0, 0, 0)).status, 204);
}

TEST(HttpBricks, MetricsPageStaysValidForPrometheus) {
  SoltexdProcess server(http_args());
  const std::string id = register_over_http(server.http_port())["id"];
  EXPECT_EQ(http_request(server.http_port(), "GET", brick_path(id, 0, 0, 0, 0)).status, 200);
  EXPECT_EQ(http_request(server.http_port(), "GET", "/bad").status, 404);
  const std::string page = testing::metrics(server);
  EXPECT_EQ(testing::metric_value(page, "soltex_http_bricks_served_total"), 1);
  EXPECT_EQ(
      testing::metric_value(page, "soltex_http_responses_total{route=\"brick\",code=\"200\"}"), 1);
  EXPECT_EQ(
      testing::metric_value(page, "soltex_http_responses_total{route=\"other\",code=\"404\"}"), 1);
  const std::string file = ::testing::TempDir() + "/soltexd_http_metrics.txt";
  std::ofstream(file) << page;
  // Debian's python3 carries python3-prometheus-client; a pyenv or venv python may not.
  const std::string python =
      std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string command = python + " " + CHECK_METRICS_SCRIPT + " " + file +
                              " soltex_http_responses_total soltex_http_connections_total"
                              " soltex_http_bricks_served_total > /dev/null";
  EXPECT_EQ(std::system(command.c_str()), 0) << page;
}

}  // namespace
}  // namespace soltex

namespace soltex {
namespace {

// soltex-load --http against the endpoint: every request answered, every brick verified.
TEST(HttpBricks, SoltexLoadLoadsTheHttpPath) {
  SoltexdProcess server(http_args());
  const std::string out = ::testing::TempDir() + "/http_load.json";
  const std::string command = std::string(SOLTEX_LOAD_BINARY) +
                              " --http --server 127.0.0.1:" + std::to_string(server.http_port()) +
                              " --connections 2 --mix uniform --finest-level 7"
                              " --duration-s 0.5 --verify --format json --no-progress > " +
                              out;
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream in(out);
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["mode"], "http");
  EXPECT_GT(report["requests"].get<int>(), 0);
  EXPECT_EQ(report["statuses"].size(), 1u) << report.dump();
  EXPECT_EQ(report["statuses"]["200"], report["requests"]);
  EXPECT_EQ(report["checksum_failures"], 0);
  EXPECT_EQ(report["cache_statuses"]["none"], report["requests"]);  // no cache in front
  EXPECT_GT(report["latency_us"]["p50"].get<double>(), 0.0);
  EXPECT_EQ(testing::metric_value(testing::metrics(server), "soltex_http_bricks_served_total"),
            report["bricks"].get<double>());
}

// A server that wants a token over HTTP as over gRPC: soltex-load --http sends the token it is
// given, and refuses the TLS options it cannot use instead of speaking plain HTTP to them.
TEST(HttpBricks, SoltexLoadSendsItsTokenOverHttp) {
  const std::string token_file = testing::write_temporary_file("token", "http-load-token\n");
  SoltexdProcess server(http_args({"--token-file", token_file}));
  const std::string base = std::string(SOLTEX_LOAD_BINARY) +
                           " --http --server 127.0.0.1:" + std::to_string(server.http_port()) +
                           " --connections 1 --mix uniform --finest-level 7 --count 20"
                           " --verify --no-progress";
  EXPECT_EQ(std::system((base + " --token-file " + token_file + " > /dev/null").c_str()), 0);
  EXPECT_GE(testing::metric_value(testing::metrics(server), "soltex_http_bricks_served_total"),
            20.0);  // and those of its warmup
  EXPECT_NE(std::system((base + " > /dev/null 2>&1").c_str()), 0) << "no token: refused";
  const int tls = std::system(
      (base + " --token-file " + token_file + " --tls-ca " + token_file + " > /dev/null 2>&1")
          .c_str());
  EXPECT_TRUE(WIFEXITED(tls) && WEXITSTATUS(tls) == 2) << tls;
  std::filesystem::remove(token_file);
}

}  // namespace
}  // namespace soltex

namespace soltex {
namespace {

namespace ssl = boost::asio::ssl;

// GET over HTTPS; the status, or 0 when the handshake or the exchange failed.
int https_get(int port, const std::string& target, const testing::TestCertificates& certificates,
              bool present_client_certificate) {
  namespace beast = boost::beast;
  namespace http = beast::http;
  boost::asio::io_context io;
  ssl::context context(ssl::context::tls_client);
  context.load_verify_file(certificates.ca());
  context.set_verify_mode(ssl::verify_peer);
  if (present_client_certificate) {
    context.use_certificate_chain_file(certificates.client_cert());
    context.use_private_key_file(certificates.client_key(), ssl::context::pem);
  }
  beast::ssl_stream<beast::tcp_stream> stream(io, context);
  beast::error_code ec;
  beast::get_lowest_layer(stream).connect(
      {boost::asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)}, ec);
  if (!ec) stream.handshake(ssl::stream_base::client, ec);
  http::request<http::empty_body> request{http::verb::get, target, 11};
  request.set(http::field::host, "127.0.0.1");
  if (!ec) http::write(stream, request, ec);
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  if (!ec) http::read(stream, buffer, response, ec);
  return ec ? 0 : response.result_int();
}

// With --tls-cert the HTTP endpoint speaks HTTPS with gRPC's files, client CA included.
TEST(HttpBricks, TlsUsesTheGrpcCertificatesAndClientCa) {
  testing::TestCertificates certificates;
  SoltexdProcess server(
      http_args({"--tls-cert", certificates.server_cert(), "--tls-key", certificates.server_key(),
                 "--tls-client-ca", certificates.ca()}));
  const std::string brick = brick_path("0123456789abcdef", 0, 0, 0, 0);
  EXPECT_EQ(https_get(server.http_port(), brick, certificates, true), 404);  // answered
  EXPECT_EQ(https_get(server.http_port(), brick, certificates, false), 0);   // no client cert
  // Plain HTTP to the HTTPS port gets no HTTP answer.
  EXPECT_EQ(http_request(server.http_port(), "GET", brick).status, 0);
  EXPECT_EQ(https_get(server.http_port(), brick, certificates, true), 404);  // still serving
}

}  // namespace
}  // namespace soltex
