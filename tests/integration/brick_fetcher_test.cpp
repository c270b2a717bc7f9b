// The client's brick fetcher against a real soltexd on loopback.
#include "soltex/net/brick_fetcher.h"

#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/net/channel_security.h"
#include "soltexd_process.h"
#include "test_certificates.h"

namespace soltex {
namespace {

using testing::SoltexdProcess;

TextureSpec marble() {
  TextureSpec spec;
  spec.pattern = MarbleParams{};
  return spec;
}

Volume unit_volume(int finest_level_log2) {
  Volume v;
  v.min = glm::dvec3(-1.0);
  v.max = glm::dvec3(1.0);
  v.finest_level_log2 = finest_level_log2;
  return v;
}

std::vector<net::BrickWant> level(uint64_t texture, int level, int bricks) {
  std::vector<net::BrickWant> wants;
  for (int z = 0; z < bricks; ++z)
    for (int y = 0; y < bricks; ++y)
      for (int x = 0; x < bricks; ++x) wants.push_back({{texture, level, {x, y, z}}, 1});
  return wants;
}

// Reconnects within half a second, so restart tests do not wait on the default backoff.
net::FetcherOptions quick_reconnect() {
  net::FetcherOptions options;
  options.initial_backoff = std::chrono::milliseconds(50);
  options.max_backoff = std::chrono::milliseconds(400);
  return options;
}

// A soltexd started with `server_args`, a cache, and a fetcher against that soltexd with the
// marble texture registered as `id`.
struct FetcherAgainstServer {
  explicit FetcherAgainstServer(std::vector<std::string> server_args = {})
      : server(std::move(server_args)),
        fetcher(server.grpc_address(), cache),
        id(fetcher.register_texture(marble(), unit_volume(6), 8, {})) {}

  SoltexdProcess server;
  BrickCache cache{64 << 20};
  net::BrickFetcher fetcher;
  uint64_t id;
};

// Compares every sample of a cached brick with this process's evaluation.
void expect_cached_brick_is_local(BrickCache& cache, uint64_t id, int level_index,
                                  glm::ivec3 brick) {
  const TextureEvaluator evaluator(marble());
  const BrickLayout layout(unit_volume(6), 8);
  std::vector<float> samples(static_cast<std::size_t>(layout.samples_per_brick()) * 3);
  evaluate_brick(evaluator, layout, level_index, brick, {}, samples);
  const std::vector<uint8_t> expected = quantize(samples);
  const auto cached = cache.find({id, level_index, brick});
  ASSERT_TRUE(cached);
  const std::size_t n = static_cast<std::size_t>(layout.samples_per_brick());
  for (int z = 0; z < 9; ++z)
    for (int y = 0; y < 9; ++y)
      for (int x = 0; x < 9; ++x)
        for (int c = 0; c < 3; ++c) {
          ASSERT_EQ(cached->at(x, y, z, c),
                    expected[c * n + static_cast<std::size_t>((z * 9 + y) * 9 + x)]);
        }
}

TEST(BrickFetcher, FetchedBricksEqualLocalEvaluation) {
  FetcherAgainstServer setup;
  auto& [server, cache, fetcher, id] = setup;
  fetcher.want(level(id, 1, 4));
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));
  const net::SourceStats stats = fetcher.stats();
  EXPECT_EQ(stats.received, 64u);
  EXPECT_EQ(stats.errors, 0u);
  EXPECT_GT(stats.bytes, 0u);

  expect_cached_brick_is_local(cache, id, 1, {2, 1, 3});
}

