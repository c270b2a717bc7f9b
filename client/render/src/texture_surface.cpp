#include "texture_surface.h"

#include <glm/matrix.hpp>
#include <variant>

namespace soltex::render {

bool has_planar_edges(const TextureSpec& spec) {
  if (spec.graph) return false;  // a graph's edges may lie in any direction
  return std::holds_alternative<StripesParams>(spec.pattern) ||
         std::holds_alternative<CheckerParams>(spec.pattern);
}

TextureSurface::TextureSurface(const PreparedObject& object) {
  // Normals go through the inverse transpose of the linear map from world to texture space.
  const glm::dmat3 texture_from_world = glm::dmat3(object.raster.texture_from_object) *
                                        glm::inverse(glm::dmat3(object.world_from_object));
  const glm::dmat3 normal_map = glm::transpose(glm::inverse(texture_from_world));
  bool finite = true;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) finite = finite && std::isfinite(normal_map[c][r]);
  // A singular transform has no normal map; keep the world normal rather than NaNs.
  if (finite) normal_from_world_ = normal_map;
}

}  // namespace soltex::render
