#pragma once

#include <cmath>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "soltex/common/texture_evaluator.h"
#include "soltex/common/texture_spec.h"
#include "soltex/render/prepared_scene.h"

// Where on a surface a pixel looks its texture up, and over what box.
//
// An object is carved out of its solid texture, so a face that lies on one of the pattern's
// discontinuities (a box face on a checker boundary, a clip plane's cap on a stripe edge) shows
// the material just inside the object. Both ways of reading the texture look it up at a point
// moved inward along the surface's normal (in texture space), by an amount that clears the
// filter that reads it:
//  - evaluated per pixel, the box is the pixel's footprint in the surface's plane, which has
//    no extent along the normal, so a step of a small fraction of the footprint is enough
//    (kEvaluatedInset) and hardly moves anything else;
//  - looked up in a brick of level l, trilinear interpolation reads samples up to h_l away,
//    each averaged over a box of width h_l, so the step must be 1.5 h_l (kCachedInset) for
//    every sample read to lie inside. Only textures whose edges are planes need it (stripes,
//    checkers), and only on a surface that faces one of the texture's axes, as their planes
//    do: a step of d elsewhere moves the edges of the planes across axis a along the surface
//    by d |n_a| / sqrt(1 - n_a^2), several pixels on a face at a slant and more near
//    grazing, so there the lookup stays where it is (axis_face_inset()). Nor can a face or
//    cap lie all over a ring's cylinder.
namespace soltex::render {

inline constexpr double kEvaluatedInset = 1.0 / 16.0;  // of the pixel's footprint
inline constexpr double kCachedInset = 1.5;            // of the level's spacing

// Whether a texture's field jumps across planes (stripes, checkers).
bool has_planar_edges(const TextureSpec& spec);

// One object's map from world-space normals to unit texture-space normals.
class TextureSurface {
 public:
  TextureSurface() = default;
  explicit TextureSurface(const PreparedObject& object);

  // The unit texture-space normal of a world-space normal (zero stays zero).
  glm::dvec3 normal(const glm::vec3& world_normal) const {
    const glm::dvec3 n = normal_from_world_ * glm::dvec3(world_normal);
    const double length = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    return length > 0.0 ? n / length : glm::dvec3(0.0);
  }

  const glm::dmat3& normal_from_world() const { return normal_from_world_; }

 private:
  glm::dmat3 normal_from_world_{1.0};
};

// The box over which a pixel of texture-space footprint `footprint` (a diameter in the plane
// with unit normal n), looked up kEvaluatedInset * footprint inside, averages hard edges: on
// each axis the extent of that disc, footprint * sqrt(1 - n_axis^2), plus the extent of the
// depth from the surface down to twice the inset, so that a pattern finer than the inset
// along the normal averages to its mean instead of aliasing (and a face on an edge still sees
// only the inside). The band limit of noise stays the footprint itself.
inline SampleFootprint surface_footprint(double footprint, const glm::dvec3& n) {
  if (!(footprint > 0.0)) return SampleFootprint::isotropic(footprint);
  const double depth = 2.0 * kEvaluatedInset * footprint;
  const auto extent = [&](double c) {
    return footprint * std::sqrt(std::fmax(0.0, 1.0 - c * c)) + depth * std::fabs(c);
  };
  return {footprint, {extent(n.x), extent(n.y), extent(n.z)}};
}

// A surface whose unit texture-space normal is within this of an axis (|n_a| >= 1 - it,
// 0.8 degrees) faces that axis: a box's face, or a cap, on a pattern plane. A curved surface
// faces an axis only within 0.8 degrees of where it touches a plane across that axis.
inline constexpr double kAxisFaceTolerance = 1e-4;

// p moved inward by `distance` along the texture axis the surface faces, if it faces one;
// otherwise unmoved.
inline glm::dvec3 axis_face_inset(const glm::dvec3& p, const glm::dvec3& n, double distance) {
  if (!std::isfinite(distance)) return p;
  glm::dvec3 moved = p;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::fabs(n[axis]) >= 1.0 - kAxisFaceTolerance) {
      moved[axis] -= std::copysign(distance, n[axis]);
    }
  }
  return moved;
}

// p moved inward (against the outward unit normal n) by `distance`.
inline glm::dvec3 inset(const glm::dvec3& p, const glm::dvec3& n, double distance) {
  return std::isfinite(distance) ? p - n * distance : p;
}

}  // namespace soltex::render
