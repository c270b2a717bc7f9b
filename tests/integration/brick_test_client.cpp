#include "brick_test_client.h"

#include <grpcpp/generic/generic_stub.h>
#include <gtest/gtest.h>

#include <future>

#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/spec_proto/spec_from_proto.h"

namespace soltex::testing {

std::unique_ptr<v1::BrickService::Stub> connect(const std::string& address) {
  return v1::BrickService::NewStub(
      grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
}

std::unique_ptr<v1::BrickService::Stub> connect(const SoltexdProcess& server) {
  return connect(server.grpc_address());
}

v1::RegisterTextureRequest marble_request(int finest_level_log2, int brick_size) {
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

std::vector<v1::BrickKey> level_keys(uint64_t texture, int level, int bricks_per_axis) {
  std::vector<v1::BrickKey> keys;
  for (int z = 0; z < bricks_per_axis; ++z)
    for (int y = 0; y < bricks_per_axis; ++y)
      for (int x = 0; x < bricks_per_axis; ++x) keys.push_back(key_of(texture, level, x, y, z));
  return keys;
}

StreamResult stream_once(v1::BrickService::Stub& stub, const v1::BrickRequest& request,
                         const std::vector<std::pair<std::string, std::string>>& metadata) {
  grpc::ClientContext context;
  for (const auto& [name, value] : metadata) context.AddMetadata(name, value);
  auto stream = stub.StreamBricks(&context);
  StreamResult result;
  stream->Write(request);
  stream->WritesDone();
  v1::BrickBatch batch;
  while (stream->Read(&batch)) {
    result.bricks_per_message.push_back(batch.bricks_size());
    for (auto& b : *batch.mutable_bricks()) result.bricks.push_back(std::move(b));
    for (auto& e : *batch.mutable_errors()) result.errors.push_back(std::move(e));
    for (auto& e : *batch.mutable_request_errors()) result.request_errors.push_back(std::move(e));
  }
  result.status = stream->Finish();
  return result;
}

v1::BrickRequest want(const std::vector<v1::BrickKey>& keys, v1::Codec codec) {
  v1::BrickRequest request;
  for (const auto& key : keys) *request.add_want()->mutable_key() = key;
  request.add_accept_codecs(codec);
  return request;
}

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

namespace {

// One unary call with an empty request message (which encodes to no bytes, but the buffer
// must exist) to `method`, without credentials; the response's bytes go to `response_bytes`.
grpc::Status call_with_empty_request(const SoltexdProcess& server, const std::string& method,
                                     std::string& response_bytes) {
  auto channel = grpc::CreateChannel(server.grpc_address(), grpc::InsecureChannelCredentials());
  grpc::GenericStub stub(channel);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
  grpc::Slice empty("");
  grpc::ByteBuffer request(&empty, 1), response;
  std::promise<grpc::Status> done;
  stub.UnaryCall(&context, method, grpc::StubOptions(), &request, &response,
                 [&](grpc::Status s) { done.set_value(s); });
  const grpc::Status status = done.get_future().get();
  std::vector<grpc::Slice> slices;
  if (status.ok()) (void)response.Dump(&slices);
  for (const auto& s : slices) {
    response_bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
  }
  return status;
}

}  // namespace

int health_status(const SoltexdProcess& server) {
  std::string bytes;
  const grpc::Status status =
      call_with_empty_request(server, "/grpc.health.v1.Health/Check", bytes);
  if (!status.ok()) return -status.error_code();
  // HealthCheckResponse{status = 1}: field 1, varint.
  return bytes.size() == 2 && bytes[0] == 0x08 ? bytes[1] : -100;
}

grpc::StatusCode reflection_status(const SoltexdProcess& server) {
  std::string bytes;
  return call_with_empty_request(
             server, "/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo", bytes)
      .error_code();
}

std::string metrics(const SoltexdProcess& server) {
  return http_get(server.metrics_port(), "/metrics");
}

}  // namespace soltex::testing
