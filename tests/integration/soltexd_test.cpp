// soltexd over loopback: a real daemon process on port 0, real gRPC clients.
#include <arpa/inet.h>
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <csignal>
#include <functional>
#include <future>
#include <map>
#include <set>
#include <thread>

#include "brick_test_client.h"
#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/texture_id.h"
#include "soltex/spec_proto/spec_from_proto.h"
#include "soltex/v1/brick_service.grpc.pb.h"
#include "soltexd_process.h"

namespace soltex {
namespace {

using namespace testing;

TEST(Soltexd, AStreamThatCarriesItsTexturesNeedsNoRegistration) {
  SoltexdProcess server;
  auto stub = connect(server);
  const v1::RegisterTextureRequest registration = marble_request(6, 8);
  // Ids are content hashes: the client knows it without asking.
  const uint64_t id =
      texture_id(from_proto(registration.spec()), from_proto(registration.volume()), 8);
  v1::RegisterTextureRequest broken = marble_request(6, 8);
  broken.mutable_volume()->set_finest_level_log2(99);
  v1::BrickRequest request = want({key_of(id, 1, 0, 1, 2), key_of(id, 3, 0, 0, 0)});
  *request.add_textures() = registration;
  *request.add_textures() = broken;
  const StreamResult result = stream_once(*stub, request);
  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  ASSERT_EQ(result.bricks.size(), 2u);
  for (const v1::Brick& brick : result.bricks) {
    const DecodedBrick decoded = decode_brick(std::span(
        reinterpret_cast<const uint8_t*>(brick.payload().data()), brick.payload().size()));
    EXPECT_EQ(decoded.samples, local_brick(registration, brick.key()));
  }
  // The broken texture is refused by name and bound; the stream went on.
  ASSERT_EQ(result.request_errors.size(), 1u);
  EXPECT_EQ(result.request_errors[0].code(), static_cast<int>(grpc::StatusCode::INVALID_ARGUMENT));
  EXPECT_NE(result.request_errors[0].message().find("finest_level_log2"), std::string::npos)
      << result.request_errors[0].message();
}

TEST(Soltexd, ServerInfoReportsLimits) {
  SoltexdProcess server({"--max-keys-per-request", "100", "--max-queued-per-stream", "1000"});
  auto stub = connect(server);
  grpc::ClientContext context;
  v1::ServerInfo info;
  ASSERT_TRUE(stub->GetServerInfo(&context, {}, &info).ok());
  EXPECT_FALSE(info.version().empty());
  EXPECT_EQ(info.limits().max_keys_per_request(), 100u);
  EXPECT_EQ(info.limits().max_queued_per_stream(), 1000u);
  EXPECT_EQ(info.brick_sizes_size(), 2);
  EXPECT_EQ(info.codecs_size(), 3);
}

TEST(Soltexd, StreamedBricksEqualLocalEvaluationBitForBit) {
  SoltexdProcess server;
  auto stub = connect(server);
  const v1::RegisterTextureRequest registration = marble_request();
  const v1::TextureHandle handle = register_texture(*stub, registration);
  EXPECT_EQ(handle.id(),
            texture_id(from_proto(registration.spec()), from_proto(registration.volume()), 8));
  EXPECT_EQ(handle.levels(), 4u);  // 64, 32, 16, 8 cells
  // Registering again is idempotent.
  EXPECT_EQ(register_texture(*stub, registration).id(), handle.id());

  std::vector<v1::BrickKey> keys = level_keys(handle.id(), 3, 1);
  for (const auto& k : level_keys(handle.id(), 2, 2)) keys.push_back(k);
  keys.push_back(key_of(handle.id(), 0, 7, 0, 3));
  for (v1::Codec codec : {v1::CODEC_ZSTD, v1::CODEC_LZ4, v1::CODEC_RAW}) {
    const StreamResult result = stream_once(*stub, want(keys, codec));
    ASSERT_TRUE(result.status.ok()) << result.status.error_message();
    EXPECT_TRUE(result.errors.empty());
    ASSERT_EQ(result.bricks.size(), keys.size());
    for (const v1::Brick& brick : result.bricks) {
      EXPECT_EQ(brick.codec(), codec);
      const DecodedBrick decoded = decode_brick(std::span(
          reinterpret_cast<const uint8_t*>(brick.payload().data()), brick.payload().size()));
      EXPECT_EQ(decoded.brick_size, 8);
      EXPECT_EQ(decoded.channels, 3);
      ASSERT_EQ(decoded.samples, local_brick(registration, brick.key()))
          << "level " << brick.key().level();
    }
  }
}

// A key wanted many times in one message is one brick, whether it is made for the message or
// already in the server's brick cache (docs/PROTOCOL.md: duplicates are merged).
TEST(Soltexd, AKeyWantedTwiceInOneMessageIsSentOnce) {
  SoltexdProcess server;
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request(6));
  const std::vector<v1::BrickKey> copies(1024, key_of(handle.id(), 1, 0, 1, 0));
  for (const char* when : {"made", "cached"}) {
    const StreamResult result = stream_once(*stub, want(copies, v1::CODEC_RAW));
    EXPECT_TRUE(result.status.ok()) << when << ": " << result.status.error_message();
    EXPECT_EQ(result.bricks.size(), 1u) << when;
    EXPECT_TRUE(result.errors.empty()) << when;
  }
  // Forty keys, each twice: past the few a message is scanned for, a set remembers them.
  std::vector<v1::BrickKey> twice = level_keys(handle.id(), 0, 4);
  twice.resize(40);
  twice.insert(twice.end(), twice.begin(), twice.end());
  for (const char* when : {"made", "cached"}) {
    const StreamResult result = stream_once(*stub, want(twice, v1::CODEC_RAW));
    std::set<std::string> distinct;
    for (const v1::Brick& brick : result.bricks) distinct.insert(brick.key().SerializeAsString());
    EXPECT_EQ(result.bricks.size(), 40u) << when;
    EXPECT_EQ(distinct.size(), 40u) << when;
  }
}

// A key asked for again in a later message while still queued is merged with the first ask,
// even with the stream's queue at its bound: not refused, and sent once.
TEST(Soltexd, AKeyAskedAgainWhileQueuedIsMergedEvenAtTheQueueBound) {
  SoltexdProcess server({"--threads", "1", "--fault-delay-ms", "300", "--max-queued-per-stream",
                         "8", "--max-keys-per-request", "8"});
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request(6, 8));
  std::vector<v1::BrickKey> keys = level_keys(handle.id(), 0, 8);
  keys.resize(8);
  grpc::ClientContext context;
  auto stream = stub->StreamBricks(&context);
  ASSERT_TRUE(stream->Write(want(keys)));
  // One brick in the making (300 ms each), seven queued: the stream owes its bound of 8. The
  // last four are made last, so they are still queued when asked for again.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(stream->Write(want({keys.begin() + 4, keys.end()})));
  stream->WritesDone();
  std::multiset<std::string> received;
  std::size_t refused = 0;
  v1::BrickBatch batch;
  while (stream->Read(&batch)) {
    for (const v1::Brick& brick : batch.bricks()) received.insert(brick.key().SerializeAsString());
    refused += static_cast<std::size_t>(batch.errors_size());
  }
  EXPECT_TRUE(stream->Finish().ok());
  EXPECT_EQ(refused, 0u) << "a merged ask was refused over the queue bound";
  EXPECT_EQ(received.size(), keys.size()) << "a brick was sent twice or not at all";
  for (const v1::BrickKey& key : keys) EXPECT_EQ(received.count(key.SerializeAsString()), 1u);
}

