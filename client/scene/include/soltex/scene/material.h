#pragma once

#include <glm/vec3.hpp>
#include <optional>

#include "soltex/common/texture_spec.h"

namespace soltex {

// Where an object's points are looked up in its texture. In object space the texture is
// fixed to the object (it moves and turns with it); in world space the object moves through
// the texture.
enum class TextureSpace { object, world };

// The cache cube a material's texture is sampled through. Each part may be left to the
// client: the box defaults to the object's texture-space bounds padded (texture_volume.h),
// the finest level to what the client's screen resolution needs.
struct VolumeRequest {
  struct Box {
    glm::dvec3 min{0.0};
    glm::dvec3 max{1.0};
  };
  std::optional<Box> box;
  std::optional<int> finest_level_log2;
};

struct Material {
  TextureSpec texture;  // validated
  TextureSpace space = TextureSpace::object;
  VolumeRequest volume;
  float specular = 0.2f;    // Phong specular coefficient, [0, 1]
  float shininess = 32.0f;  // Phong exponent, [1, 10000]
  bool unlit = false;       // show the texture colour as it is, without lighting
};

}  // namespace soltex
