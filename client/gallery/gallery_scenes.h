#pragma once

#include <string>
#include <vector>

#include "soltex/common/texture_spec.h"

namespace soltex::gallery {

struct NamedTexture {
  std::string name;
  std::string description;
  TextureSpec spec;
};

// Every texture of the lecture slides with the slides' parameters, and the ones beyond them.
std::vector<NamedTexture> gallery_textures();

}  // namespace soltex::gallery