TEST(Soltexd, CoarseLevelsAreServedFirst) {
  SoltexdProcess server({"--threads", "1"});
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request());
  std::vector<v1::BrickKey> keys = level_keys(handle.id(), 0, 8);  // fine first in the request
  keys.resize(64);
  keys.push_back(key_of(handle.id(), 3, 0, 0, 0));
  const StreamResult result = stream_once(*stub, want(keys));
  ASSERT_EQ(result.bricks.size(), keys.size());
  // The coarsest brick was queued with the rest but is served before the fine ones still queued.
  std::size_t position = 0;
  for (std::size_t i = 0; i < result.bricks.size(); ++i) {
    if (result.bricks[i].key().level() == 3) position = i;
  }
  EXPECT_LT(position, 8u);
}

TEST(Soltexd, BricksMadeTogetherShareMessages) {
  // A wait no brick reaches: only "nothing more is coming" sends a message short.
  SoltexdProcess server(
      {"--threads", "2", "--coalesce-bricks", "8", "--coalesce-wait-us", "1000000"});
  auto stub = connect(server);
  // Bricks of 16 take longer to make than a message takes to write, as in a real frame.
  const v1::TextureHandle handle = register_texture(*stub, marble_request(8, 16));
  const std::vector<v1::BrickKey> keys = level_keys(handle.id(), 0, 4);  // 64 bricks
  const StreamResult result = stream_once(*stub, want(keys));
  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  ASSERT_EQ(result.bricks.size(), keys.size());
  int short_messages = 0;
  for (const int bricks : result.bricks_per_message) {
    EXPECT_LE(bricks, 32);
    short_messages += bricks < 8 ? 1 : 0;
  }
  EXPECT_LE(short_messages, 1) << result.bricks_per_message.size() << " messages";
}

