#include "brick_service.h"

#include <spdlog/spdlog.h>

#include "texture_registration.h"

namespace soltex::server {
namespace {

// A stream refused before it starts (no token, too many streams): finishes at once.
class RefusedStream final : public grpc::ServerBidiReactor<v1::BrickRequest, v1::BrickBatch> {
 public:
  explicit RefusedStream(const grpc::Status& status) { Finish(status); }
  void OnDone() override { delete this; }
};

}  // namespace

BrickServiceImpl::BrickServiceImpl(BrickStream::Context context, ClientAccess& access,
                                   v1::ServerInfo info)
    : context_(context), access_(access), info_(std::move(info)) {}

grpc::Status BrickServiceImpl::admit(const grpc::CallbackServerContext& context) {
  grpc::Status status = access_.authenticate(context);
  if (!status.ok()) {
    context_.metrics.count_error(static_cast<int>(status.error_code()));
    spdlog::warn("call from {} refused: {}", context.peer(), status.error_message());
  }
  return status;
}

grpc::ServerUnaryReactor* BrickServiceImpl::GetServerInfo(grpc::CallbackServerContext* context,
                                                          const v1::GetServerInfoRequest*,
                                                          v1::ServerInfo* response) {
  auto* reactor = context->DefaultReactor();
  const grpc::Status admitted = admit(*context);
  if (admitted.ok()) *response = info_;
  reactor->Finish(admitted);
  return reactor;
}

grpc::ServerUnaryReactor* BrickServiceImpl::RegisterTexture(
    grpc::CallbackServerContext* context, const v1::RegisterTextureRequest* request,
    v1::TextureHandle* response) {
  auto* reactor = context->DefaultReactor();
  if (grpc::Status admitted = admit(*context); !admitted.ok()) {
    reactor->Finish(admitted);
    return reactor;
  }
  context_.metrics.register_requests.fetch_add(1, std::memory_order_relaxed);
  try {
    *response = texture_handle(*register_texture(context_.registry, *request));
  } catch (const RegistrationError& e) {
    context_.metrics.count_error(static_cast<int>(e.code()));
    spdlog::debug("RegisterTexture from {} refused: {}", context->peer(), e.what());
    reactor->Finish(grpc::Status(e.code(), e.what()));
    return reactor;
  }
  reactor->Finish(grpc::Status::OK);
  return reactor;
}

grpc::ServerBidiReactor<v1::BrickRequest, v1::BrickBatch>* BrickServiceImpl::StreamBricks(
    grpc::CallbackServerContext* context) {
  if (grpc::Status admitted = admit(*context); !admitted.ok()) {
    return new RefusedStream(admitted);
  }
  grpc::Status refusal;
  const std::string client = access_.client_of(*context);
  std::unique_ptr<StreamLease> lease = access_.open_stream(client, refusal);
  if (!lease) {
    context_.metrics.count_error(static_cast<int>(refusal.error_code()));
    spdlog::warn("stream from {} refused: {}", context->peer(), refusal.error_message());
    return new RefusedStream(refusal);
  }
  const uint64_t id = next_stream_id_.fetch_add(1, std::memory_order_relaxed);
  auto stream = std::make_shared<BrickStream>(context_, id, context->peer(), std::move(lease));
  {
    std::lock_guard lock(streams_mutex_);
    // Forget streams that have ended, so the map stays the size of the open ones.
    std::erase_if(streams_, [](const auto& entry) { return entry.second.expired(); });
    streams_.emplace(id, stream);
  }
  return stream->start();
}

void BrickServiceImpl::shut_down_streams() {
  std::vector<std::shared_ptr<BrickStream>> open;
  {
    std::lock_guard lock(streams_mutex_);
    for (const auto& [id, weak] : streams_) {
      if (auto stream = weak.lock()) open.push_back(std::move(stream));
    }
  }
  for (const auto& stream : open) stream->shut_down();
}

}  // namespace soltex::server