// The codec changes on the live stream: later wants come in the new one, and decode to the
// same samples.
TEST(BrickFetcher, AsksForTheCodecSetAndSwitchesMidStream) {
  FetcherAgainstServer setup;
  auto& [server, cache, fetcher, id] = setup;
  const auto raw = static_cast<std::size_t>(Codec::raw);
  const auto zstd = static_cast<std::size_t>(Codec::zstd);
  fetcher.want(level(id, 2, 2));
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));
  const net::SourceStats packed = fetcher.stats();
  EXPECT_EQ(packed.decoded_bytes[raw], 0u);
  EXPECT_EQ(packed.decoded_bytes[zstd], 8u * 9 * 9 * 9 * 3);

  fetcher.set_codec(Codec::raw);
  fetcher.want(level(id, 1, 4));
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));
  const net::SourceStats both = fetcher.stats();
  EXPECT_EQ(both.received, 72u);
  EXPECT_EQ(both.decoded_bytes[zstd], packed.decoded_bytes[zstd]);
  EXPECT_EQ(both.decoded_bytes[raw], 64u * 9 * 9 * 9 * 3);
  // Raw bricks carry every sample and a 28-byte header.
  EXPECT_EQ(both.bytes - packed.bytes, 64u * (9 * 9 * 9 * 3 + 28));
  expect_cached_brick_is_local(cache, id, 1, {2, 1, 3});
  expect_cached_brick_is_local(cache, id, 2, {1, 0, 1});

  net::FetcherOptions options;
  options.codec = Codec::lz4;
  BrickCache lz4_cache{64 << 20};
  net::BrickFetcher lz4_fetcher(server.grpc_address(), lz4_cache, options);
  const uint64_t lz4_id = lz4_fetcher.register_texture(marble(), unit_volume(6), 8, {});
  lz4_fetcher.want(level(lz4_id, 2, 2));
  ASSERT_TRUE(lz4_fetcher.wait_idle(std::chrono::seconds(30)));
  EXPECT_EQ(lz4_fetcher.stats().decoded_bytes[static_cast<std::size_t>(Codec::lz4)],
            8u * 9 * 9 * 9 * 3);
  expect_cached_brick_is_local(lz4_cache, lz4_id, 2, {1, 0, 1});
}

TEST(BrickFetcher, DuplicatesResidentAndStaleWantsAreNotFetchedTwice) {
  FetcherAgainstServer setup;
  auto& [server, cache, fetcher, id] = setup;
  std::vector<net::BrickWant> wants = level(id, 2, 2);
  const std::vector<net::BrickWant> again = wants;
  wants.insert(wants.end(), again.begin(), again.end());  // every key twice
  fetcher.want(wants);
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));
  fetcher.want(again);  // all resident now
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(5)));
  EXPECT_EQ(fetcher.stats().requested, 8u);
  EXPECT_EQ(fetcher.stats().received, 8u);
}

// A frame's misses asked for in pieces while it is drawn (from several threads, overlapping),
// each key once; what arrives while arrivals are held stays out of the cache, in flight, until
// released, and then all of it goes in; the frame's own want() afterwards cancels nothing.
TEST(BrickFetcher, EarlyWantsWhileArrivalsAreHeld) {
  FetcherAgainstServer setup;
  auto& [server, cache, fetcher, id] = setup;
  const std::vector<net::BrickWant> frame = level(id, 1, 4);
  fetcher.hold_arrivals(true);
  std::vector<std::thread> tiles;
  for (int t = 0; t < 4; ++t) {
    tiles.emplace_back([&, t] {
      // Each "thread" asks for half the keys, so every key is asked for twice.
      for (std::size_t i = 0; i < frame.size(); ++i) {
        if ((i / 8 + static_cast<std::size_t>(t)) % 2 == 0) fetcher.want_early({frame[i]});
      }
    });
  }
  for (std::thread& tile : tiles) tile.join();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (fetcher.stats().bytes == 0 || fetcher.stats().waiting > 0 ||
         fetcher.stats().in_flight < frame.size()) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "nothing arrived";
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  // Let the rest arrive; held, none is in the cache and the fetcher is not idle.
  EXPECT_FALSE(fetcher.wait_idle(std::chrono::milliseconds(500)));
  EXPECT_EQ(fetcher.stats().received, 0u);
  EXPECT_FALSE(cache.contains(frame.front().key));

  fetcher.hold_arrivals(false);
  fetcher.want(frame);
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));
  const net::SourceStats stats = fetcher.stats();
  EXPECT_EQ(stats.requested, frame.size());
  EXPECT_EQ(stats.received, frame.size());
  EXPECT_EQ(stats.cancelled, 0u);
  expect_cached_brick_is_local(cache, id, 1, {2, 1, 3});
}

