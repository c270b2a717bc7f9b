#include "soltex/scene/texture_volume.h"

#include <algorithm>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

namespace soltex {

BoundingBox texture_space_bounds(const SceneObject& object) {
  if (!object.mesh) return {};
  if (object.material.space == TextureSpace::object) return object.mesh->bounds;
  const glm::dmat4 to_world = object.transform.matrix();
  BoundingBox box;
  for (const glm::vec3& p : object.mesh->positions) {
    box.extend(glm::vec3(to_world * glm::dvec4(glm::dvec3(p), 1.0)));
  }
  return box;
}

Volume padded_cube(const BoundingBox& bounds, int finest_level_log2) {
  Volume volume;
  volume.finest_level_log2 = finest_level_log2;
  if (bounds.empty()) return volume;
  const glm::dvec3 lo(bounds.min), hi(bounds.max);
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const glm::dvec3 size = hi - lo;
  // A point-sized object still needs a box with max > min.
  const double side = std::max(std::max({size.x, size.y, size.z}) * (1.0 + 2.0 / 32.0), 1e-3);
  volume.min = centre - 0.5 * side;
  volume.max = centre + 0.5 * side;
  return volume;
}

Volume texture_volume(const SceneObject& object, int client_finest_level_log2) {
  const VolumeRequest& request = object.material.volume;
  const int level = request.finest_level_log2.value_or(client_finest_level_log2);
  Volume volume = padded_cube(texture_space_bounds(object), level);
  if (request.box) {
    volume.min = request.box->min;
    volume.max = request.box->max;
  }
  return validated(volume);
}

}  // namespace soltex
