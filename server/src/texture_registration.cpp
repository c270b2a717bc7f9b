#include "texture_registration.h"

#include <algorithm>
#include <optional>

#include "soltex/common/spec_error.h"
#include "soltex/spec_proto/brick_proto.h"
#include "soltex/spec_proto/spec_from_proto.h"

namespace soltex::server {
namespace {

MipSettings mip_from(const v1::RegisterTextureRequest& request) {
  const std::optional<MipMode> mode = mip_mode_from_proto(request.mip_mode());
  if (!mode) {
    throw RegistrationError(
        grpc::StatusCode::INVALID_ARGUMENT,
        "mip_mode = " + std::to_string(request.mip_mode()) +
            ": must be MIP_MODE_BAND_LIMITED, MIP_MODE_POINT or MIP_MODE_SUPERSAMPLED");
  }
  MipSettings mip;
  mip.mode = *mode;
  if (mip.mode == MipMode::supersampled) {
    // Out-of-range values are clamped into the validator's view so it can name the bound.
    mip.supersample =
        request.supersample() == 0 ? 2 : static_cast<int>(std::min(request.supersample(), 1000u));
  }
  return mip;
}

}  // namespace

TexturePtr register_texture(TextureRegistry& registry, const v1::RegisterTextureRequest& request) {
  try {
    const TextureSpec spec = from_proto(request.spec());
    const Volume volume = from_proto(request.volume());
    const int brick_size =
        request.brick_size() == 0 ? 16 : static_cast<int>(std::min(request.brick_size(), 1000u));
    return registry.register_texture(spec, volume, brick_size, mip_from(request));
  } catch (const SpecError& e) {
    throw RegistrationError(grpc::StatusCode::INVALID_ARGUMENT, e.what());
  } catch (const RegistryFull& e) {
    throw RegistrationError(grpc::StatusCode::RESOURCE_EXHAUSTED, e.what());
  }
}

v1::TextureHandle texture_handle(const RegisteredTexture& texture) {
  v1::TextureHandle handle;
  handle.set_id(texture.id);
  handle.set_levels(static_cast<uint32_t>(texture.layout.level_count()));
  handle.set_brick_size(static_cast<uint32_t>(texture.layout.brick_size()));
  handle.set_finest_level_log2(static_cast<uint32_t>(texture.layout.finest_level_log2()));
  const ChannelSet& channels = texture.evaluator.spec().channels;
  if (channels.colour) handle.add_channels(v1::CHANNEL_COLOUR);
  if (channels.opacity) handle.add_channels(v1::CHANNEL_OPACITY);
  if (channels.specular) handle.add_channels(v1::CHANNEL_SPECULAR);
  return handle;
}

}  // namespace soltex::server
