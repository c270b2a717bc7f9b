#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <unordered_map>

#include "soltex/common/brick_evaluator.h"
#include "soltex/common/brick_layout.h"
#include "soltex/common/texture_evaluator.h"

namespace soltex::server {

// A texture the server can evaluate bricks of. Immutable once registered, shared by every
// stream and worker that uses it.
struct RegisteredTexture {
  uint64_t id;
  TextureEvaluator evaluator;
  BrickLayout layout;
  MipSettings mip;
};

using TexturePtr = std::shared_ptr<const RegisteredTexture>;

class RegistryFull : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Content-addressed, bounded: registering the same texture twice returns the first entry.
class TextureRegistry {
 public:
  explicit TextureRegistry(std::size_t max_textures) : max_textures_(max_textures) {}

  // Validates (throws SpecError naming the field) and registers; throws RegistryFull when the
  // registry already holds max_textures other textures.
  TexturePtr register_texture(const TextureSpec& spec, const Volume& volume, int brick_size,
                              const MipSettings& mip);

  TexturePtr find(uint64_t id) const;
  std::size_t size() const;
  std::size_t max_textures() const { return max_textures_; }

 private:
  const std::size_t max_textures_;
  mutable std::mutex mutex_;
  std::unordered_map<uint64_t, TexturePtr> textures_;
};

}  // namespace soltex::server
