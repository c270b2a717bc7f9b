// Runtime dispatch of cap tracing across a run of pixels (cap_kernels.h). Highway compiles this
// file once per target (hwy/foreach_target.h re-includes it) and HWY_DYNAMIC_DISPATCH calls the
// widest one the CPU supports, once per run. The loops are plain per-lane double arithmetic,
// written with selects rather than branches so that the compiler runs them in vector lanes:
// one pixel's divisions and square roots wait on each other, a run's do not. No contraction
// (-ffp-contract=off holds for every target): the same bits as CapTracer::trace().
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "cap_kernels.cpp"
#include "cap_kernels.h"

#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <cmath>
#include <cstddef>
#include <limits>

#include "finite_lane.h"

#ifndef SOLTEX_CAP_KERNELS_SHARED
#define SOLTEX_CAP_KERNELS_SHARED
namespace soltex::raster_internal::cap_kernels_detail {

// glm's mat4 * vec4, component c: (m0 x + m1 y) + (m2 z + m3 w).
inline double row_product(const glm::dmat4& m, int c, double x, double y, double z, double w) {
  return (m[0][c] * x + m[1][c] * y) + (m[2][c] * z + m[3][c] * w);
}

// glm::dot of a plane's normal with a vector: (a x + b y) + c z.
inline double plane_dot(const glm::dvec4& p, double x, double y, double z) {
  return (p.x * x + p.y * y) + p.z * z;
}

}  // namespace soltex::raster_internal::cap_kernels_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace soltex::raster_internal::HWY_NAMESPACE {

using cap_kernels_detail::plane_dot;
using cap_kernels_detail::row_product;

void trace_ray_lanes_target(const glm::dmat4& m, int width, int height, CapRayLanes& r,
                            std::size_t count) {
  const double w = width, h = height;
  for (std::size_t l = 0; l < count; ++l) {
    const double ndc_x = r.px[l] / w * 2.0 - 1.0;
    const double ndc_y = 1.0 - r.py[l] / h * 2.0;
    // The near plane and the middle of the depth range: both finite for an infinite far plane.
    const double near_x = row_product(m, 0, ndc_x, ndc_y, -1.0, 1.0);
    const double near_y = row_product(m, 1, ndc_x, ndc_y, -1.0, 1.0);
    const double near_z = row_product(m, 2, ndc_x, ndc_y, -1.0, 1.0);
    const double near_w = row_product(m, 3, ndc_x, ndc_y, -1.0, 1.0);
    const double middle_x = row_product(m, 0, ndc_x, ndc_y, 0.0, 1.0);
    const double middle_y = row_product(m, 1, ndc_x, ndc_y, 0.0, 1.0);
    const double middle_z = row_product(m, 2, ndc_x, ndc_y, 0.0, 1.0);
    const double middle_w = row_product(m, 3, ndc_x, ndc_y, 0.0, 1.0);
    const double ox = near_x / near_w, oy = near_y / near_w, oz = near_z / near_w;
    r.origin_x[l] = ox;
    r.origin_y[l] = oy;
    r.origin_z[l] = oz;
    r.direction_x[l] = middle_x / middle_w - ox;
    r.direction_y[l] = middle_y / middle_w - oy;
    r.direction_z[l] = middle_z / middle_w - oz;
  }
}

// The texture-space distance from a cap point to where a neighbour's ray meets the cap's plane
// (a x + b y + c z + w = 0), or +inf where it runs parallel to it or meets it nowhere finite:
// CapTracer::trace()'s footprint term.
inline double neighbour_distance(const glm::dmat4& t, double a, double b, double c, double w,
                                 const CapPixelLanes::Rays& rays, std::size_t l, double point_x,
                                 double point_y, double point_z) {
  const double ox = rays.origin_x[l], oy = rays.origin_y[l], oz = rays.origin_z[l];
  const double dx = rays.direction_x[l], dy = rays.direction_y[l], dz = rays.direction_z[l];
  const double along = (a * dx + b * dy) + c * dz;
  const double along_t = -(((a * ox + b * oy) + c * oz) + w) / along;
  const bool meets = (along != 0.0) & finite_lane(along_t);
  const double vx = (ox + along_t * dx) - point_x;
  const double vy = (oy + along_t * dy) - point_y;
  const double vz = (oz + along_t * dz) - point_z;
  // glm's mat3 * vec3 on texture_from_world's linear part: (m0 x + m1 y) + m2 z per row.
  const double tx = (t[0][0] * vx + t[1][0] * vy) + t[2][0] * vz;
  const double ty = (t[0][1] * vx + t[1][1] * vy) + t[2][1] * vz;
  const double tz = (t[0][2] * vx + t[1][2] * vy) + t[2][2] * vz;
  const double length = std::sqrt((tx * tx + ty * ty) + tz * tz);
  return meets ? length : std::numeric_limits<double>::infinity();
}

// Lane l's entry into the kept region (CapTracer::trace()'s slab method): the largest entry
// parameter over the planes the ray enters through, the plane it is on (plane_count for
// none), and whether the ray starts outside a plane it never reaches. Planes in the outer
// loop, so that each inner loop runs across the lanes without branches.
struct CapEntries {
  alignas(64) CapPixelLanes::Lanes<double> entry, plane, missed;

