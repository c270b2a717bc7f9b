#include "brick_service.h"

#include <spdlog/spdlog.h>

#include "soltex/common/spec_error.h"
#include "soltex/common/texture_id.h"
#include "soltex/spec_proto/brick_proto.h"
#include "soltex/spec_proto/spec_from_proto.h"

namespace soltex::server {
namespace {

std::optional<MipSettings> mip_from(const v1::RegisterTextureRequest& request) {
  const std::optional<MipMode> mode = mip_mode_from_proto(request.mip_mode());
  if (!mode) return std::nullopt;
  MipSettings mip;
  mip.mode = *mode;
  if (mip.mode == MipMode::supersampled) {
    mip.supersample =
        request.supersample() == 0 ? 2 : static_cast<int>(std::min(request.supersample(), 1000u));
  }
  return mip;
}

}  // namespace

BrickServiceImpl::BrickServiceImpl(BrickStream::Context context, v1::ServerInfo info)
    : context_(context), info_(std::move(info)) {}

grpc::ServerUnaryReactor* BrickServiceImpl::GetServerInfo(grpc::CallbackServerContext* context,
                                                          const v1::GetServerInfoRequest*,
                                                          v1::ServerInfo* response) {
  *response = info_;
  auto* reactor = context->DefaultReactor();
  reactor->Finish(grpc::Status::OK);
  return reactor;
}

grpc::ServerUnaryReactor* BrickServiceImpl::RegisterTexture(
    grpc::CallbackServerContext* context, const v1::RegisterTextureRequest* request,
    v1::TextureHandle* response) {
  auto* reactor = context->DefaultReactor();
  context_.metrics.register_requests.fetch_add(1, std::memory_order_relaxed);
  const auto fail = [&](grpc::StatusCode code, const std::string& message) {
    context_.metrics.count_error(static_cast<int>(code));
    spdlog::debug("RegisterTexture from {} refused: {}", context->peer(), message);
    reactor->Finish(grpc::Status(code, message));
    return reactor;
  };
  try {
    const TextureSpec spec = from_proto(request->spec());
    const Volume volume = from_proto(request->volume());
    const int brick_size =
        request->brick_size() == 0 ? 16 : static_cast<int>(std::min(request->brick_size(), 1000u));
    const std::optional<MipSettings> mip = mip_from(*request);
    if (!mip) {
      return fail(grpc::StatusCode::INVALID_ARGUMENT,
                  "mip_mode = " + std::to_string(request->mip_mode()) +
                      ": must be MIP_MODE_BAND_LIMITED, MIP_MODE_POINT or MIP_MODE_SUPERSAMPLED");
    }
    const TexturePtr texture = context_.registry.register_texture(spec, volume, brick_size, *mip);
    response->set_id(texture->id);
    response->set_levels(static_cast<uint32_t>(texture->layout.level_count()));
    response->set_brick_size(static_cast<uint32_t>(texture->layout.brick_size()));
    response->set_finest_level_log2(static_cast<uint32_t>(volume.finest_level_log2));
    const ChannelSet& channels = texture->evaluator.spec().channels;
    if (channels.colour) response->add_channels(v1::CHANNEL_COLOUR);
    if (channels.opacity) response->add_channels(v1::CHANNEL_OPACITY);
    if (channels.specular) response->add_channels(v1::CHANNEL_SPECULAR);
  } catch (const SpecError& e) {
    return fail(grpc::StatusCode::INVALID_ARGUMENT, e.what());
  } catch (const RegistryFull& e) {
    return fail(grpc::StatusCode::RESOURCE_EXHAUSTED, e.what());
  }
  reactor->Finish(grpc::Status::OK);
  return reactor;
}

grpc::ServerBidiReactor<v1::BrickRequest, v1::BrickBatch>* BrickServiceImpl::StreamBricks(
    grpc::CallbackServerContext* context) {
  const uint64_t id = next_stream_id_.fetch_add(1, std::memory_order_relaxed);
  auto stream = std::make_shared<BrickStream>(context_, id, context->peer());
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
