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
// each call admitted by ClientAccess (token, per-client stream bound) first.
class BrickServiceImpl final : public v1::BrickService::CallbackService {
 public:
  BrickServiceImpl(BrickStream::Context context, ClientAccess& access, v1::ServerInfo info);

  grpc::ServerUnaryReactor* GetServerInfo(grpc::CallbackServerContext* context,
                                          const v1::GetServerInfoRequest* request,
                                          v1::ServerInfo* response) override;
  grpc::ServerUnaryReactor* RegisterTexture(grpc::CallbackServerContext* context,
                                            const v1::RegisterTextureRequest* request,
                                            v1::TextureHandle* response) override;
  grpc::ServerBidiReactor<v1::BrickRequest, v1::BrickBatch>* StreamBricks(
      grpc::CallbackServerContext* context) override;

  // Finishes every open stream (UNAVAILABLE) once its current write is done.
  void shut_down_streams();

 private:
  // OK with `client` set to the caller's identity, or the status the call is refused with
  // (counted, and logged at most once a second per client).
  grpc::Status admit(const grpc::CallbackServerContext& context, std::string& client);

  BrickStream::Context context_;
  ClientAccess& access_;
  const v1::ServerInfo info_;
  std::atomic<uint64_t> next_stream_id_{1};
  std::mutex streams_mutex_;
  std::unordered_map<uint64_t, std::weak_ptr<BrickStream>> streams_;
};

}  // namespace soltex::server
