#pragma once

#include <grpcpp/grpcpp.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "soltex/v1/brick_service.grpc.pb.h"
#include "soltexd_process.h"

// Plain gRPC calls to a soltexd under test, for the integration tests.
namespace soltex::testing {

std::unique_ptr<v1::BrickService::Stub> connect(const SoltexdProcess& server);
std::unique_ptr<v1::BrickService::Stub> connect(const std::string& address);

// A marble texture over [-1, 1]^3.
v1::RegisterTextureRequest marble_request(int finest_level_log2 = 6, int brick_size = 8);

// Registers (expecting success) and returns the handle.
v1::TextureHandle register_texture(v1::BrickService::Stub& stub,
                                   const v1::RegisterTextureRequest& request);

v1::BrickKey key_of(uint64_t texture, int level, int x, int y, int z);

// All bricks of `level`.
std::vector<v1::BrickKey> level_keys(uint64_t texture, int level, int bricks_per_axis);

struct StreamResult {
  std::vector<v1::Brick> bricks;
  std::vector<v1::BrickError> errors;
  std::vector<v1::RequestError> request_errors;
  std::vector<int> bricks_per_message;  // one entry per BrickBatch read
  grpc::Status status;
};

// Sends one request (then half-closes) and reads every batch until the server finishes.
// `metadata` is added to the call (e.g. an authorization header).
StreamResult stream_once(v1::BrickService::Stub& stub, const v1::BrickRequest& request,
                         const std::vector<std::pair<std::string, std::string>>& metadata = {});

v1::BrickRequest want(const std::vector<v1::BrickKey>& keys, v1::Codec codec = v1::CODEC_ZSTD);

// The same brick made here: evaluate, quantize.
std::vector<uint8_t> local_brick(const v1::RegisterTextureRequest& registration,
                                 const v1::BrickKey& key);

// The gRPC health service's answer without credentials: 1 SERVING, 2 NOT_SERVING, or minus
// the status code of a failed call.
int health_status(const SoltexdProcess& server);

// The status of one call to server reflection: UNIMPLEMENTED when it is not offered.
grpc::StatusCode reflection_status(const SoltexdProcess& server);

// GET /metrics of the server.
std::string metrics(const SoltexdProcess& server);

}  // namespace soltex::testing
