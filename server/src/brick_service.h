#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "brick_stream.h"
#include "client_access.h"
#include "soltex/v1/brick_service.grpc.pb.h"

namespace soltex::server {

// The gRPC service (callback API): server info, texture registration and brick streams,
// each call admitted by ClientAccess (token, per-client stream bound) first. Every method is
// raw, its messages bytes: StreamBricks so that bricks go out as their cached serialized
// entries (EncodedBrick) rather than through a protobuf message; the unary ones so that a
// request that does not parse is answered INVALID_ARGUMENT saying so (gRPC's callback API
// would answer UNIMPLEMENTED with no message, as if the method did not exist).
using BrickServiceBase = v1::BrickService::WithRawCallbackMethod_GetServerInfo<
    v1::BrickService::WithRawCallbackMethod_RegisterTexture<
        v1::BrickService::WithRawCallbackMethod_StreamBricks<v1::BrickService::Service>>>;

class BrickServiceImpl final : public BrickServiceBase {
 public:
  BrickServiceImpl(BrickStream::Context context, ClientAccess& access, v1::ServerInfo info);

  grpc::ServerUnaryReactor* GetServerInfo(grpc::CallbackServerContext* context,
                                          const grpc::ByteBuffer* request,
                                          grpc::ByteBuffer* response) override;
  grpc::ServerUnaryReactor* RegisterTexture(grpc::CallbackServerContext* context,
                                            const grpc::ByteBuffer* request,
                                            grpc::ByteBuffer* response) override;
  BrickStream::ServerReactor* StreamBricks(grpc::CallbackServerContext* context) override;

  // Stops reading every open stream; each finishes once it has sent what it was asked for.
  void drain_streams();
  // Finishes every open stream (UNAVAILABLE) once its current write is done.
  void shut_down_streams();

 private:
  std::vector<std::shared_ptr<BrickStream>> open_streams();

  // OK with `client` set to the caller's identity, or the status the call is refused with
  // (counted, and logged at most once a second per client).
  grpc::Status admit(const grpc::CallbackServerContext& context, std::string& client);

  BrickStream::Context context_;
  ClientAccess& access_;
  const v1::ServerInfo info_;
  std::atomic<uint64_t> next_stream_id_{1};
  std::mutex streams_mutex_;
  std::unordered_map<uint64_t, std::weak_ptr<BrickStream>> streams_;
  bool draining_ = false;  // drain_streams() was called; under streams_mutex_
};

}  // namespace soltex::server