// Held bricks released into the cache stay pending until they count as received: whoever
// looks meanwhile (another thread) sees every brick either pending or received, and never an
// idle fetcher that has not counted them all.
TEST(BrickFetcher, ReleasedBricksArePendingUntilCounted) {
  FetcherAgainstServer setup;
  auto& [server, cache, fetcher, id] = setup;
  const std::vector<net::BrickWant> frame = level(id, 0, 8);
  const std::size_t raw_brick_bytes = 9 * 9 * 9 * 3 + 28;  // every sample and the header
  fetcher.set_codec(Codec::raw);  // so the bytes received tell when every brick has arrived
  fetcher.hold_arrivals(true);
  fetcher.want(frame);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (fetcher.stats().bytes < frame.size() * raw_brick_bytes) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "the bricks did not arrive";
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(fetcher.stats().in_flight, frame.size());

  std::atomic<bool> released = false;
  std::atomic<std::size_t> looks = 0;
  std::size_t uncounted = 0;   // looks that saw bricks neither pending nor received
  std::size_t idle_early = 0;  // looks that saw an idle fetcher short of bricks received
  std::thread observer([&] {
    while (!released) {
      const net::SourceStats s = fetcher.stats();
      if (s.waiting + s.in_flight + s.received != frame.size()) ++uncounted;
      if (fetcher.idle() && fetcher.stats().received != frame.size()) ++idle_early;
      ++looks;
    }
  });
  while (looks == 0) std::this_thread::yield();
  fetcher.hold_arrivals(false);
  released = true;
  observer.join();
  EXPECT_EQ(uncounted, 0u) << "of " << looks.load() << " looks";
  EXPECT_EQ(idle_early, 0u) << "of " << looks.load() << " looks";
  EXPECT_TRUE(fetcher.idle());
  EXPECT_EQ(fetcher.stats().received, frame.size());
  expect_cached_brick_is_local(cache, id, 0, {7, 2, 5});
}

TEST(BrickFetcher, RefusedKeysAreReportedAndNotAskedAgain) {
  FetcherAgainstServer setup;
  auto& [server, cache, fetcher, id] = setup;
  fetcher.want({{{id, 0, {99, 0, 0}}, 1}});
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(10)));
  fetcher.want({{{id, 0, {99, 0, 0}}, 1}});
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(10)));
  EXPECT_EQ(fetcher.stats().errors, 1u);
  EXPECT_EQ(fetcher.stats().requested, 1u);
}

// A server that takes small messages, few wants a message and a short queue per stream: the
// fetcher reads those bounds and packs its requests to fit, so every brick arrives, nothing is
// refused and the stream is never dropped for a message too large.
TEST(BrickFetcher, KeepsWithinTheServersMessageAndQueueBounds) {
  FetcherAgainstServer setup({"--max-message-bytes", "1024", "--max-keys-per-request", "16",
                              "--max-queued-per-stream", "24"});
  auto& [server, cache, fetcher, id] = setup;
  fetcher.want(level(id, 0, 8));
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(60)));
  const net::SourceStats stats = fetcher.stats();
  EXPECT_EQ(stats.received, 512u);
  EXPECT_EQ(stats.errors, 0u);
  EXPECT_EQ(stats.reconnects, 0u);
  expect_cached_brick_is_local(cache, id, 0, {5, 6, 7});
}

// Reconnected to a server with smaller bounds than the one it lost, the fetcher asks again for
// what was in flight only as far as the new bounds allow; the rest waits its turn.
TEST(BrickFetcher, AReplacementServersSmallerQueueIsKept) {
  const int port = testing::free_port();
  // Bricks held a long while: all 64 are still in flight when this server goes.
  std::optional<SoltexdProcess> server(std::in_place,
                                       std::vector<std::string>{"--fault-delay-ms", "60000"}, port);
  BrickCache cache(64 << 20);
  net::BrickFetcher fetcher("127.0.0.1:" + std::to_string(port), cache, quick_reconnect());
  const uint64_t id = fetcher.register_texture(marble(), unit_volume(6), 8, {});
  fetcher.want(level(id, 1, 4));
  for (int i = 0; i < 200 && fetcher.stats().in_flight < 64; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_EQ(fetcher.stats().in_flight, 64u);
  server->kill_now();
  server.reset();
  server.emplace(
      std::vector<std::string>{"--max-queued-per-stream", "24", "--max-keys-per-request", "16"},
      port);
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));
  const net::SourceStats stats = fetcher.stats();
  EXPECT_EQ(stats.received, 64u);
  EXPECT_EQ(stats.deferred, 0u);
  EXPECT_EQ(stats.errors, 0u);
}

