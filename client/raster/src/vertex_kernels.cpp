// Runtime dispatch of transform_and_project (vertex_kernels.h). Highway compiles this file once
// per target (hwy/foreach_target.h re-includes it) and HWY_DYNAMIC_DISPATCH calls the widest
// one the CPU supports, once per block of vertices. The lane loop is plain per-lane arithmetic,
// selects rather than branches, that the compiler runs in vector lanes; each lane does what
// transform_vertices() and TriangleSetup::project() do for one vertex, in their order (glm's
// products written out as glm groups them), with no contraction (-ffp-contract=off): the same
// bits on every target.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "vertex_kernels.cpp"
#include "vertex_kernels.h"

#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "finite_lane.h"
#include "screen_triangle.h"

#ifndef SOLTEX_VERTEX_KERNELS_SHARED
#define SOLTEX_VERTEX_KERNELS_SHARED
namespace soltex::raster_internal::vertex_kernels_detail {

// Vertices computed together: a multiple of every target's vector width in doubles and floats.
constexpr std::size_t kBlock = 64;

// One block's inputs and results, a plane per quantity.
struct VertexLanes {
  template <typename T>
  using Lanes = std::array<T, kBlock>;

  alignas(64) std::array<Lanes<float>, 3> position, normal;  // in: object space
  alignas(64) std::array<Lanes<float>, 4> clip;              // out: clip space
  alignas(64) std::array<Lanes<double>, 3> texture;
  alignas(64) std::array<Lanes<float>, 3> unit_normal;  // world space, or zero
  alignas(64) Lanes<double> screen_x, screen_y, depth;  // fixed point, rounded; window depth
  alignas(64) Lanes<float> inv_w;
  // 32 bits, as wide as a float lane: narrower lanes kept the loops from vectorising.
  alignas(64) Lanes<uint32_t> valid, frustum_outside, clip_outside;
};

// The pieces of a frame's matrices the lanes read, as scalars.
struct VertexMatrices {
  std::array<std::array<float, 4>, 4> clip;      // clip_from_object[column][row]
  std::array<std::array<double, 4>, 4> texture;  // texture_from_object[column][row]
  std::array<std::array<float, 3>, 3> normal;    // world_normal_from_object[column][row]
  std::array<std::array<float, 4>, ClipPolygon::kMaxPlanes> planes;  // ClipPlanes::planes
};

}  // namespace soltex::raster_internal::vertex_kernels_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace soltex::raster_internal::HWY_NAMESPACE {

using vertex_kernels_detail::kBlock;
using vertex_kernels_detail::VertexLanes;
using vertex_kernels_detail::VertexMatrices;

// glm's mat4 * vec4(p, 1), row `r`: (m0 x + m1 y) + (m2 z + m3 * 1), m3 * 1 being m3.
template <typename Real>
Real affine_row(const std::array<std::array<Real, 4>, 4>& m, std::size_t r, Real x, Real y,
                Real z) {
  return (m[0][r] * x + m[1][r] * y) + (m[2][r] * z + m[3][r]);
}

