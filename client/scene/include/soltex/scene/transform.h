#pragma once

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace soltex {

// Object to world: scale, then rotate about x, then y, then z, then translate.
struct Transform {
  glm::dvec3 translate{0.0};
  glm::dvec3 rotate_degrees{0.0};
  glm::dvec3 scale{1.0};  // positive: a mirror would turn the triangles inside out

  // translate * Rz * Ry * Rx * scale.
  glm::dmat4 matrix() const;
  // The inverse transpose of the upper 3x3, which keeps normals perpendicular to surfaces
  // under non-uniform scale (normalise after multiplying).
  glm::dmat3 normal_matrix() const;
};

// Bounds a scene file's transform must keep.
struct TransformLimits {
  // Positions are doubles until they are made relative to the camera: at 1e9 a double still
  // resolves 1.2e-7, a float's resolution on a unit-sized object, so an object there draws as
  // it does at the origin. Further out it would visibly quantize.
  static constexpr double kMaxTranslate = 1e9;
  static constexpr double kMaxRotateDegrees = 360.0;
  static constexpr double kMinScale = 1e-6;
  static constexpr double kMaxScale = 1e6;
};

}  // namespace soltex