// Two clients of one address share that address's queue bound: each keeps within what it is
// told, yet together they overrun it. Refused wants are asked for again at a pace the server
// keeps up with, not in a storm, and none is lost or counted as an error.
TEST(BrickFetcher, ClientsSharingAnAddressBoundGetEveryBrick) {
  SoltexdProcess server({"--max-queued-per-client", "8", "--max-keys-per-request", "8",
                         "--max-queued-per-stream", "8"});
  BrickCache cache_a(64 << 20), cache_b(64 << 20);
  net::BrickFetcher a(server.grpc_address(), cache_a), b(server.grpc_address(), cache_b);
  const uint64_t id = a.register_texture(marble(), unit_volume(6), 8, {});
  ASSERT_EQ(b.register_texture(marble(), unit_volume(6), 8, {}), id);
  a.want(level(id, 0, 8));
  b.want(level(id, 0, 8));
  ASSERT_TRUE(a.wait_idle(std::chrono::seconds(60)));
  ASSERT_TRUE(b.wait_idle(std::chrono::seconds(60)));
  for (const net::BrickFetcher* f : {&a, &b}) {
    const net::SourceStats stats = f->stats();
    EXPECT_EQ(stats.received, 512u);
    EXPECT_EQ(stats.errors, 0u);
    // A storm would refuse many times the bricks; pacing keeps it to a fraction of them.
    EXPECT_LT(stats.deferred, 512u) << stats.deferred;
  }
}

// A texture the server took by RegisterTexture but refuses when a stream sends it (here a
// replacement server, whose registry holds one texture, gets both on the new stream) is
// reported once, with the server's reason; its wants are dropped and the other texture's
// bricks all arrive. Which of the two the stream carries first, and so keeps, is the order of
// the fetcher's own table.
TEST(BrickFetcher, ATextureRefusedOnTheStreamIsReported) {
  const int port = testing::free_port();
  std::optional<SoltexdProcess> server(std::in_place, std::vector<std::string>{}, port);
  BrickCache cache(64 << 20);
  net::BrickFetcher fetcher("127.0.0.1:" + std::to_string(port), cache, quick_reconnect());
  TextureSpec other;
  other.pattern = WoodParams{};
  const uint64_t marble_id = fetcher.register_texture(marble(), unit_volume(6), 8, {});
  const uint64_t wood_id = fetcher.register_texture(other, unit_volume(6), 8, {});
  EXPECT_EQ(server->terminate(), 0);
  server.emplace(std::vector<std::string>{"--max-textures", "1"}, port);
  std::vector<net::BrickWant> wants = level(marble_id, 1, 4);
  for (const net::BrickWant& w : level(wood_id, 1, 4)) wants.push_back(w);
  fetcher.want(wants);
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));
  const auto refusals = fetcher.take_refused_textures();
  ASSERT_EQ(refusals.size(), 1u);
  const uint64_t refused = refusals[0].first;
  EXPECT_TRUE(refused == marble_id || refused == wood_id) << refused;
  const uint64_t kept = refused == marble_id ? wood_id : marble_id;
  EXPECT_NE(refusals[0].second.find("max_textures"), std::string::npos) << refusals[0].second;
  EXPECT_TRUE(fetcher.take_refused_textures().empty());
  EXPECT_EQ(fetcher.stats().received, 64u);
  EXPECT_EQ(fetcher.stats().errors, 0u);
  EXPECT_TRUE(cache.contains({kept, 1, {3, 3, 3}}));
  fetcher.want(level(refused, 1, 4));  // not asked for again
  EXPECT_TRUE(fetcher.idle());
}

