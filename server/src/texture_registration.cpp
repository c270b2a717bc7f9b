#include "texture_registration.h"

#include <cstdint>
#include <optional>
#include <string>

#include "soltex/common/brick_layout.h"
#include "soltex/common/spec_error.h"
#include "soltex/common/texture_id.h"
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
    // Checked as sent, before any conversion, so the message quotes the client's value.
    const uint32_t k = request.supersample();
    if (k > static_cast<uint32_t>(kMaxSupersample)) {
      throw RegistrationError(grpc::StatusCode::INVALID_ARGUMENT,
                              "supersample = " + std::to_string(k) + ": must be in [1, " +
                                  std::to_string(kMaxSupersample) + "] (0: the default, 2)");
    }
    mip.supersample = k == 0 ? 2 : static_cast<int>(k);
  }
  return mip;
}

// 0 means the default, 16; anything else must be a size the layout supports, checked as sent.
int brick_size_from(uint32_t size) {
  if (size == 0) return kMaxBrickSize;
  if (size != static_cast<uint32_t>(kMinBrickSize) &&
      size != static_cast<uint32_t>(kMaxBrickSize)) {
    throw RegistrationError(grpc::StatusCode::INVALID_ARGUMENT,
                            "brick_size = " + std::to_string(size) + ": must be " +
                                std::to_string(kMinBrickSize) + " or " +
                                std::to_string(kMaxBrickSize) + " (0: the default, 16)");
  }
  return static_cast<int>(size);
}

}  // namespace

TexturePin register_texture(TextureRegistry& registry, const v1::RegisterTextureRequest& request,
                            const std::string& client, const TextureRegistry::Check& check) {
  try {
    const TextureSpec spec = from_proto(request.spec());
    const Volume volume = from_proto(request.volume());
    const int brick_size = brick_size_from(request.brick_size());
    return registry.register_texture(spec, volume, brick_size, mip_from(request), client, check);
  } catch (const SpecError& e) {
    throw RegistrationError(grpc::StatusCode::INVALID_ARGUMENT, e.what());
  } catch (const RegistryFull& e) {
    throw RegistrationError(grpc::StatusCode::RESOURCE_EXHAUSTED, e.what());
  }
}

uint64_t registration_id(const v1::RegisterTextureRequest& request) {
  try {
    return texture_id(from_proto(request.spec()), from_proto(request.volume()),
                      brick_size_from(request.brick_size()), mip_from(request));
  } catch (const SpecError& e) {
    throw RegistrationError(grpc::StatusCode::INVALID_ARGUMENT, e.what());
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
