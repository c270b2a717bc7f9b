#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>

namespace soltex {

// Names one brick: (texture id, level, brick coordinate at that level). Level 0 is finest.
struct BrickKey {
  uint64_t texture = 0;
  int32_t level = 0;
  glm::ivec3 brick{0};

  bool operator==(const BrickKey& other) const {
    return texture == other.texture && level == other.level && brick == other.brick;
  }
};

struct BrickKeyHash {
  std::size_t operator()(const BrickKey& key) const noexcept {
    // Coordinates are small; pack them and mix with the texture id (splitmix64 finalizer).
    uint64_t h = key.texture ^ (static_cast<uint64_t>(static_cast<uint32_t>(key.level)) << 58);
    h ^= (static_cast<uint64_t>(static_cast<uint32_t>(key.brick.x)) & 0xFFFFF) |
         ((static_cast<uint64_t>(static_cast<uint32_t>(key.brick.y)) & 0xFFFFF) << 20) |
         ((static_cast<uint64_t>(static_cast<uint32_t>(key.brick.z)) & 0xFFFFF) << 40);
    h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ULL;
    h = (h ^ (h >> 27)) * 0x94D049BB133111EBULL;
    return static_cast<std::size_t>(h ^ (h >> 31));
  }
};

}  // namespace soltex
