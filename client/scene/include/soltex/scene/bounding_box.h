#pragma once

#include <glm/vec3.hpp>
#include <limits>
#include <span>

namespace soltex {

// An axis-aligned box. A default-constructed box is empty (min > max), so extending it by
// the first point makes it that point.
struct BoundingBox {
  glm::vec3 min{std::numeric_limits<float>::infinity()};
  glm::vec3 max{-std::numeric_limits<float>::infinity()};

  bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
  glm::vec3 centre() const { return 0.5f * (min + max); }
  glm::vec3 size() const { return max - min; }

  void extend(const glm::vec3& point) {
    for (int axis = 0; axis < 3; ++axis) {
      if (point[axis] < min[axis]) min[axis] = point[axis];
      if (point[axis] > max[axis]) max[axis] = point[axis];
    }
  }
};

inline BoundingBox bounds_of(std::span<const glm::vec3> points) {
  BoundingBox box;
  for (const glm::vec3& point : points) box.extend(point);
  return box;
}

}  // namespace soltex