  void find(const CapFrame& f, const CapPixelLanes::Rays& own, std::size_t count) {
    const auto none = static_cast<double>(f.plane_count);
    for (std::size_t l = 0; l < count; ++l) {
      entry[l] = 0.0;
      plane[l] = none;
      missed[l] = 0.0;
    }
    for (std::size_t j = 0; j < f.plane_count; ++j) {
      if (((f.plane_mask >> j) & 1u) == 0) continue;  // this plane does not cut the object
      const glm::dvec4& q = (*f.planes)[j];
      const auto index = static_cast<double>(j);
      for (std::size_t l = 0; l < count; ++l) {
        const double start = plane_dot(q, own.origin_x[l], own.origin_y[l], own.origin_z[l]) + q.w;
        const double along =
            plane_dot(q, own.direction_x[l], own.direction_y[l], own.direction_z[l]);
        const double t = -start / along;
        const bool enters = !(start >= 0.0);
        const bool never = enters & !(along > 0.0);
        const bool later = enters & !never & (missed[l] == 0.0) & (t > entry[l]);
        missed[l] = never ? 1.0 : missed[l];
        entry[l] = later ? t : entry[l];
        plane[l] = later ? index : plane[l];
      }
    }
  }
};

void trace_cap_lanes_target(const CapFrame& f, CapPixelLanes& p, std::size_t count) {
  constexpr double kFloatMax = std::numeric_limits<float>::max();
  CapEntries entries;
  entries.find(f, p.own, count);
  // Each lane's cap plane and its normal (plane 0 where the ray enters none: not written).
  alignas(64) CapPixelLanes::Lanes<double> a, b, c, w;
  const std::array<glm::dvec4, RasterView::kMaxClipPlanes>& planes = *f.planes;
  const std::array<glm::vec3, RasterView::kMaxClipPlanes>& normals = *f.cap_normals;
  for (std::size_t l = 0; l < count; ++l) {
    a[l] = planes[0].x;
    b[l] = planes[0].y;
    c[l] = planes[0].z;
    w[l] = planes[0].w;
    p.normal_x[l] = normals[0].x;
    p.normal_y[l] = normals[0].y;
    p.normal_z[l] = normals[0].z;
  }
  for (std::size_t j = 1; j < f.plane_count; ++j) {
    const glm::dvec4& q = planes[j];
    const glm::vec3& n = normals[j];
    const auto index = static_cast<double>(j);
    for (std::size_t l = 0; l < count; ++l) {
      const bool here = entries.plane[l] == index;
      a[l] = here ? q.x : a[l];
      b[l] = here ? q.y : b[l];
      c[l] = here ? q.z : c[l];
      w[l] = here ? q.w : w[l];
      p.normal_x[l] = here ? n.x : p.normal_x[l];
      p.normal_y[l] = here ? n.y : p.normal_y[l];
      p.normal_z[l] = here ? n.z : p.normal_z[l];
    }
  }
  const glm::dmat4& t = f.texture_from_world;
  const glm::dmat4& clip = f.clip_from_world;
  const auto none = static_cast<double>(f.plane_count);
  for (std::size_t l = 0; l < count; ++l) {
    const double entry = entries.entry[l];
    const bool hit = (entries.missed[l] == 0.0) & (entries.plane[l] != none) & finite_lane(entry);
    p.hit[l] = hit ? 1 : 0;
    const double point_x = p.own.origin_x[l] + entry * p.own.direction_x[l];
    const double point_y = p.own.origin_y[l] + entry * p.own.direction_y[l];
    const double point_z = p.own.origin_z[l] + entry * p.own.direction_z[l];
    const double clip_z = row_product(clip, 2, point_x, point_y, point_z, 1.0);
    const double clip_w = row_product(clip, 3, point_x, point_y, point_z, 1.0);
    p.texture_x[l] = row_product(t, 0, point_x, point_y, point_z, 1.0);
    p.texture_y[l] = row_product(t, 1, point_x, point_y, point_z, 1.0);
    p.texture_z[l] = row_product(t, 2, point_x, point_y, point_z, 1.0);
    // to_float_saturated(): NaN stays NaN, the rest clamped to float's range.
    const double window = clip_z / clip_w * 0.5 + 0.5;
    const double low = window < -kFloatMax ? -kFloatMax : window;
    const double clamped = kFloatMax < window ? kFloatMax : low;  // std::clamp
    p.depth[l] = static_cast<float>(window != window ? window : clamped);
    // The same plane seen through the next pixel to the right and the next one down.
    double footprint = 0.0;
    const double right =
        neighbour_distance(t, a[l], b[l], c[l], w[l], p.right, l, point_x, point_y, point_z);
    footprint = footprint < right ? right : footprint;  // std::max
    const double below =
        neighbour_distance(t, a[l], b[l], c[l], w[l], p.below, l, point_x, point_y, point_z);
    footprint = footprint < below ? below : footprint;
    // to_footprint(): past float's range or NaN, +inf.
    const double non_negative = footprint < 0.0 ? 0.0 : footprint;  // std::max(size, 0.0)
    p.footprint[l] = footprint <= kFloatMax ? static_cast<float>(non_negative)
                                            : std::numeric_limits<float>::infinity();
  }
}

}  // namespace soltex::raster_internal::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex::raster_internal {

HWY_EXPORT(trace_ray_lanes_target);
HWY_EXPORT(trace_cap_lanes_target);

void trace_ray_lanes(const glm::dmat4& world_from_clip, int width, int height, CapRayLanes& lanes,
                     std::size_t count) {
  HWY_DYNAMIC_DISPATCH(trace_ray_lanes_target)(world_from_clip, width, height, lanes, count);
}

void trace_cap_lanes(const CapFrame& frame, CapPixelLanes& lanes, std::size_t count) {
  HWY_DYNAMIC_DISPATCH(trace_cap_lanes_target)(frame, lanes, count);
}

}  // namespace soltex::raster_internal
#endif