// A held-back brick goes out when its wait ends, even if the stream's next brick is slow.
TEST(Soltexd, AHeldBrickWaitsNoLongerThanTheCoalesceWait) {
  SoltexdProcess server({"--threads", "1", "--fault-delay-ms", "300", "--coalesce-bricks", "8",
                         "--coalesce-wait-us", "20000"});
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request());
  const StreamResult result =
      stream_once(*stub, want({key_of(handle.id(), 3, 0, 0, 0), key_of(handle.id(), 2, 0, 0, 0)}));
  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  ASSERT_EQ(result.bricks.size(), 2u);
  // The first brick waited 20 ms for the second, which came 300 ms later: alone.
  EXPECT_EQ(result.bricks_per_message, (std::vector<int>{1, 1}));
}

// A lone brick is not held back waiting for company.
TEST(Soltexd, ALoneBrickIsSentAtOnce) {
  SoltexdProcess server;
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request());
  const StreamResult result = stream_once(*stub, want({key_of(handle.id(), 3, 0, 0, 0)}));
  ASSERT_TRUE(result.status.ok()) << result.status.error_message();
  ASSERT_EQ(result.bricks.size(), 1u);
  EXPECT_EQ(result.bricks_per_message, std::vector<int>{1});
}

// With more streams waiting than workers, a stream's turn makes a run of its bricks, and the
// run shares a message: not one message per brick. Every stream is still served in full.
TEST(Soltexd, AmongManyStreamsATurnsBricksShareAMessage) {
  SoltexdProcess server({"--threads", "1", "--coalesce-wait-us", "1000000"});
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request(8, 16));
  constexpr int kStreams = 6;
  std::vector<std::future<StreamResult>> results;
  for (int s = 0; s < kStreams; ++s) {
    results.push_back(std::async(std::launch::async, [&, s] {
      // Each stream its own 16 bricks, so none is answered from another's work.
      std::vector<v1::BrickKey> keys;
      for (int i = 0; i < 16; ++i) keys.push_back(key_of(handle.id(), 0, i % 4, i / 4, s));
      return stream_once(*stub, want(keys));
    }));
  }
  std::size_t messages = 0;
  for (auto& f : results) {
    const StreamResult r = f.get();
    ASSERT_TRUE(r.status.ok()) << r.status.error_message();
    EXPECT_EQ(r.bricks.size(), 16u);
    messages += r.bricks_per_message.size();
  }
  // One brick a message would be 96; runs of 16 make about 1 a stream (the first requests may
  // arrive before the others and be served a brick at a time).
  EXPECT_LE(messages, static_cast<std::size_t>(kStreams * 16 / 3)) << messages << " messages";
}

// A run's bricks share one message even when making them takes far longer than the coalesce
// wait: the run's last brick sends it, not the timer.
TEST(Soltexd, ARunSharesOneMessagePastTheCoalesceWait) {
  SoltexdProcess server({"--threads", "1", "--coalesce-wait-us", "1"});
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request(8, 16));
  constexpr int kStreams = 6;
  std::vector<std::future<StreamResult>> results;
  for (int s = 0; s < kStreams; ++s) {
    results.push_back(std::async(std::launch::async, [&, s] {
      std::vector<v1::BrickKey> keys;
      for (int i = 0; i < 16; ++i) keys.push_back(key_of(handle.id(), 0, i % 4, i / 4, s));
      return stream_once(*stub, want(keys));
    }));
  }
  std::size_t messages = 0;
  for (auto& f : results) {
    const StreamResult r = f.get();
    ASSERT_TRUE(r.status.ok()) << r.status.error_message();
    EXPECT_EQ(r.bricks.size(), 16u);
    messages += r.bricks_per_message.size();
  }
  // A 1 µs wait alone would send nearly every brick by itself (96 messages); the streams that
  // ask before the others are crowded are still served a brick at a time.
  EXPECT_LE(messages, static_cast<std::size_t>(kStreams * 16 / 3)) << messages << " messages";
}

TEST(Soltexd, ManyConcurrentStreamsAndSingleFlight) {
  SoltexdProcess server;
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request());
  const std::vector<v1::BrickKey> keys = level_keys(handle.id(), 1, 4);  // 64 bricks
  const double evaluated_before = metric_value(metrics(server), "soltex_bricks_evaluated_total");

  constexpr int kStreams = 12;
  std::vector<std::future<StreamResult>> results;
  for (int s = 0; s < kStreams; ++s) {
    results.push_back(
        std::async(std::launch::async, [&] { return stream_once(*stub, want(keys)); }));
  }
  for (auto& f : results) {
    const StreamResult r = f.get();
    EXPECT_TRUE(r.status.ok()) << r.status.error_message();
    EXPECT_EQ(r.bricks.size(), keys.size());
  }
  const std::string after = metrics(server);
  // Every brick was evaluated once, however many streams wanted it at the same time.
  EXPECT_EQ(metric_value(after, "soltex_bricks_evaluated_total") - evaluated_before, 64.0);
  EXPECT_EQ(metric_value(after, "soltex_bricks_served_total"), 64.0 * kStreams);
  EXPECT_EQ(metric_value(after, "soltex_streams_opened_total"), kStreams);
  EXPECT_EQ(metric_value(after, "soltex_cache_hits_total") +
                metric_value(after, "soltex_cache_misses_total"),
            64.0 * kStreams);
}

