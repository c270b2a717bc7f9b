#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

// Clipping a triangle in homogeneous clip space, before the perspective divide, so that a
// vertex behind the camera (w <= 0) never reaches the divide.
//
// A polygon vertex carries its clip-space position and its barycentric weights with respect
// to the original triangle: every attribute is affine in object space, and so is the clip
// position, so the weights give each attribute at a new vertex exactly, in whatever precision
// the caller keeps it (texture positions in double).
//
// Watertightness: a new vertex on an edge is computed from the edge's inside end towards its
// outside end, never the other way round, so two triangles that share the edge (and list it in
// opposite directions) get the bit-identical point.
namespace soltex::raster_internal {

struct ClipVertex {
  glm::vec4 clip;
  glm::vec3 weights;  // of the original triangle's vertices 0, 1, 2
};

// A triangle clipped by up to kMaxPlanes planes has at most 3 + kMaxPlanes vertices (each
// plane cuts a convex polygon once). Rounding can make a sliver polygon slightly non-convex;
// one that would outgrow the capacity is dropped rather than overrun it.
struct ClipPolygon {
  static constexpr int kMaxPlanes = 6;
  static constexpr int kCapacity = 3 + kMaxPlanes;

  std::array<ClipVertex, kCapacity> vertices;
  int size = 0;
};

// The planes a triangle is clipped against, as bits. Each keeps dot(plane, clip) >= 0.
enum ClipPlaneBit : uint32_t {
  kClipNear = 1u << 0,         // z >= -w
  kClipPositiveW = 1u << 1,    // w >= kMinClipW, for projections whose near plane does not
                               // already keep w > 0 (an inverted or degenerate matrix)
  kClipGuardLeft = 1u << 2,    // x >= -guard * w
  kClipGuardRight = 1u << 3,   // x <= guard * w
  kClipGuardBottom = 1u << 4,  // y >= -guard * w
  kClipGuardTop = 1u << 5,     // y <= guard * w
};

// Below the nearest near plane a scene may set (1e-6): an ordinary projection's near plane
// keeps w above this already, so the guard cuts only what a degenerate matrix would put at or
// behind the eye (at 1e-5 it cut away objects between a near plane of 1e-6 and 1e-5).
inline constexpr float kMinClipW = 5e-7f;

// What plane `index` of ClipPlanes subtracts from dot(plane, clip): kClipPositiveW keeps
// w >= kMinClipW, not w >= 0; every other plane keeps dot >= 0.
inline constexpr float clip_plane_offset(std::size_t index) {
  return (1u << index) == kClipPositiveW ? kMinClipW : 0.0f;
}

// The planes, in clip space, for a guard band of guard_x, guard_y (>= 1) times the viewport.
struct ClipPlanes {
  std::array<glm::vec4, ClipPolygon::kMaxPlanes> planes;

  ClipPlanes(float guard_x, float guard_y);

  // The bits of the planes the clip-space point is outside of.
  uint32_t outside(const glm::vec4& clip) const;
};

// Clips the triangle (a, b, c) against the planes in `mask`; the result is convex, in the
// triangle's winding, and empty when nothing is left.
ClipPolygon clip_triangle(const ClipPlanes& planes, uint32_t mask, const glm::vec4& a,
                          const glm::vec4& b, const glm::vec4& c);

}  // namespace soltex::raster_internal
