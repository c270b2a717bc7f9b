// The memcached brick cache that replicas share: real memcached processes, real soltexd
// replicas on loopback.
#include <gtest/gtest.h>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <thread>

#include "brick_test_client.h"
#include "memcached_process.h"
#include "shared_brick_cache.h"
#include "soltex/common/brick_codec.h"
#include "soltex/spec_proto/brick_proto.h"

namespace soltex {
namespace {

using namespace testing;

#define REQUIRE_MEMCACHED()                                                        \
  if (MemcachedProcess::binary().empty()) {                                        \
    GTEST_SKIP() << "memcached is not installed (deploy/install-deps.sh adds it)"; \
  }

double metric(const SoltexdProcess& server, const std::string& name) {
  return metric_value(metrics(server), name);
}

// Write-backs happen after the client has its brick: wait until `count` have landed.
bool wait_for_metric(const SoltexdProcess& server, const std::string& name, double count) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    if (metric(server, name) >= count) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// Every brick decodes to what this process evaluates.
void expect_bricks_are_local(const StreamResult& result,
                             const v1::RegisterTextureRequest& registration) {
  for (const v1::Brick& brick : result.bricks) {
    const DecodedBrick decoded = decode_brick(std::span(
        reinterpret_cast<const uint8_t*>(brick.payload().data()), brick.payload().size()));
    EXPECT_EQ(decoded.samples, local_brick(registration, brick.key()));
  }
}

// Overwrites one memcached value with `value` over the text protocol.
void memcached_set(int port, const std::string& key, const std::string& value) {
  boost::asio::io_context io;
  boost::asio::ip::tcp::socket socket(io);
  socket.connect({boost::asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)});
  const std::string command =
      "set " + key + " 0 0 " + std::to_string(value.size()) + "\r\n" + value + "\r\n";
  boost::asio::write(socket, boost::asio::buffer(command));
  boost::asio::streambuf reply;
  boost::asio::read_until(socket, reply, "\r\n");
  std::string line(boost::asio::buffers_begin(reply.data()),
                   boost::asio::buffers_end(reply.data()));
  ASSERT_EQ(line, "STORED\r\n");
}

TEST(SharedCache, ABrickEvaluatedOnceIsServedFromMemcachedByAnotherReplica) {
  REQUIRE_MEMCACHED();
  MemcachedProcess first_node, second_node;
  const std::string nodes = first_node.address() + "," + second_node.address();
  SoltexdProcess a({"--memcached", nodes}), b({"--memcached", nodes});
  const v1::RegisterTextureRequest registration = marble_request(6, 8);
  auto stub_a = connect(a);
  auto stub_b = connect(b);
  const uint64_t id = register_texture(*stub_a, registration).id();
  const std::vector<v1::BrickKey> keys = level_keys(id, 1, 4);  // 64 bricks

  const StreamResult from_a = stream_once(*stub_a, want(keys));
  ASSERT_TRUE(from_a.status.ok()) << from_a.status.error_message();
  ASSERT_EQ(from_a.bricks.size(), keys.size());
  ASSERT_TRUE(wait_for_metric(a, "soltex_shared_cache_stores_total", 64));
  EXPECT_EQ(metric(a, "soltex_bricks_evaluated_total"), 64);

  // Replica b has never seen the texture: the stream carries it.
  v1::BrickRequest request = want(keys);
  *request.add_textures() = registration;
  const StreamResult from_b = stream_once(*stub_b, request);
  ASSERT_TRUE(from_b.status.ok()) << from_b.status.error_message();
  ASSERT_EQ(from_b.bricks.size(), keys.size());
  EXPECT_TRUE(from_b.errors.empty());
  EXPECT_EQ(metric(b, "soltex_bricks_evaluated_total"), 0);
  EXPECT_EQ(metric(b, "soltex_bricks_from_shared_cache_total"), 64);
  EXPECT_EQ(metric(b, "soltex_shared_cache_hits_total"), 64);
  expect_bricks_are_local(from_b, registration);
}

TEST(SharedCache, AnUnreachableMemcachedDegradesToLocalEvaluation) {
  SoltexdProcess server(
      {"--memcached", "127.0.0.1:" + std::to_string(free_port()), "--memcached-timeout-ms", "100"});
  auto stub = connect(server);
  const v1::RegisterTextureRequest registration = marble_request(6, 8);
  const uint64_t id = register_texture(*stub, registration).id();
  const StreamResult result = stream_once(*stub, want(level_keys(id, 1, 4)));
  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  EXPECT_EQ(result.bricks.size(), 64u);
  EXPECT_TRUE(result.errors.empty());
  EXPECT_EQ(metric(server, "soltex_bricks_evaluated_total"), 64);
  EXPECT_GT(metric(server, "soltex_shared_cache_errors_total"), 0);
  expect_bricks_are_local(result, registration);
}

TEST(SharedCache, LosingOneMemcachedNodeCostsNoClientErrors) {
  REQUIRE_MEMCACHED();
  MemcachedProcess first_node, second_node;
  SoltexdProcess server({"--memcached", first_node.address() + "," + second_node.address(),
                         "--memcached-timeout-ms", "100"});
  auto stub = connect(server);
  const v1::RegisterTextureRequest registration = marble_request(6, 8);
  const uint64_t id = register_texture(*stub, registration).id();
  ASSERT_TRUE(stream_once(*stub, want(level_keys(id, 1, 4))).status.ok());

  second_node.kill();
  const std::vector<v1::BrickKey> finest = level_keys(id, 0, 8);  // 512 bricks, none cached
  const StreamResult result = stream_once(*stub, want(finest));
  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  EXPECT_EQ(result.bricks.size(), finest.size());
  EXPECT_TRUE(result.errors.empty());
  EXPECT_TRUE(result.request_errors.empty());
  // The surviving node took over the dead one's keys: write-backs go on.
  ASSERT_TRUE(wait_for_metric(server, "soltex_shared_cache_stores_total", 64 + 256));
  expect_bricks_are_local(result, registration);
}

// A node that accepts connections and never answers (stopped, hung) times out instead of
// failing: after its first timeout it rests, and its keys are misses without a call, so the
// bricks do not each wait out a lookup and a write-back.
TEST(SharedCache, AHungMemcachedNodeRestsAfterItsFirstTimeout) {
  REQUIRE_MEMCACHED();
  MemcachedProcess node;
  SoltexdProcess server({"--memcached", node.address(), "--memcached-timeout-ms", "200"});
  auto stub = connect(server);
  const v1::RegisterTextureRequest registration = marble_request(6, 8);
  const uint64_t id = register_texture(*stub, registration).id();
  ASSERT_TRUE(stream_once(*stub, want(level_keys(id, 1, 4))).status.ok());
  node.pause();
  const std::vector<v1::BrickKey> finest = level_keys(id, 0, 8);  // 512 bricks, none cached
  const StreamResult result = stream_once(*stub, want(finest));
  node.resume();
  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  EXPECT_EQ(result.bricks.size(), finest.size());
  EXPECT_TRUE(result.errors.empty());
  // A timeout for each worker that called before the first one ended, at most.
  const double failed = metric(server, "soltex_shared_cache_errors_total") +
                        metric(server, "soltex_shared_cache_store_errors_total");
  EXPECT_GE(failed, 1);
  EXPECT_LE(failed, 8);
  EXPECT_GE(metric(server, "soltex_shared_cache_skipped_total"), 512 - failed);
  expect_bricks_are_local(result, registration);
}

TEST(SharedCache, ACorruptSharedValueIsEvaluatedAgain) {
  REQUIRE_MEMCACHED();
  MemcachedProcess node;
  SoltexdProcess a({"--memcached", node.address()}), b({"--memcached", node.address()});
  const v1::RegisterTextureRequest registration = marble_request(6, 8);
  auto stub_a = connect(a);
  auto stub_b = connect(b);
  const uint64_t id = register_texture(*stub_a, registration).id();
  register_texture(*stub_b, registration);
  const v1::BrickKey key = key_of(id, 2, 1, 0, 1);
  ASSERT_TRUE(stream_once(*stub_a, want({key})).status.ok());
  ASSERT_TRUE(wait_for_metric(a, "soltex_shared_cache_stores_total", 1));

  memcached_set(node.port(), server::SharedBrickCache::key_of(from_proto(key), Codec::zstd),
                "twelve bytes of nonsense");
  const StreamResult result = stream_once(*stub_b, want({key}));
  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  ASSERT_EQ(result.bricks.size(), 1u);
  expect_bricks_are_local(result, registration);
  EXPECT_EQ(metric(b, "soltex_shared_cache_corrupt_total"), 1);
  EXPECT_EQ(metric(b, "soltex_bricks_evaluated_total"), 1);
}

}  // namespace
}  // namespace soltex
