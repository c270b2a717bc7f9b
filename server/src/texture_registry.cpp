#include "texture_registry.h"

#include <string>

#include "soltex/common/spec_error.h"
#include "soltex/common/texture_id.h"

namespace soltex::server {

TexturePtr TextureRegistry::register_texture(const TextureSpec& spec, const Volume& volume,
                                             int brick_size, const MipSettings& mip) {
  if (mip.mode == MipMode::supersampled && (mip.supersample < 1 || mip.supersample > 4)) {
    throw SpecError("supersample", std::to_string(mip.supersample), "must be in [1, 4]");
  }
  // Validation and id computation happen outside the lock: they may throw and take time.
  auto texture = std::make_shared<const RegisteredTexture>(
      RegisteredTexture{texture_id(spec, volume, brick_size, mip), TextureEvaluator(spec),
                        BrickLayout(volume, brick_size), mip});
  std::lock_guard lock(mutex_);
  if (auto it = textures_.find(texture->id); it != textures_.end()) return it->second;
  if (textures_.size() >= max_textures_) {
    throw RegistryFull("texture registry is full: " + std::to_string(textures_.size()) +
                       " textures registered, the limit is " + std::to_string(max_textures_));
  }
  textures_.emplace(texture->id, texture);
  return texture;
}

TexturePtr TextureRegistry::find(uint64_t id) const {
  std::lock_guard lock(mutex_);
  auto it = textures_.find(id);
  return it == textures_.end() ? nullptr : it->second;
}

std::size_t TextureRegistry::size() const {
  std::lock_guard lock(mutex_);
  return textures_.size();
}

}  // namespace soltex::server