TEST(Soltexd, CancellationDropsQueuedWork) {
  SoltexdProcess server({"--threads", "1"});
  auto stub = connect(server);
  v1::RegisterTextureRequest registration = marble_request(7, 8);
  registration.set_mip_mode(v1::MIP_MODE_SUPERSAMPLED);  // slow bricks: the queue fills up
  registration.set_supersample(3);
  const v1::TextureHandle handle = register_texture(*stub, registration);
  const std::vector<v1::BrickKey> keys = level_keys(handle.id(), 0, 16);  // 4096 bricks
  const std::vector<v1::BrickKey> first(keys.begin(), keys.begin() + 1000);

  grpc::ClientContext context;
  auto stream = stub->StreamBricks(&context);
  ASSERT_TRUE(stream->Write(want(first)));
  v1::BrickRequest cancel;
  for (const auto& key : first) *cancel.add_cancel() = key;
  ASSERT_TRUE(stream->Write(cancel));
  stream->WritesDone();
  std::size_t received = 0;
  v1::BrickBatch batch;
  while (stream->Read(&batch)) received += static_cast<std::size_t>(batch.bricks_size());
  EXPECT_TRUE(stream->Finish().ok());
  EXPECT_LT(received, first.size());
  const std::string m = metrics(server);
  EXPECT_EQ(metric_value(m, "soltex_bricks_cancelled_total") + static_cast<double>(received),
            static_cast<double>(first.size()));
  EXPECT_EQ(metric_value(m, "soltex_queue_depth"), 0.0);
}

// A client that asks for many bricks and does not read: the server makes only what fits its
// unsent-bytes bound (StreamLimits::max_unsent_bytes, 2 MiB) and holds the rest as keys, then
// makes them as the client reads.
TEST(Soltexd, AStreamThatDoesNotReadHoldsABoundedPartOfItsBricks) {
  SoltexdProcess server({"--threads", "2"});
  auto stub = connect(server);
  v1::RegisterTextureRequest registration = marble_request(8, 16);
  for (const auto channel : {v1::CHANNEL_COLOUR, v1::CHANNEL_OPACITY, v1::CHANNEL_SPECULAR}) {
    registration.mutable_spec()->add_channels(channel);
  }
  const v1::TextureHandle handle = register_texture(*stub, registration);
  std::vector<v1::BrickKey> keys = level_keys(handle.id(), 0, 16);
  keys.resize(1024);  // 17^3 samples x 5 channels raw: about 24 KB each, 25 MB in all

  grpc::ClientContext context;
  auto stream = stub->StreamBricks(&context);
  ASSERT_TRUE(stream->Write(want(keys, v1::CODEC_RAW)));
  // Until the server stops making bricks for it: the count stays put for a second.
  double evaluated = -1.0;
  for (int still = 0, polls = 0; still < 5 && polls < 200; ++polls) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const double now = metric_value(metrics(server), "soltex_bricks_evaluated_total");
    still = now == evaluated ? still + 1 : 0;
    evaluated = now;
  }
  // 2 MiB of unsent bricks, the write in flight and what HTTP/2's windows took: a few
  // hundred at most, not the 1024 asked for.
  EXPECT_LT(evaluated, 512.0);
  EXPECT_GT(evaluated, 0.0);

  // Read, and the rest is made.
  stream->WritesDone();
  std::size_t received = 0;
  v1::BrickBatch batch;
  while (stream->Read(&batch)) received += static_cast<std::size_t>(batch.bricks_size());
  EXPECT_TRUE(stream->Finish().ok());
  EXPECT_EQ(received, keys.size());
}

