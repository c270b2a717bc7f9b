#pragma once

#include <string>
#include <vector>

#include "soltex/common/texture_spec.h"

namespace soltex::view {

struct NamedTexture {
  std::string name;
  TextureSpec spec;  // validated
};

// The lecture's textures, in the order the viewer's number keys pick them (1 is the first),
// sized for objects about two units across, as the built-in shapes are.
const std::vector<NamedTexture>& lecture_textures();

}  // namespace soltex::view
