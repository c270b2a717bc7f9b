#include "soltex/scene/texture_volume.h"

#include <algorithm>
#include <glm/common.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <glm/vector_relational.hpp>
#include <limits>
#include <optional>

namespace soltex {
namespace {

// Bounds in double: a world-space object 1e9 from the origin has vertices a float cannot
// tell apart, and its volume would shrink to nothing.
struct WideBounds {
  glm::dvec3 min{std::numeric_limits<double>::infinity()};
  glm::dvec3 max{-std::numeric_limits<double>::infinity()};
  bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
  void extend(const glm::dvec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
};

WideBounds wide_texture_space_bounds(const SceneObject& object) {
  WideBounds box;
  if (!object.mesh) return box;
  if (object.material.space == TextureSpace::object) {
    if (!object.mesh->bounds.empty()) {
      box.extend(glm::dvec3(object.mesh->bounds.min));
      box.extend(glm::dvec3(object.mesh->bounds.max));
    }
    return box;
  }
  const glm::dmat4 to_world = object.transform.matrix();
  for (const glm::vec3& p : object.mesh->positions) {
    box.extend(glm::dvec3(to_world * glm::dvec4(glm::dvec3(p), 1.0)));
  }
  return box;
}

Volume padded_cube(const WideBounds& bounds, int finest_level_log2) {
  Volume volume;
  volume.finest_level_log2 = finest_level_log2;
  if (bounds.empty()) return volume;
  const glm::dvec3 centre = 0.5 * (bounds.min + bounds.max);
  const glm::dvec3 size = bounds.max - bounds.min;
  // A point-sized object still needs a box with max > min.
  const double side = std::max(std::max({size.x, size.y, size.z}) * (1.0 + 2.0 / 32.0), 1e-3);
  volume.min = centre - 0.5 * side;
  volume.max = centre + 0.5 * side;
  return volume;
}

}  // namespace

BoundingBox texture_space_bounds(const SceneObject& object) {
  const WideBounds wide = wide_texture_space_bounds(object);
  BoundingBox box;
  if (!wide.empty()) {
    box.extend(glm::vec3(wide.min));
    box.extend(glm::vec3(wide.max));
  }
  return box;
}

Volume padded_cube(const BoundingBox& bounds, int finest_level_log2) {
  WideBounds wide;
  if (!bounds.empty()) {
    wide.extend(glm::dvec3(bounds.min));
    wide.extend(glm::dvec3(bounds.max));
  }
  return padded_cube(wide, finest_level_log2);
}

bool explicit_volume_contains_object(const SceneObject& object) {
  const std::optional<VolumeRequest::Box>& box = object.material.volume.box;
  if (!box) return true;
  const WideBounds bounds = wide_texture_space_bounds(object);
  if (bounds.empty()) return true;
  const glm::dvec3 slack = 1e-6 * (box->max - box->min);
  return glm::all(glm::greaterThanEqual(bounds.min, box->min - slack)) &&
         glm::all(glm::lessThanEqual(bounds.max, box->max + slack));
}

Volume texture_volume(const SceneObject& object, int client_finest_level_log2) {
  const VolumeRequest& request = object.material.volume;
  const int level = request.finest_level_log2.value_or(client_finest_level_log2);
  Volume volume = padded_cube(wide_texture_space_bounds(object), level);
  if (request.box) {
    volume.min = request.box->min;
    volume.max = request.box->max;
  }
  return validated(volume);
}

}  // namespace soltex
