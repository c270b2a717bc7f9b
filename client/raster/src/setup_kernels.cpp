// Runtime dispatch of set_up_lanes (setup_kernels.h). Highway compiles this file once per
// target (hwy/foreach_target.h re-includes it) and HWY_DYNAMIC_DISPATCH calls the widest one
// the CPU supports, once per block of triangles. The loops are plain per-lane arithmetic,
// selects rather than branches, that the compiler runs in vector lanes; each lane does what
// TriangleSetup::emit() does for an unclipped triangle whose corners carry the identity
// weights, with the same IEEE operations in the same order (no contraction:
// -ffp-contract=off), so every target gives emit()'s bits. The 64-bit edge function is
// computed in double, where it is exact: coordinates are below 2^24 in magnitude, so
// differences below 2^25, products below 2^50 and the area below 2^51.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "setup_kernels.cpp"
#include "setup_kernels.h"

#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <cstddef>
#include <cstdint>

#include "saturating_cast.h"
#include "screen_triangle.h"

HWY_BEFORE_NAMESPACE();
namespace soltex::raster_internal::HWY_NAMESPACE {

// Orientation, the screen triangle's corners and bounds, and what emit() decides.
void orient_lanes(SetupLanes& s, std::size_t n, int width, int height, bool keep_between_centres) {
  constexpr int32_t kHalf = static_cast<int32_t>(kSubpixelScale / 2);
  for (std::size_t l = 0; l < n; ++l) {
    const int32_t x0 = s.x[0][l], x1 = s.x[1][l], x2 = s.x[2][l];
    const int32_t y0 = s.y[0][l], y1 = s.y[1][l], y2 = s.y[2][l];
    // edge_function(p0, p1, p2).
    const double area = static_cast<double>(x1 - x0) * static_cast<double>(y2 - y0) -
                        static_cast<double>(y1 - y0) * static_cast<double>(x2 - x0);
    // Counter-clockwise in NDC is clockwise on screen; a front face swaps corners 1 and 2.
    const bool back = area > 0.0;
    const int32_t sx1 = back ? x1 : x2, sx2 = back ? x2 : x1;
    const int32_t sy1 = back ? y1 : y2, sy2 = back ? y2 : y1;
    s.back_face[l] = back ? 1u : 0u;
    s.double_area[l] = back ? area : -area;
    s.screen_x[0][l] = x0;
    s.screen_x[1][l] = sx1;
    s.screen_x[2][l] = sx2;
    s.screen_y[0][l] = y0;
    s.screen_y[1][l] = sy1;
    s.screen_y[2][l] = sy2;
    // pixel_centre_span() of the corners' extent, clamped to the viewport.
    const int32_t low_x = x0 < x1 ? (x0 < x2 ? x0 : x2) : (x1 < x2 ? x1 : x2);
    const int32_t high_x = x0 > x1 ? (x0 > x2 ? x0 : x2) : (x1 > x2 ? x1 : x2);
    const int32_t low_y = y0 < y1 ? (y0 < y2 ? y0 : y2) : (y1 < y2 ? y1 : y2);
    const int32_t high_y = y0 > y1 ? (y0 > y2 ? y0 : y2) : (y1 > y2 ? y1 : y2);
    int32_t first_x = -((kHalf - low_x) >> kSubpixelBits);
    int32_t first_y = -((kHalf - low_y) >> kSubpixelBits);
    int32_t last_x = (high_x - kHalf) >> kSubpixelBits;
    int32_t last_y = (high_y - kHalf) >> kSubpixelBits;
    if (keep_between_centres && (first_x > last_x || first_y > last_y)) {
      first_x = low_x >> kSubpixelBits;  // the pixels it touches, as emit() takes them
      last_x = high_x >> kSubpixelBits;
      first_y = low_y >> kSubpixelBits;
      last_y = high_y >> kSubpixelBits;
    }
    const int32_t min_px = first_x > 0 ? first_x : 0;
    const int32_t min_py = first_y > 0 ? first_y : 0;
    const int32_t max_px = last_x < width - 1 ? last_x : width - 1;
    const int32_t max_py = last_y < height - 1 ? last_y : height - 1;
    s.min_px[l] = min_px;
    s.min_py[l] = min_py;
    s.max_px[l] = max_px;
    s.max_py[l] = max_py;
    const bool off_screen = (min_px > max_px) | (min_py > max_py);
    s.outcome[l] = area == 0.0  ? SetupLanes::kDegenerate
                   : off_screen ? SetupLanes::kOffScreen
                                : SetupLanes::kEmitted;
  }
}

// The window depth's affine form, as affine_form() (triangle_setup.cpp) computes it.
void depth_lanes(SetupLanes& s, std::size_t n) {
  constexpr double kInverseScale = 1.0 / static_cast<double>(kSubpixelScale);
  for (std::size_t l = 0; l < n; ++l) {
    const bool back = s.back_face[l] != 0;
    const int32_t x0 = s.screen_x[0][l], y0 = s.screen_y[0][l];
    const double x1 = static_cast<double>(s.screen_x[1][l] - x0) * kInverseScale;
    const double y1 = static_cast<double>(s.screen_y[1][l] - y0) * kInverseScale;
    const double x2 = static_cast<double>(s.screen_x[2][l] - x0) * kInverseScale;
    const double y2 = static_cast<double>(s.screen_y[2][l] - y0) * kInverseScale;
    const double area = s.double_area[l] * (kInverseScale * kInverseScale);
    const double v0 = s.depth[0][l];
    const double v1 = back ? s.depth[1][l] : s.depth[2][l];
    const double v2 = back ? s.depth[2][l] : s.depth[1][l];
    const double d1 = v1 - v0;
    const double d2 = v2 - v0;
    s.depth_at_vertex0[l] = to_float_saturated(v0);
    s.depth_per_x[l] = to_float_saturated((d1 * y2 - d2 * y1) / area);
    s.depth_per_y[l] = to_float_saturated((d2 * x1 - d1 * x2) / area);
  }
}

// Corner k's texture offset from vertex 0, weights.y * (t1 - t0) + weights.z * (t2 - t0) in
// double with the corner's 0/1 weights, and its normal, (weights.x * n0 + weights.y * n1) +
// weights.z * n2 in float: the products by 0 and 1 kept, as they give -0 and NaN where emit()'s
// do. Corner 0 weighs (1, 0, 0); corners 1 and 2 weigh (0, 1, 0) and (0, 0, 1), swapped for a
// front face. Written per component (c = x, y, z) through the planes given.
struct CornerPlanes {
  const std::array<SetupLanes::Lanes<double>, 3>& texture;
  const std::array<SetupLanes::Lanes<float>, 3>& normal;
  std::array<SetupLanes::Lanes<float>, 3>& offset;
  std::array<SetupLanes::Lanes<float>, 3>& corner_normal;
};

void corner_lanes(const SetupLanes& s, const CornerPlanes& p, std::size_t n) {
  for (std::size_t l = 0; l < n; ++l) {
    const bool back = s.back_face[l] != 0;
    const double d1 = p.texture[1][l] - p.texture[0][l];
    const double d2 = p.texture[2][l] - p.texture[0][l];
    const float offset_1 = to_float_saturated(1.0 * d1 + 0.0 * d2);  // weights (0, 1, 0)
    const float offset_2 = to_float_saturated(0.0 * d1 + 1.0 * d2);  // weights (0, 0, 1)
    p.offset[0][l] = to_float_saturated(0.0 * d1 + 0.0 * d2);
    p.offset[1][l] = back ? offset_1 : offset_2;
    p.offset[2][l] = back ? offset_2 : offset_1;
    const float n0 = p.normal[0][l], n1 = p.normal[1][l], n2 = p.normal[2][l];
    const float normal_1 = (0.0f * n0 + 1.0f * n1) + 0.0f * n2;
    const float normal_2 = (0.0f * n0 + 0.0f * n1) + 1.0f * n2;
    p.corner_normal[0][l] = (1.0f * n0 + 0.0f * n1) + 0.0f * n2;
    p.corner_normal[1][l] = back ? normal_1 : normal_2;
    p.corner_normal[2][l] = back ? normal_2 : normal_1;
  }
}

// The corners' 1/w, in the screen triangle's order.
void inverse_w_lanes(SetupLanes& s, std::size_t n) {
  for (std::size_t l = 0; l < n; ++l) {
    const bool back = s.back_face[l] != 0;
    s.corner_inv_w[0][l] = s.inv_w[0][l];
    s.corner_inv_w[1][l] = back ? s.inv_w[1][l] : s.inv_w[2][l];
    s.corner_inv_w[2][l] = back ? s.inv_w[2][l] : s.inv_w[1][l];
  }
}

void set_up_lanes_target(SetupLanes& s, int width, int height, bool keep_between_centres) {
  const std::size_t n = s.count;
  orient_lanes(s, n, width, height, keep_between_centres);
  depth_lanes(s, n);
  inverse_w_lanes(s, n);
  // Per component: the texture positions' x with the normals' x, and so on.
  const std::array<std::array<SetupLanes::Lanes<double>, 3>*, 3> texture = {&s.tx, &s.ty, &s.tz};
  const std::array<std::array<SetupLanes::Lanes<float>, 3>*, 3> normal = {&s.nx, &s.ny, &s.nz};
  const std::array<std::array<SetupLanes::Lanes<float>, 3>*, 3> offset = {&s.offset_x, &s.offset_y,
                                                                          &s.offset_z};
  const std::array<std::array<SetupLanes::Lanes<float>, 3>*, 3> corner_normal = {
      &s.normal_x, &s.normal_y, &s.normal_z};
  for (std::size_t c = 0; c < 3; ++c) {
    corner_lanes(s, CornerPlanes{*texture[c], *normal[c], *offset[c], *corner_normal[c]}, n);
  }
}

}  // namespace soltex::raster_internal::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex::raster_internal {

HWY_EXPORT(set_up_lanes_target);

void set_up_lanes(SetupLanes& lanes, int width, int height, bool keep_between_centres) {
  HWY_DYNAMIC_DISPATCH(set_up_lanes_target)(lanes, width, height, keep_between_centres);
}

int64_t setup_kernels_compiled_targets() {
  return HWY_TARGETS;
}

}  // namespace soltex::raster_internal
#endif  // HWY_ONCE