TEST(BrickFetcher, SurvivesAServerRestart) {
  const int port = testing::free_port();
  std::optional<SoltexdProcess> server(std::in_place, std::vector<std::string>{}, port);
  BrickCache cache(64 << 20);
  const net::FetcherOptions options = quick_reconnect();
  net::BrickFetcher fetcher("127.0.0.1:" + std::to_string(port), cache, options);
  const uint64_t id = fetcher.register_texture(marble(), unit_volume(6), 8, {});
  fetcher.want(level(id, 2, 2));
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));

  EXPECT_EQ(server->terminate(), 0);
  server.reset();
  // While the server is away the fetcher keeps what it has and queues what it is asked for.
  EXPECT_TRUE(cache.contains({id, 2, {1, 1, 1}}));
  fetcher.want(level(id, 1, 4));
  EXPECT_FALSE(fetcher.idle());

  server.emplace(std::vector<std::string>{}, port);  // same port: the fetcher reconnects
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));
  const net::SourceStats stats = fetcher.stats();
  EXPECT_GE(stats.reconnects, 1u);
  EXPECT_EQ(stats.received, 8u + 64u);
  EXPECT_TRUE(cache.contains({id, 1, {3, 3, 3}}));
}

TEST(BrickFetcher, AServerBackOnItsPortIsReachedBeforeTheBackoffEnds) {
  const int port = testing::free_port();
  std::optional<SoltexdProcess> server(std::in_place, std::vector<std::string>{}, port);
  BrickCache cache(64 << 20);
  // A backoff far longer than the wait below: the reconnect must come from the channel
  // connecting again, not from the backoff running out.
  net::FetcherOptions options;
  options.initial_backoff = std::chrono::seconds(120);
  options.max_backoff = std::chrono::seconds(120);
  net::BrickFetcher fetcher("127.0.0.1:" + std::to_string(port), cache, options);
  const uint64_t id = fetcher.register_texture(marble(), unit_volume(6), 8, {});
  fetcher.want(level(id, 2, 2));
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));

  server->kill_now();
  server.reset();
  fetcher.want(level(id, 1, 4));
  server.emplace(std::vector<std::string>{}, port);
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(60)))
      << "not reconnected: waiting out the 120 s backoff";
  EXPECT_GE(fetcher.stats().reconnects, 1u);
  EXPECT_TRUE(cache.contains({id, 1, {3, 3, 3}}));
}

// A listening socket that no one accepts from: the kernel completes TCP handshakes into its
// backlog, so a client connects and then hears nothing, as from a stopped server.
class SilentListener {
 public:
  SilentListener() : fd_(socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t size = sizeof address;
    if (fd_ < 0 || bind(fd_, reinterpret_cast<sockaddr*>(&address), size) != 0 ||
        listen(fd_, 16) != 0 ||
        getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &size) != 0) {
      throw std::runtime_error("cannot listen on loopback");
    }
    port_ = ntohs(address.sin_port);
  }
  ~SilentListener() { close(fd_); }
  SilentListener(const SilentListener&) = delete;
  SilentListener& operator=(const SilentListener&) = delete;
  int port() const { return port_; }

 private:
  int fd_;
  int port_ = 0;
};

// A server that answers at once, refusing, is not one that did not answer: the message says
// which it was.
TEST(BrickFetcher, ARefusalIsToldFromASilence) {
  const std::string token_file = testing::write_temporary_file("token", "right-token\n");
  SoltexdProcess server({"--token-file", token_file});
  BrickCache cache(16 << 20);
  net::BrickFetcher fetcher(server.grpc_address(), cache);
  try {
    fetcher.measure_round_trip(std::chrono::seconds(5));
    ADD_FAILURE() << "a server that wants a token answered without one";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("refused this client: this server requires a bearer token"),
              std::string::npos)
        << what;
    EXPECT_EQ(what.find("did not answer"), std::string::npos) << what;
  }
  std::filesystem::remove(token_file);
}