// transform_vertices(): clip and texture positions, the unit normal, validity. Two loops, one
// in float and one in double, each of which the compiler runs in vector lanes.
void transform_lanes(const VertexMatrices& m, bool has_normals, VertexLanes& v, std::size_t n) {
  for (std::size_t l = 0; l < n; ++l) {
    const float x = v.position[0][l], y = v.position[1][l], z = v.position[2][l];
    const float cx = affine_row(m.clip, 0, x, y, z), cy = affine_row(m.clip, 1, x, y, z);
    const float cz = affine_row(m.clip, 2, x, y, z), cw = affine_row(m.clip, 3, x, y, z);
    v.clip[0][l] = cx;
    v.clip[1][l] = cy;
    v.clip[2][l] = cz;
    v.clip[3][l] = cw;
    // glm's mat3 * vec3, left to right; then unit_or_zero(): the square root of glm::dot's
    // (x x + y y) + z z, and the three divisions by it.
    const float nx = v.normal[0][l], ny = v.normal[1][l], nz = v.normal[2][l];
    const auto& r = m.normal;
    const float tx = r[0][0] * nx + r[1][0] * ny + r[2][0] * nz;
    const float ty = r[0][1] * nx + r[1][1] * ny + r[2][1] * nz;
    const float tz = r[0][2] * nx + r[1][2] * ny + r[2][2] * nz;
    const float length = std::sqrt((tx * tx + ty * ty) + tz * tz);
    const bool unit = has_normals & (length > 0.0f) & finite_lane(length);
    v.unit_normal[0][l] = unit ? tx / length : 0.0f;
    v.unit_normal[1][l] = unit ? ty / length : 0.0f;
    v.unit_normal[2][l] = unit ? tz / length : 0.0f;
    const bool finite = finite_lane(cx) & finite_lane(cy) & finite_lane(cz) & finite_lane(cw);
    v.valid[l] = finite ? 1u : 0u;
  }
  for (std::size_t l = 0; l < n; ++l) {
    const double x = v.position[0][l], y = v.position[1][l], z = v.position[2][l];
    const double tx = affine_row(m.texture, 0, x, y, z), ty = affine_row(m.texture, 1, x, y, z);
    const double tz = affine_row(m.texture, 2, x, y, z);
    v.texture[0][l] = tx;
    v.texture[1][l] = ty;
    v.texture[2][l] = tz;
    const bool finite = finite_lane(tx) & finite_lane(ty) & finite_lane(tz);
    v.valid[l] &= finite ? 1u : 0u;
  }
}

// TriangleSetup::project_vertices(): outcodes, guard band and near planes (dot products as
// glm::dot groups them), and project()'s screen position (rounded, not yet an integer), depth
// and 1/w; lanes the vertex does not project to (invalid, or outside a plane) hold values
// nobody reads.
void project_lanes(const VertexMatrices& m, double width, double height, VertexLanes& v,
                   std::size_t n) {
  for (std::size_t l = 0; l < n; ++l) {
    const float x = v.clip[0][l], y = v.clip[1][l], z = v.clip[2][l], w = v.clip[3][l];
    const uint32_t frustum = (x < -w ? 1u : 0u) | (x > w ? 2u : 0u) | (y < -w ? 4u : 0u) |
                             (y > w ? 8u : 0u) | (z < -w ? 16u : 0u) | (z > w ? 32u : 0u);
    uint32_t outside = 0;
    for (std::size_t p = 0; p < ClipPolygon::kMaxPlanes; ++p) {
      const std::array<float, 4>& plane = m.planes[p];
      const float distance =
          ((plane[0] * x + plane[1] * y) + (plane[2] * z + plane[3] * w)) - clip_plane_offset(p);
      outside |= distance >= 0.0f ? 0u : 1u << p;
    }
    v.frustum_outside[l] = frustum;
    v.clip_outside[l] = outside;
    const double inv_w = 1.0 / static_cast<double>(w);
    const double ndc_x = static_cast<double>(x) * inv_w;
    const double ndc_y = static_cast<double>(y) * inv_w;
    const double ndc_z = static_cast<double>(z) * inv_w;
    const double screen_x = (ndc_x * 0.5 + 0.5) * width;
    const double screen_y = (0.5 - ndc_y * 0.5) * height;
    v.screen_x[l] = subpixel_position(screen_x);
    v.screen_y[l] = subpixel_position(screen_y);
    v.depth[l] = ndc_z * 0.5 + 0.5;
    v.inv_w[l] = static_cast<float>(inv_w);
  }
}

