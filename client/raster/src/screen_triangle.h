#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "soltex/raster/gbuffer.h"

// A triangle ready to rasterize: what triangle setup hands to the tile rasterizer.
namespace soltex::raster_internal {

// Screen positions are fixed point with kSubpixelBits fractional bits, so edge functions are
// exact integers: a pixel centre is on an edge or not, the same for both triangles that share
// it, and the top-left rule can settle the tie.
inline constexpr int kSubpixelBits = 8;
inline constexpr int64_t kSubpixelScale = int64_t{1} << kSubpixelBits;

// A screen coordinate in pixels as a fixed-point value, rounded to nearest (ties to even, as
// std::nearbyint in the default mode), still a double. The guard band bounds the coordinate;
// the clamp (min and max, which vector lanes keep) only keeps a rounding overshoot defined.
// Inline and without a library call: the generic x86-64 target has no rounding instruction,
// and adding 1.5 * 2^52 leaves the sum no fraction bits, so the addition rounds.
inline double subpixel_position(double pixels) {
  constexpr double kLimit = double{1 << 24};
  constexpr double kShift = 6755399441055744.0;  // 1.5 * 2^52
  const double scaled = pixels * static_cast<double>(kSubpixelScale);
  const double clamped = std::min(std::max(scaled, -kLimit), kLimit);
  return (clamped + kShift) - kShift;
}

// An affine function of the pixel position (px, py), relative to the triangle's first
// vertex so that float keeps its precision: value(px, py) = at_vertex0 + per_x * (px - x0) +
// per_y * (py - y0).
struct AffineForm {
  float at_vertex0 = 0.0f;
  float per_x = 0.0f;
  float per_y = 0.0f;
};

// The clip planes of `mask` whose form (forms[j] for plane j) is negative at (dx, dy) from
// the triangle's first vertex: those that discard the fragment there.
inline uint32_t failed_planes(uint32_t mask, const AffineForm* forms, float dx, float dy) {
  uint32_t failed = 0;
  for (; mask != 0; mask &= mask - 1) {
    const int j = std::countr_zero(mask);
    const AffineForm& form = forms[j];
    if (form.at_vertex0 + form.per_x * dx + form.per_y * dy < 0.0f) failed |= 1u << j;
  }
  return failed;
}

// Laid out for the tile pass: what drawing reads (positions, bounds, depth, clip mask) fills
// the first 64-byte line, so a triangle drawn into a tile and beaten there costs one line;
// resolving a winner reads the other two. No field has a default: TriangleSetup::emit() writes
// every one into the chunk's storage (ScreenTriangles), where a zeroed triangle, or one built
// elsewhere and copied, cost a fine mesh's set-up a second pass over 192 bytes a triangle.
struct alignas(64) ScreenTriangle {
  // Fixed-point positions, y down, ordered so that double_area > 0 (clockwise on screen).
  std::array<int32_t, 3> x;
  std::array<int32_t, 3> y;
  int64_t double_area;
  // Pixels whose centres can be inside, clamped to the viewport (inclusive).
  int32_t min_px, min_py, max_px, max_py;
  AffineForm depth;  // window depth, affine on screen
  // User clip planes this triangle straddles (bit j: plane j needs a per-fragment test), and
  // where their forms (signed distance / w, affine on screen; one per clip plane of the frame)
  // start in the chunk's clip-form array.
  uint32_t clip_mask;

  uint32_t first_clip_form;
  uint32_t object;  // index of the object in the render call
  bool back_face;
  // Per vertex (in the order above): 1/w, and attributes to interpolate perspective-correctly.
  std::array<float, 3> inv_w;
  std::array<glm::vec3, 3> texture_offset;  // texture position - texture_origin
  std::array<glm::vec3, 3> normal;          // world space
  glm::dvec3 texture_origin;

  float x0_pixels() const { return static_cast<float>(x[0]) / static_cast<float>(kSubpixelScale); }
  float y0_pixels() const { return static_cast<float>(y[0]) / static_cast<float>(kSubpixelScale); }
};

// A chunk's screen triangles: appended uninitialised (UninitializedAllocator), then written
// field by field in place.
using ScreenTriangles = std::vector<ScreenTriangle, UninitializedAllocator<ScreenTriangle>>;

// Twice the signed area of (a, b, p), in fixed-point units squared: positive when p is to the
// inside of the edge a -> b for a triangle with double_area > 0. Exact in int64: coordinates
// stay below 2^24 in magnitude (see the guard band), so products stay below 2^50.
inline int64_t edge_function(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t px,
                             int64_t py) {
  return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

// The top-left rule for a clockwise-on-screen (y down) triangle: a top edge is horizontal and
// runs to the right; a left edge runs up. A pixel centre exactly on an edge is inside only
// when the edge is top or left; the triangle across the edge runs it the other way round.
inline bool is_top_left(int64_t ax, int64_t ay, int64_t bx, int64_t by) {
  return (ay == by && bx > ax) || by < ay;
}

}  // namespace soltex::raster_internal