TEST(BrickFetcher, AServerThatNeverAnswersFailsWithinTheTimeoutAndStopsPromptly) {
  SilentListener silent;
  BrickCache cache(16 << 20);
  const auto start = std::chrono::steady_clock::now();
  {
    net::BrickFetcher fetcher("127.0.0.1:" + std::to_string(silent.port()), cache, {});
    try {
      fetcher.measure_round_trip(std::chrono::milliseconds(300));
      ADD_FAILURE() << "a silent server answered";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("did not answer within 300 ms"), std::string::npos)
          << e.what();
    }
    // Stopping cancels the stream still waiting for its connection, rather than waiting out
    // gRPC's 20 s connect timeout.
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

TEST(BrickFetcher, CorruptBricksAreFetchedAgain) {
  FetcherAgainstServer setup({"--fault-corrupt-every", "5"});
  auto& [server, cache, fetcher, id] = setup;
  fetcher.want(level(id, 1, 4));
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));
  const net::SourceStats stats = fetcher.stats();
  EXPECT_EQ(stats.received, 64u);
  EXPECT_EQ(stats.errors, 0u);
  EXPECT_GE(stats.corrupt, 64u / 5);
  const double corrupted = testing::metric_value(
      testing::http_get(server.metrics_port(), "/metrics"), "soltex_faults_corrupted_total");
  EXPECT_EQ(static_cast<double>(stats.corrupt), corrupted);
  for (int i = 0; i < 4; ++i) expect_cached_brick_is_local(cache, id, 1, {i, 3 - i, i});
}

TEST(BrickFetcher, SurvivesAServerKilledMidStream) {
  const int port = testing::free_port();
  // Slow bricks, so the kill lands while most are still owed.
  std::optional<SoltexdProcess> server(
      std::in_place, std::vector<std::string>{"--fault-delay-ms", "20", "--threads", "1"}, port);
  BrickCache cache(64 << 20);
  const net::FetcherOptions options = quick_reconnect();
  net::BrickFetcher fetcher("127.0.0.1:" + std::to_string(port), cache, options);
  const uint64_t id = fetcher.register_texture(marble(), unit_volume(6), 8, {});
  fetcher.want(level(id, 1, 4));
  while (fetcher.stats().received < 4) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  server->kill_now();
  server.reset();
  EXPECT_FALSE(fetcher.idle());

  server.emplace(std::vector<std::string>{}, port);  // a fresh server that never saw the texture
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));
  const net::SourceStats stats = fetcher.stats();
  EXPECT_GE(stats.reconnects, 1u);
  EXPECT_EQ(stats.received, 64u);
  EXPECT_EQ(stats.errors, 0u);
  expect_cached_brick_is_local(cache, id, 1, {3, 0, 2});
}

TEST(BrickFetcher, SpeaksTlsWithAClientCertificateAndAToken) {
  const testing::TestCertificates certs;
  const std::string token_file = testing::write_temporary_file("token", "fetcher-token\n");
  SoltexdProcess server({"--tls-cert", certs.server_cert(), "--tls-key", certs.server_key(),
                         "--tls-client-ca", certs.ca(), "--token-file", token_file});
  BrickCache cache(64 << 20);
  net::FetcherOptions options;
  options.security.tls_ca_file = certs.ca();
  options.security.tls_cert_file = certs.client_cert();
  options.security.tls_key_file = certs.client_key();
  options.security.token = net::read_token_file(token_file);
  std::filesystem::remove(token_file);
  net::BrickFetcher fetcher(server.grpc_address(), cache, options);
  const uint64_t id = fetcher.register_texture(marble(), unit_volume(6), 8, {});
  fetcher.want(level(id, 2, 2));
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(30)));
  EXPECT_EQ(fetcher.stats().received, 8u);
  EXPECT_EQ(fetcher.stats().errors, 0u);

  // Without the token the same TLS client is refused, with a message that says why.
  options.security.token.clear();
  options.register_timeout = std::chrono::milliseconds(3000);
  BrickCache other_cache(64 << 20);
  net::BrickFetcher anonymous(server.grpc_address(), other_cache, options);
  try {
    anonymous.register_texture(marble(), unit_volume(6), 8, {});
    ADD_FAILURE() << "registered without a token";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bearer token"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace soltex
