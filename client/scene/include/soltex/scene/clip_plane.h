#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace soltex {

// A world-space plane dot(normal, x) = offset that cuts objects open: the half-space the
// normal points into is cut away, so a solid texture shows what is inside the object.
struct ClipPlane {
  glm::dvec3 normal{0.0, 0.0, 1.0};  // unit length
  double offset = 0.0;

  double signed_distance(const glm::dvec3& point) const { return glm::dot(normal, point) - offset; }
  bool keeps(const glm::dvec3& point) const { return signed_distance(point) <= 0.0; }
};

}  // namespace soltex
