// soltexd over loopback: a real daemon process on port 0, real gRPC clients.
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <future>
#include <map>
#include <set>
#include <thread>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/texture_id.h"
#include "soltex/spec_proto/spec_from_proto.h"
#include "soltex/v1/brick_service.grpc.pb.h"
#include "soltexd_process.h"

namespace soltex {
namespace {

using testing::http_get;
using testing::metric_value;
using testing::SoltexdProcess;

std::unique_ptr<v1::BrickService::Stub> connect(const SoltexdProcess& server) {
  return v1::BrickService::NewStub(
      grpc::CreateChannel(server.grpc_address(), grpc::InsecureChannelCredentials()));
}

v1::RegisterTextureRequest marble_request(int finest_level_log2 = 6, int brick_size = 8) {
  v1::RegisterTextureRequest request;
  request.mutable_spec()->mutable_marble();
  auto* volume = request.mutable_volume();
  volume->mutable_min()->set_x(-1);
  volume->mutable_min()->set_y(-1);
  volume->mutable_min()->set_z(-1);
  volume->mutable_max()->set_x(1);
  volume->mutable_max()->set_y(1);
  volume->mutable_max()->set_z(1);
  volume->set_finest_level_log2(static_cast<uint32_t>(finest_level_log2));
  request.set_brick_size(static_cast<uint32_t>(brick_size));
  return request;
}

v1::TextureHandle register_texture(v1::BrickService::Stub& stub,
                                   const v1::RegisterTextureRequest& request) {
  grpc::ClientContext context;
  v1::TextureHandle handle;
  const grpc::Status status = stub.RegisterTexture(&context, request, &handle);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return handle;
}

v1::BrickKey key_of(uint64_t texture, int level, int x, int y, int z) {
  v1::BrickKey key;
  key.set_texture_id(texture);
  key.set_level(static_cast<uint32_t>(level));
  key.set_x(x);
  key.set_y(y);
  key.set_z(z);
  return key;
}

// All bricks of `level`.
std::vector<v1::BrickKey> level_keys(uint64_t texture, int level, int bricks_per_axis) {
  std::vector<v1::BrickKey> keys;
  for (int z = 0; z < bricks_per_axis; ++z)
    for (int y = 0; y < bricks_per_axis; ++y)
      for (int x = 0; x < bricks_per_axis; ++x) keys.push_back(key_of(texture, level, x, y, z));
  return keys;
}

struct StreamResult {
  std::vector<v1::Brick> bricks;
  std::vector<v1::BrickError> errors;
  std::vector<v1::RequestError> request_errors;
  grpc::Status status;
};

// Sends one request (then half-closes) and reads every batch until the server finishes.
StreamResult stream_once(v1::BrickService::Stub& stub, const v1::BrickRequest& request) {
  grpc::ClientContext context;
  auto stream = stub.StreamBricks(&context);
  StreamResult result;
  stream->Write(request);
  stream->WritesDone();
  v1::BrickBatch batch;
  while (stream->Read(&batch)) {
    for (auto& b : *batch.mutable_bricks()) result.bricks.push_back(std::move(b));
    for (auto& e : *batch.mutable_errors()) result.errors.push_back(std::move(e));
    for (auto& e : *batch.mutable_request_errors()) result.request_errors.push_back(std::move(e));
  }
  result.status = stream->Finish();
  return result;
}

v1::BrickRequest want(const std::vector<v1::BrickKey>& keys, v1::Codec codec = v1::CODEC_ZSTD) {
  v1::BrickRequest request;
  for (const auto& key : keys) *request.add_want()->mutable_key() = key;
  request.add_accept_codecs(codec);
  return request;
}

// The same brick made here: evaluate, quantize.
std::vector<uint8_t> local_brick(const v1::RegisterTextureRequest& registration,
                                 const v1::BrickKey& key) {
  const TextureSpec spec = from_proto(registration.spec());
  const Volume volume = from_proto(registration.volume());
  const TextureEvaluator evaluator(spec);
  const BrickLayout layout(volume, static_cast<int>(registration.brick_size()));
  std::vector<float> samples(static_cast<std::size_t>(layout.samples_per_brick()) *
                             spec.channels.sample_count());
  evaluate_brick(evaluator, layout, static_cast<int>(key.level()), {key.x(), key.y(), key.z()}, {},
                 samples);
  return quantize(samples);
}

std::string metrics(const SoltexdProcess& server) {
  return http_get(server.metrics_port(), "/metrics");
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
  EXPECT_EQ(metric_value(m, "soltex_errors_total{code=\"NOT_FOUND\"}"), 1.0);
  EXPECT_EQ(metric_value(m, "soltex_errors_total{code=\"OUT_OF_RANGE\"}"), 2.0);
  EXPECT_EQ(metric_value(m, "soltex_errors_total{code=\"RESOURCE_EXHAUSTED\"}"), 1.0);
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
  {
    grpc::ClientContext context;
    v1::TextureHandle handle;
    const grpc::Status status = stub->RegisterTexture(&context, marble_request(8), &handle);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(status.error_message().find("the limit is 2"), std::string::npos);
  }
  // The registered ones still serve.
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

int health_status(const SoltexdProcess& server) {
  auto channel = grpc::CreateChannel(server.grpc_address(), grpc::InsecureChannelCredentials());
  grpc::GenericStub stub(channel);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
  // HealthCheckRequest{service: ""} encodes to no bytes (but the buffer must exist).
  grpc::Slice empty("");
  grpc::ByteBuffer request(&empty, 1), response;
  std::promise<grpc::Status> done;
  stub.UnaryCall(&context, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request, &response,
                 [&](grpc::Status s) { done.set_value(s); });
  const grpc::Status status = done.get_future().get();
  if (!status.ok()) return -status.error_code();
  std::vector<grpc::Slice> slices;
  (void)response.Dump(&slices);
  std::string bytes;
  for (const auto& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
  // HealthCheckResponse{status = 1}: field 1, varint.
  return bytes.size() == 2 && bytes[0] == 0x08 ? bytes[1] : -100;
}

TEST(Soltexd, HealthAndGracefulShutdownWithOpenStreams) {
  SoltexdProcess server({"--threads", "1"});
  EXPECT_EQ(health_status(server), 1);  // SERVING
  auto stub = connect(server);
  v1::RegisterTextureRequest registration = marble_request(7, 8);
  registration.set_mip_mode(v1::MIP_MODE_SUPERSAMPLED);
  registration.set_supersample(4);
  const v1::TextureHandle handle = register_texture(*stub, registration);

  grpc::ClientContext context;
  auto stream = stub->StreamBricks(&context);
  std::vector<v1::BrickKey> keys = level_keys(handle.id(), 0, 16);
  keys.resize(1000);
  ASSERT_TRUE(stream->Write(want(keys)));
  v1::BrickBatch batch;
  ASSERT_TRUE(stream->Read(&batch));  // the stream is live and producing

  EXPECT_EQ(server.terminate(), 0) << server.log();
  while (stream->Read(&batch)) {
  }
  const grpc::Status status = stream->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAVAILABLE) << status.error_message();
  EXPECT_NE(server.log().find("shutting down"), std::string::npos);
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