void TransformAndProjectKernel(const ObjectFrame& object, const VertexProjection& projection,
                               std::size_t begin, std::size_t end, TransformedVertices& out) {
  const RasterMesh& mesh = object.source->mesh;
  const bool has_normals = !mesh.normals.empty();
  VertexMatrices m;
  for (std::size_t c = 0; c < 4; ++c) {
    for (std::size_t r = 0; r < 4; ++r) {
      m.clip[c][r] = object.clip_from_object[static_cast<int>(c)][static_cast<int>(r)];
      m.texture[c][r] =
          object.source->texture_from_object[static_cast<int>(c)][static_cast<int>(r)];
    }
  }
  for (std::size_t c = 0; c < 3; ++c) {
    for (std::size_t r = 0; r < 3; ++r) {
      m.normal[c][r] = object.world_normal_from_object[static_cast<int>(c)][static_cast<int>(r)];
    }
  }
  for (std::size_t p = 0; p < ClipPolygon::kMaxPlanes; ++p) {
    for (std::size_t k = 0; k < 4; ++k) {
      m.planes[p][k] = projection.planes->planes[p][static_cast<int>(k)];
    }
  }
  const double width = static_cast<double>(projection.width);
  const double height = static_cast<double>(projection.height);
  VertexLanes lanes;  // uninitialised: each block fills what it reads
  for (std::size_t first = begin; first < end; first += kBlock) {
    const std::size_t n = std::min(kBlock, end - first);
    for (std::size_t l = 0; l < n; ++l) {
      const glm::vec3& p = mesh.positions[first + l];
      const glm::vec3 normal = has_normals ? mesh.normals[first + l] : glm::vec3(0.0f);
      for (std::size_t r = 0; r < 3; ++r) {
        lanes.position[r][l] = p[static_cast<int>(r)];
        lanes.normal[r][l] = normal[static_cast<int>(r)];
      }
    }
    transform_lanes(m, has_normals, lanes, n);
    project_lanes(m, width, height, lanes, n);
    for (std::size_t l = 0; l < n; ++l) {
      const std::size_t at = object.first_vertex + first + l;
      TransformedVertex& v = out.vertex[at];
      out.clip[at] =
          glm::vec4(lanes.clip[0][l], lanes.clip[1][l], lanes.clip[2][l], lanes.clip[3][l]);
      v.texture = glm::dvec3(lanes.texture[0][l], lanes.texture[1][l], lanes.texture[2][l]);
      v.normal =
          glm::vec3(lanes.unit_normal[0][l], lanes.unit_normal[1][l], lanes.unit_normal[2][l]);
      v.valid = static_cast<uint8_t>(lanes.valid[l]);
      if (v.valid == 0) continue;
      v.frustum_outside = static_cast<uint8_t>(lanes.frustum_outside[l]);
      v.clip_outside = static_cast<uint8_t>(lanes.clip_outside[l]);
      // Only where the vertex is inside the guard band: there the clamped, rounded position
      // is an integer below 2^24 in magnitude.
      if (v.clip_outside != 0) continue;
      v.x = static_cast<int32_t>(lanes.screen_x[l]);
      v.y = static_cast<int32_t>(lanes.screen_y[l]);
      v.depth = lanes.depth[l];
      v.inv_w = lanes.inv_w[l];
    }
  }
}

int64_t TargetOfVertexKernels() {
  return HWY_TARGET;
}

}  // namespace soltex::raster_internal::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex::raster_internal {

HWY_EXPORT(TransformAndProjectKernel);
HWY_EXPORT(TargetOfVertexKernels);

void transform_and_project(const ObjectFrame& object, const VertexProjection& projection,
                           std::size_t begin, std::size_t end, TransformedVertices& out) {
  HWY_DYNAMIC_DISPATCH(TransformAndProjectKernel)(object, projection, begin, end, out);
  write_plane_distances(object, begin, end, out);
}

int64_t vertex_kernels_compiled_targets() {
  return HWY_TARGETS;
}

int64_t vertex_kernels_dispatched_target() {
  return HWY_DYNAMIC_DISPATCH(TargetOfVertexKernels)();
}

}  // namespace soltex::raster_internal
#endif  // HWY_ONCE