// Past gRPC threads' share of request handling (0 here), a stream's request waits for a
// worker's turn, charged to its client, and the stream's next message is read only after it:
// a client's flood of requests queues in its own connection, not in front of other clients'.
TEST(Soltexd, PastTheDirectShareRequestsAreReadOneAtATimeOnWorkerTurns) {
  // One worker, kept busy 4 s by a brick of the first stream.
  SoltexdProcess server(
      {"--threads", "1", "--fault-delay-ms", "4000", "--direct-request-share", "0"});
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request());
  grpc::ClientContext busy_context;
  auto busy = stub->StreamBricks(&busy_context);
  ASSERT_TRUE(busy->Write(want({key_of(handle.id(), 3, 0, 0, 0)})));
  const auto poll_until = [&](const std::function<bool(const std::string&)>& done) {
    for (int polls = 0; polls < 250; ++polls) {
      if (done(metrics(server))) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  };
  // Queued by a worker's turn, then taken off the queue: the worker is making it.
  ASSERT_TRUE(poll_until([](const std::string& m) {
    return metric_value(m, "soltex_bricks_requested_total") == 1.0 &&
           metric_value(m, "soltex_queue_depth") == 0.0;
  }));

  grpc::ClientContext context;
  auto stream = stub->StreamBricks(&context);
  constexpr int kRequests = 5;
  for (int i = 0; i < kRequests; ++i) {
    v1::BrickRequest cancel;
    *cancel.add_cancel() = key_of(handle.id(), 0, i, 0, 0);  // queued nowhere: nothing to do
    ASSERT_TRUE(stream->Write(cancel));
  }
  // Its first request is read and waits for the worker; the others wait unread.
  ASSERT_TRUE(poll_until(
      [](const std::string& m) { return metric_value(m, "soltex_stream_messages_total") >= 2.0; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  std::string m = metrics(server);
  EXPECT_EQ(metric_value(m, "soltex_stream_messages_total"), 2.0);
  EXPECT_EQ(metric_value(m, "soltex_bricks_served_total"), 0.0);  // still within the 4 s

  stream->WritesDone();
  v1::BrickBatch batch;
  while (stream->Read(&batch)) ADD_FAILURE() << "a stream that only cancels gets no message";
  EXPECT_TRUE(stream->Finish().ok());
  busy->WritesDone();
  std::size_t bricks = 0;
  while (busy->Read(&batch)) bricks += static_cast<std::size_t>(batch.bricks_size());
  EXPECT_TRUE(busy->Finish().ok());
  EXPECT_EQ(bricks, 1u);
  m = metrics(server);
  EXPECT_EQ(metric_value(m, "soltex_stream_messages_total"), 1.0 + kRequests);
  EXPECT_EQ(metric_value(m, "soltex_stream_messages_on_turns_total"), 1.0 + kRequests);
}

// A stream whose queue is full is still read while its client reads: wants past the bound get
// RESOURCE_EXHAUSTED at once, and a cancel sent after them takes effect at once, not after
// the queue has drained (here 256 bricks of 20 ms each).
TEST(Soltexd, AFullQueueRefusesMoreAndCancelsAtOnce) {
  SoltexdProcess server({"--max-keys-per-request", "64", "--max-queued-per-stream", "256",
                         "--threads", "1", "--fault-delay-ms", "20"});
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request(8, 16));
  const std::vector<v1::BrickKey> keys = level_keys(handle.id(), 0, 16);  // 4,096
  grpc::ClientContext context;
  auto stream = stub->StreamBricks(&context);
  constexpr std::size_t kMessages = 8, kPerMessage = 64;
  v1::BrickRequest cancel;
  for (std::size_t m = 0; m < kMessages; ++m) {
    const std::vector<v1::BrickKey> part(
        keys.begin() + static_cast<std::ptrdiff_t>(m * kPerMessage),
        keys.begin() + static_cast<std::ptrdiff_t>((m + 1) * kPerMessage));
    ASSERT_TRUE(stream->Write(want(part)));
    for (const v1::BrickKey& key : part) *cancel.add_cancel() = key;
  }
  ASSERT_TRUE(stream->Write(cancel));
  stream->WritesDone();
  std::size_t bricks = 0, refused = 0;
  v1::BrickBatch batch;
  while (stream->Read(&batch)) {
    bricks += static_cast<std::size_t>(batch.bricks_size());
    for (const auto& e : batch.errors()) {
      if (e.code() == grpc::StatusCode::RESOURCE_EXHAUSTED) ++refused;
    }
  }
  EXPECT_TRUE(stream->Finish().ok());
  // 512 asked for, 256 queued at most: nearly all of the other 256 refused (a brick or two
  // may be made while the wants arrive, which frees a place each).
  EXPECT_GE(refused, 200u);
  EXPECT_LE(bricks, 64u) << "the cancel waited behind the full queue";
}

TEST(Soltexd, BadKeysGetTheirCodeAndTheStreamGoesOn) {
  SoltexdProcess server({"--max-keys-per-request", "64", "--max-queued-per-stream", "64"});
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request());

  grpc::ClientContext context;
  auto stream = stub->StreamBricks(&context);
  // Unknown texture, level beyond the coarsest, brick beyond the level, and one good key.
  ASSERT_TRUE(
      stream->Write(want({key_of(handle.id() ^ 1, 0, 0, 0, 0), key_of(handle.id(), 9, 0, 0, 0),
                          key_of(handle.id(), 0, 8, 0, 0), key_of(handle.id(), 3, 0, 0, 0)})));
  // Too many keys in one request.
  ASSERT_TRUE(stream->Write(want(level_keys(handle.id(), 1, 5))));  // 125 > 64
  // Afterwards the stream still serves.
  ASSERT_TRUE(stream->Write(want({key_of(handle.id(), 2, 1, 1, 1)})));
  stream->WritesDone();
  std::map<int, std::vector<std::string>> errors;
  std::vector<std::string> request_errors;
  std::set<uint32_t> served_levels;
  v1::BrickBatch batch;
  while (stream->Read(&batch)) {
    for (const auto& e : batch.errors()) errors[e.code()].push_back(e.message());
    for (const auto& e : batch.request_errors()) {
      EXPECT_EQ(e.code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
      request_errors.push_back(e.message());
    }
    for (const auto& b : batch.bricks()) served_levels.insert(b.key().level());
  }
  EXPECT_TRUE(stream->Finish().ok());
  ASSERT_EQ(errors[grpc::StatusCode::NOT_FOUND].size(), 1u);
  EXPECT_NE(errors[grpc::StatusCode::NOT_FOUND][0].find("is not registered"), std::string::npos);
  ASSERT_EQ(errors[grpc::StatusCode::OUT_OF_RANGE].size(), 2u);
  EXPECT_NE(errors[grpc::StatusCode::OUT_OF_RANGE][0].find("level 9 is outside [0, 3]"),
            std::string::npos);
  EXPECT_NE(errors[grpc::StatusCode::OUT_OF_RANGE][1].find("must be in [0, 7] at level 0"),
            std::string::npos);
  ASSERT_EQ(request_errors.size(), 1u);
  EXPECT_NE(request_errors[0].find("request wants 125 bricks; at most 64"), std::string::npos);
  EXPECT_EQ(served_levels, (std::set<uint32_t>{2, 3}));

  const std::string m = metrics(server);
  EXPECT_EQ(metric_value(m, "soltex_errors_total{grpc_code=\"NOT_FOUND\"}"), 1.0);
  EXPECT_EQ(metric_value(m, "soltex_errors_total{grpc_code=\"OUT_OF_RANGE\"}"), 2.0);
  EXPECT_EQ(metric_value(m, "soltex_errors_total{grpc_code=\"RESOURCE_EXHAUSTED\"}"), 1.0);
}

TEST(Soltexd, InvalidRegistrationsAreRefusedWithTheFieldAndBound) {
  SoltexdProcess server({"--max-textures", "2"});
  auto stub = connect(server);
  v1::RegisterTextureRequest bad = marble_request();
  bad.mutable_spec()->mutable_marble()->mutable_turbulence()->set_octave_max(40);
  {
    grpc::ClientContext context;
    v1::TextureHandle handle;
    const grpc::Status status = stub->RegisterTexture(&context, bad, &handle);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_NE(status.error_message().find("marble.turbulence.octave_max = 40"), std::string::npos);
  }
  {
    v1::RegisterTextureRequest too_fine = marble_request(15);
    grpc::ClientContext context;
    v1::TextureHandle handle;
    const grpc::Status status = stub->RegisterTexture(&context, too_fine, &handle);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_NE(status.error_message().find("volume.finest_level_log2"), std::string::npos);
  }
  register_texture(*stub, marble_request(6));
  register_texture(*stub, marble_request(7));
  // A full registry evicts what no stream uses (tests/integration/limits_test.cpp); only a
  // registry of textures in use refuses.
  register_texture(*stub, marble_request(8));
  // An evicted texture is registered again and serves.
  const v1::TextureHandle handle = register_texture(*stub, marble_request(6));
  EXPECT_EQ(stream_once(*stub, want({key_of(handle.id(), 3, 0, 0, 0)})).bricks.size(), 1u);
}

TEST(Soltexd, OversizeMessagesAreRefused) {
  SoltexdProcess server({"--max-message-bytes", "4096"});
  auto stub = connect(server);
  v1::RegisterTextureRequest huge = marble_request();
  for (int i = 0; i < 20000; ++i) huge.mutable_spec()->add_channels(v1::CHANNEL_COLOUR);
  grpc::ClientContext context;
  v1::TextureHandle handle;
  EXPECT_EQ(stub->RegisterTexture(&context, huge, &handle).error_code(),
            grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_EQ(register_texture(*stub, marble_request()).levels(), 4u);
}

// `count` keys of level 0 of a marble texture supersampled `supersample`^3 times per sample:
// bricks that take a worker long enough to make for a shutdown to catch them being made.
std::vector<v1::BrickKey> slow_keys(v1::BrickService::Stub& stub, int supersample,
                                    std::size_t count) {
  v1::RegisterTextureRequest registration = marble_request(7, 8);
  registration.set_mip_mode(v1::MIP_MODE_SUPERSAMPLED);
  registration.set_supersample(static_cast<uint32_t>(supersample));
  const v1::TextureHandle handle = register_texture(stub, registration);
  std::vector<v1::BrickKey> keys = level_keys(handle.id(), 0, 16);
  keys.resize(count);
  return keys;
}

// SIGTERM: health NOT_SERVING, and a stream that has not half-closed goes on receiving what
// it asked for during the grace, then ends UNAVAILABLE (1,000 supersampled bricks on one
// thread take far longer than the second of grace).
TEST(Soltexd, HealthAndGracefulShutdownWithOpenStreams) {
  SoltexdProcess server({"--threads", "1", "--shutdown-grace-s", "1"});
  EXPECT_EQ(health_status(server), 1);                                    // SERVING
  EXPECT_NE(reflection_status(server), grpc::StatusCode::UNIMPLEMENTED);  // offered without a token
  auto stub = connect(server);
  const std::vector<v1::BrickKey> keys = slow_keys(*stub, 4, 1000);
  grpc::ClientContext context;
  auto stream = stub->StreamBricks(&context);
  ASSERT_TRUE(stream->Write(want(keys)));
  v1::BrickBatch batch;
  ASSERT_TRUE(stream->Read(&batch));  // the stream is live and producing

  server.send_signal(SIGTERM);
  std::size_t after_signal = 0;
  while (stream->Read(&batch)) after_signal += static_cast<std::size_t>(batch.bricks_size());
  const grpc::Status status = stream->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAVAILABLE) << status.error_message();
  EXPECT_GT(after_signal, 0u) << "no brick was sent during the grace";
  EXPECT_EQ(server.wait_for_exit(), 0) << server.log();
  EXPECT_NE(server.log().find("shutting down"), std::string::npos);
}

// --fault-delay-ms holds a worker per brick, as a slow evaluation would; the delays end with
// the grace, so a server asked for bricks a minute each still stops within about the grace.
TEST(Soltexd, FaultDelaysEndWithTheShutdownGrace) {
  SoltexdProcess server({"--threads", "2", "--shutdown-grace-s", "1", "--fault-delay-ms", "60000"});
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request(6, 8));
  grpc::ClientContext context;
  auto stream = stub->StreamBricks(&context);
  ASSERT_TRUE(stream->Write(want(level_keys(handle.id(), 1, 4))));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // both workers in a delay
  const auto signalled = std::chrono::steady_clock::now();
  server.send_signal(SIGTERM);
  EXPECT_EQ(server.wait_for_exit(std::chrono::seconds(30)), 0) << server.log();
  EXPECT_LT(std::chrono::steady_clock::now() - signalled, std::chrono::seconds(10));
  context.TryCancel();
  (void)stream->Finish();
}

// A stream that half-closed before SIGTERM gets every brick it asked for within the grace and
// ends OK.
// A stream that has asked for 200 slow bricks and half-closed, its first batch read.
struct HalfClosedStream {
  explicit HalfClosedStream(const SoltexdProcess& server) : stub(connect(server)) {
    keys = slow_keys(*stub, 2, 200);
    stream = stub->StreamBricks(&context);
    started = stream->Write(want(keys)) && stream->WritesDone() && stream->Read(&batch);
  }
  std::unique_ptr<v1::BrickService::Stub> stub;
  std::vector<v1::BrickKey> keys;
  grpc::ClientContext context;
  std::unique_ptr<grpc::ClientReaderWriter<v1::BrickRequest, v1::BrickBatch>> stream;
  v1::BrickBatch batch;
  bool started = false;
};

TEST(Soltexd, AHalfClosedStreamGetsEveryBrickItAskedForOnShutdown) {
  SoltexdProcess server({"--threads", "1", "--shutdown-grace-s", "20"});
  HalfClosedStream open(server);
  ASSERT_TRUE(open.started);
  auto& [stub, keys, context, stream, batch, started] = open;
  std::size_t received = static_cast<std::size_t>(batch.bricks_size());

  server.send_signal(SIGTERM);
  while (stream->Read(&batch)) received += static_cast<std::size_t>(batch.bricks_size());
  const grpc::Status status = stream->Finish();
  EXPECT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(received, keys.size());
  EXPECT_EQ(server.wait_for_exit(), 0) << server.log();
}

// Once shutdown begins a stream reads no more requests: a message sent after SIGTERM is not
// read (its bricks are not made), the bricks asked for before it are sent, and the stream's
// status says a request went unread.
TEST(Soltexd, ARequestSentAfterShutdownBeganIsNotRead) {
  SoltexdProcess server({"--threads", "1", "--shutdown-grace-s", "20", "--fault-delay-ms", "100"});
  auto stub = connect(server);
  const v1::TextureHandle handle = register_texture(*stub, marble_request(6, 8));
  const std::vector<v1::BrickKey> keys = level_keys(handle.id(), 0, 8);
  const std::vector<v1::BrickKey> before(keys.begin(), keys.begin() + 8);
  const std::vector<v1::BrickKey> after(keys.begin() + 8, keys.begin() + 12);
  grpc::ClientContext context;
  auto stream = stub->StreamBricks(&context);
  ASSERT_TRUE(stream->Write(want(before)));
  v1::BrickBatch batch;
  ASSERT_TRUE(stream->Read(&batch));
  std::size_t received = static_cast<std::size_t>(batch.bricks_size());
  server.send_signal(SIGTERM);
  for (int i = 0; i < 100 && health_status(server) == 1; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(stream->Write(want(after)));
  std::set<std::string> asked_after;
  for (const v1::BrickKey& key : after) asked_after.insert(key.SerializeAsString());
  std::size_t made_after = 0;
  while (stream->Read(&batch)) {
    received += static_cast<std::size_t>(batch.bricks_size());
    for (const v1::Brick& brick : batch.bricks()) {
      made_after += asked_after.count(brick.key().SerializeAsString());
    }
  }
  const grpc::Status status = stream->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAVAILABLE) << status.error_message();
  EXPECT_NE(status.error_message().find("what was sent since was not read"), std::string::npos)
      << status.error_message();
  EXPECT_EQ(made_after, 0u) << "a request sent after SIGTERM was read and served";
  EXPECT_EQ(received, before.size());
  EXPECT_EQ(server.wait_for_exit(), 0) << server.log();
}

// Whether a TCP connection to 127.0.0.1:port is accepted.
bool accepts_connections(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool accepted = connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  close(fd);
  return accepted;
}

// From SIGTERM on, the HTTP port takes no new connections either, while a gRPC stream still
// gets its grace.
TEST(Soltexd, HttpTakesNoNewConnectionsOnceShutdownBegins) {
  SoltexdProcess server(
      {"--threads", "1", "--shutdown-grace-s", "20", "--http-listen", "127.0.0.1:0"});
  ASSERT_TRUE(accepts_connections(server.http_port()));
  HalfClosedStream open(server);
  ASSERT_TRUE(open.started);
  auto& [stub, keys, context, stream, batch, started] = open;

  server.send_signal(SIGTERM);
  bool refused = false;
  for (int i = 0; i < 200 && !refused; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    refused = !accepts_connections(server.http_port());
  }
  EXPECT_TRUE(refused) << "HTTP still accepted connections 2 s into the shutdown";
  while (stream->Read(&batch)) {
  }
  EXPECT_TRUE(stream->Finish().ok()) << "the stream did not get its grace";
  EXPECT_EQ(server.wait_for_exit(), 0) << server.log();
}

// Values are checked as sent, before any conversion: the message quotes the client's value.
TEST(Soltexd, RegistrationErrorsQuoteTheValueSent) {
  SoltexdProcess server;
  auto stub = connect(server);
  const auto refusal = [&](const v1::RegisterTextureRequest& request) {
    grpc::ClientContext context;
    v1::TextureHandle handle;
    const grpc::Status status = stub->RegisterTexture(&context, request, &handle);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    return status.error_message();
  };
  v1::RegisterTextureRequest big_bricks = marble_request();
  big_bricks.set_brick_size(4294967295u);
  EXPECT_EQ(refusal(big_bricks), "brick_size = 4294967295: must be 8 or 16 (0: the default, 16)");
  v1::RegisterTextureRequest many_samples = marble_request();
  many_samples.set_mip_mode(v1::MIP_MODE_SUPERSAMPLED);
  many_samples.set_supersample(4294967295u);
  EXPECT_EQ(refusal(many_samples),
            "supersample = 4294967295: must be in [1, 4] (0: the default, 2)");
  many_samples.set_supersample(5);
  EXPECT_NE(refusal(many_samples).find("supersample = 5:"), std::string::npos);
  many_samples.set_supersample(4);
  EXPECT_GT(register_texture(*stub, many_samples).levels(), 0u);
}

TEST(Soltexd, MetricsEndpoint) {
  SoltexdProcess server;
  int status = 0;
  const std::string body = http_get(server.metrics_port(), "/metrics", &status);
  EXPECT_EQ(status, 200);
  for (const char* name :
       {"soltex_bricks_served_total", "soltex_bricks_evaluated_total", "soltex_cache_hits_total",
        "soltex_cache_misses_total", "soltex_cache_bytes", "soltex_queue_depth",
        "soltex_brick_latency_seconds_count"}) {
    EXPECT_GE(metric_value(body, name), 0.0) << name;
  }
  http_get(server.metrics_port(), "/nothing", &status);
  EXPECT_EQ(status, 404);
}

}  // namespace
}  // namespace soltex
