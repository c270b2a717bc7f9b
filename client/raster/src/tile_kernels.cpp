// Runtime dispatch of the tile's per-pixel loops (tile_kernels.h). Highway compiles this file
// once per target (hwy/foreach_target.h re-includes it) and HWY_DYNAMIC_DISPATCH calls the
// widest one the CPU supports, once per chunk's bin of triangles drawn into a tile (and per
// large triangle drawn) and once per batch of resolved runs of pixels. Most loops are plain
// per-lane code, written with selects rather than branches so that the compiler runs them in vector
// lanes; a target only widens the lanes (AVX2: 8 floats, AVX-512: 16, against 4 in the baseline
// build, whose lack of 64-bit vector compares keeps draw_unclipped_target scalar). The small
// triangles' draw (draw_small_span), run_starts_target and gather_surface_lanes_target are written
// in Highway's operations. The same IEEE operations in the same order per lane, and no contraction
// (-ffp-contract=off holds for every target): the same bits on every target.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tile_kernels.cpp"
#include "tile_kernels.h"

#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>

#include "finite_lane.h"
#include "soltex/raster/raster_view.h"
#include "tile_rasterizer.h"
#include "whole_blocks.h"

#ifndef SOLTEX_TILE_KERNELS_SHARED
#define SOLTEX_TILE_KERNELS_SHARED
namespace soltex::raster_internal::tile_kernels_detail {

constexpr float kFarDepth = 1.0f;

// A triangle's vertex attributes as SurfaceLanes takes them: 21 floats from inv_w on, read in
// whole blocks of four (the three past the normals are part of texture_origin).
constexpr std::size_t kAttributeFloats = 21;
constexpr std::size_t kAttributeBlocks = 6;
constexpr std::size_t kAttributeSlots = kAttributeBlocks * 4;
static_assert(std::is_standard_layout_v<ScreenTriangle>);
// The positions and the double area, read as two blocks of four int32 from the start.
static_assert(offsetof(ScreenTriangle, x) == 0 && offsetof(ScreenTriangle, y) == 12 &&
              offsetof(ScreenTriangle, double_area) == 24);
static_assert(offsetof(ScreenTriangle, texture_offset) ==
              offsetof(ScreenTriangle, inv_w) + 3 * sizeof(float));
static_assert(offsetof(ScreenTriangle, normal) ==
              offsetof(ScreenTriangle, texture_offset) + 9 * sizeof(float));
static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
static_assert(offsetof(ScreenTriangle, inv_w) + kAttributeSlots * sizeof(float) <=
              sizeof(ScreenTriangle));
// Pixel centres in fixed point fit in int32 with room for a difference from a position.
static_assert(int64_t{RasterView::kMaxSize} * kSubpixelScale < (int64_t{1} << 24));

}  // namespace soltex::raster_internal::tile_kernels_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace soltex::raster_internal::HWY_NAMESPACE {

using tile_kernels_detail::kAttributeBlocks;
using tile_kernels_detail::kAttributeFloats;
using tile_kernels_detail::kAttributeSlots;
using tile_kernels_detail::kFarDepth;

// One row of draw_unclipped_target(), pixels first_x + k for k < count: inside(k) is the
// pixel's edge test, and the depth, far-plane and winner updates follow it. Called with a
// constant test for a row wholly inside, so that loop keeps only float lanes, as wide as the
// target has, with no 64-bit edge lanes to keep pace with.
template <class Inside>
HWY_INLINE void draw_row(const ScreenTriangle* self, int first_x, int count, float x0,
                         float depth_y, float* __restrict depth_row,
                         const ScreenTriangle** __restrict winner_row, const Inside& inside,
                         uint64_t& rasterized, uint64_t& depth_passed) {
  const float at_vertex0 = self->depth.at_vertex0;
  const float per_x = self->depth.per_x;
  uint64_t row_rasterized = 0, row_passed = 0;
  for (int k = 0; k < count; ++k) {
    const bool in = inside(k);
    const float dx = static_cast<float>(first_x + k) + 0.5f - x0;
    const float depth = (at_vertex0 + per_x * dx) + depth_y;
    const float old_depth = depth_row[k];
    const bool pass = in & (depth < old_depth) & !(depth > kFarDepth);
    row_rasterized += in ? 1 : 0;
    row_passed += pass ? 1 : 0;
    depth_row[k] = pass ? depth : old_depth;
    winner_row[k] = pass ? self : winner_row[k];
  }
  rasterized += row_rasterized;
  depth_passed += row_passed;
}

void draw_unclipped_target(const ScreenTriangle& t, const SpanDraw& span, float* depth_plane,
                           const ScreenTriangle** winner_plane, RasterStats& stats) {
  // The loop of draw() without clip forms and coverage counts, written with selects instead
  // of early exits so that it runs across the row in vector lanes: the same tests (edge
  // functions, depth, far plane) and the same float depth, so the same fragments win.
  const int first_x = span.first_x, last_x = span.last_x;
  std::array<int64_t, 3> row = span.row;
  const std::array<int64_t, 3>& step_x = span.step_x;
  const std::array<int64_t, 3>& step_y = span.step_y;
  const float x0 = t.x0_pixels();
  const float y0 = t.y0_pixels();
  const float per_y = t.depth.per_y;
  const ScreenTriangle* const self = &t;
  const int count = last_x - first_x + 1;
  uint64_t rasterized = 0, depth_passed = 0;
  for (int y = span.first_y; y <= span.last_y; ++y) {
    const float dy = static_cast<float>(y) + 0.5f - y0;
    const float depth_y = per_y * dy;
    const auto row_start =
        static_cast<std::ptrdiff_t>((y - span.tile_y0) * kTileSize + (first_x - span.tile_x0));
    float* __restrict depth_row = depth_plane + row_start;
    const ScreenTriangle** __restrict winner_row = winner_plane + row_start;
    const int64_t r0 = row[0], r1 = row[1], r2 = row[2];
    const int64_t s0 = step_x[0], s1 = step_x[1], s2 = step_x[2];
    row[0] += step_y[0];
    row[1] += step_y[1];
    row[2] += step_y[2];
    // Edge functions are affine along the row: its ends settle whether every pixel is inside
    // (a large triangle's rows inside a tile mostly are) or none is.
    const int64_t last = count - 1;
    const int64_t f0 = r0 + s0 * last, f1 = r1 + s1 * last, f2 = r2 + s2 * last;
    if (std::max(r0, f0) < 0 || std::max(r1, f1) < 0 || std::max(r2, f2) < 0) continue;
    if (std::min({r0, f0, r1, f1, r2, f2}) >= 0) {
      draw_row(
          self, first_x, count, x0, depth_y, depth_row, winner_row, [](int) { return true; },
          rasterized, depth_passed);
      continue;
    }
    const auto edges_inside = [&](int k) {
      const int64_t e0 = r0 + s0 * k, e1 = r1 + s1 * k, e2 = r2 + s2 * k;
      return (e0 | e1 | e2) >= 0;
    };
    draw_row(self, first_x, count, x0, depth_y, depth_row, winner_row, edges_inside, rasterized,
             depth_passed);
  }
  stats.fragments_rasterized += rasterized;
  stats.fragments_depth_passed += depth_passed;
}

// draw_unclipped_target()'s tests and depth, a tile's column of up to kSmallLanes pixels at a
// time over the triangle's rows, in 32-bit lanes (twice as many to a vector as 64-bit ones) and
// without a branch per pixel, whose outcome a small triangle's edges make random. The edge
// functions as draw() sets them up (SpanDraw), narrowed: exact in int32 (fits_int32()).
struct SmallEdges {
  std::array<int32_t, 3> row, step_x, step_y;
};

HWY_INLINE SmallEdges narrowed(const SpanDraw& span) {
  SmallEdges e;
  for (std::size_t k = 0; k < 3; ++k) {
    e.row[k] = static_cast<int32_t>(span.row[k]);
    e.step_x[k] = static_cast<int32_t>(span.step_x[k]);
    e.step_y[k] = static_cast<int32_t>(span.step_y[k]);
  }
  return e;
}

HWY_INLINE void draw_small_span(const ScreenTriangle& t, const SpanDraw& span,
                                const SmallEdges& edges, float* depth_plane,
                                const ScreenTriangle** winner_plane, uint64_t& rasterized,
                                uint64_t& depth_passed) {
  namespace hn = hwy::HWY_NAMESPACE;
  const hn::CappedTag<int32_t, kSmallLanes> di;
  const hn::Rebind<float, decltype(di)> df;
  static_assert(kPlanePadding >= kSmallLanes - 1);  // a vector may run past the tile's last pixel
  // Winners are pointers: as many 64-bit lanes, in one or two vectors.
  static_assert(sizeof(uintptr_t) == sizeof(uint64_t));
  const hn::CappedTag<uint64_t, kSmallLanes> dw;
  const int lanes = static_cast<int>(hn::Lanes(di));
  const int pointer_lanes = static_cast<int>(hn::Lanes(dw));
  const int count = span.last_x - span.first_x + 1;
  assert(count >= 1 && count <= kTileSize);
  const std::array<int32_t, 3>& row = edges.row;
  const std::array<int32_t, 3>& step_x = edges.step_x;
  const std::array<int32_t, 3>& step_y = edges.step_y;
  // Edge k's function j pixels right of a column's first: its value there plus lane j of this.
  const auto along = [&](std::size_t k) {
    return hn::Mul(hn::Iota(di, 0), hn::Set(di, step_x[k]));
  };
  const auto along0 = along(0), along1 = along(1), along2 = along(2);
  const float x0 = t.x0_pixels();
  const float y0 = t.y0_pixels();
  const auto self = hn::Set(dw, static_cast<uint64_t>(reinterpret_cast<uintptr_t>(&t)));
  auto* winners = reinterpret_cast<uint64_t*>(winner_plane);
  const auto far = hn::Set(df, kFarDepth);
  for (int c = 0; c < count; c += lanes) {
    const auto columns = hn::RebindMask(df, hn::FirstN(di, static_cast<std::size_t>(count - c)));
    auto e0 = hn::Add(hn::Set(di, row[0] + step_x[0] * c), along0);
    auto e1 = hn::Add(hn::Set(di, row[1] + step_x[1] * c), along1);
    auto e2 = hn::Add(hn::Set(di, row[2] + step_x[2] * c), along2);
    // The depth as draw_unclipped_target() has it: (at_vertex0 + per_x * dx) + per_y * dy.
    // Iota(0) is a constant; Iota(first) with a run-time first was built by scalar stores and
    // read back as a vector, which waited on their forwarding.
    const auto x = hn::ConvertTo(df, hn::Add(hn::Iota(di, 0), hn::Set(di, span.first_x + c)));
    const auto dx = hn::Sub(hn::Add(x, hn::Set(df, 0.5f)), hn::Set(df, x0));
    const auto depth_x =
        hn::Add(hn::Set(df, t.depth.at_vertex0), hn::Mul(hn::Set(df, t.depth.per_x), dx));
    for (int y = span.first_y; y <= span.last_y; ++y) {
      const float dy = static_cast<float>(y) + 0.5f - y0;
      const auto depth = hn::Add(depth_x, hn::Set(df, t.depth.per_y * dy));
      const std::ptrdiff_t at = static_cast<std::ptrdiff_t>(y - span.tile_y0) * kTileSize +
                                (span.first_x - span.tile_x0) + c;
      const auto old_depth = hn::LoadU(df, depth_plane + at);
      const auto outside = hn::Lt(hn::Or(hn::Or(e0, e1), e2), hn::Zero(di));
      const auto inside = hn::AndNot(hn::RebindMask(df, outside), columns);
      const auto pass = hn::AndNot(hn::Gt(depth, far), hn::And(inside, hn::Lt(depth, old_depth)));
      rasterized += hn::CountTrue(df, inside);
      depth_passed += hn::CountTrue(df, pass);
      // Lanes past the triangle's columns (the tile's next pixels, or its planes' padding)
      // are written back as they were.
      hn::StoreU(hn::IfThenElse(pass, depth, old_depth), df, depth_plane + at);
      uint8_t bits[8] = {};
      hn::StoreMaskBits(df, pass, bits);
      for (int w = 0; w < lanes; w += pointer_lanes) {
        const auto part = static_cast<uint8_t>(bits[0] >> w);
        hn::BlendedStore(self, hn::LoadMaskBits(dw, &part), dw, winners + at + w);
      }
      e0 = hn::Add(e0, hn::Set(di, step_y[0]));
      e1 = hn::Add(e1, hn::Set(di, step_y[1]));
      e2 = hn::Add(e2, hn::Set(di, step_y[2]));
    }
  }
}

void draw_small_target(const ScreenTriangle& t, const SpanDraw& span, float* depth_plane,
                       const ScreenTriangle** winner_plane, RasterStats& stats) {
  uint64_t rasterized = 0, depth_passed = 0;
  draw_small_span(t, span, narrowed(span), depth_plane, winner_plane, rasterized, depth_passed);
  stats.fragments_rasterized += rasterized;
  stats.fragments_depth_passed += depth_passed;
}

void draw_bin_target(const BinDraw& bin, float* depth_plane, const ScreenTriangle** winner_plane,
                     RasterStats& stats) {
  uint64_t rasterized = 0, depth_passed = 0;
  for (std::size_t k = 0; k < bin.count; ++k) {
    if (k + kBinPrefetchAhead < bin.count) {
      __builtin_prefetch(&bin.triangles[bin.items[k + kBinPrefetchAhead]]);
    }
    const ScreenTriangle& t = bin.triangles[bin.items[k]];
    SpanDraw span;
    if (!span_of(t, bin.tile_x0, bin.tile_y0, bin.tile_x1, bin.tile_y1, span)) continue;
    if (t.clip_mask != 0 || !fits_int32(t)) {
      bin.other(bin.context, t);
      continue;
    }
    draw_small_span(t, span, narrowed(span), depth_plane, winner_plane, rasterized, depth_passed);
  }
  stats.fragments_rasterized += rasterized;
  stats.fragments_depth_passed += depth_passed;
}

// Perspective-correct attributes at `count` pixel centres of one triangle, whose vertex k's
// barycentric numerators (edge functions) are edge[k]: with barycentric weights b and
// q = 1/w, P = sum(b q P) / sum(b q). Its derivative per pixel step is analytic: dP/dx =
// (d(sum b q P)/dx - P d(sum b q)/dx) / sum(b q), the weights' derivatives being constant
// over the triangle. Float suffices: P is an offset from the triangle's double origin, so
// float's error is relative to the triangle's size. Per pixel the same IEEE operations in the
// same order whatever the run, selects standing in for branches, so the loop runs in vector
// lanes; the triangle's terms are the same in every lane.
struct SurfaceChunk {
  static constexpr std::size_t kCapacity = kTileSize;
  // Lanes computed together: whole SSE, NEON and AVX2 vectors; AVX-512 runs a last block of
  // eight in its loop's half-width remainder. Sixteen made a run of four to eight pixels (most
  // of a fine mesh's long runs) compute twice its lanes.
  static constexpr std::size_t kBlock = 8;
  static_assert(kCapacity % kBlock == 0);
  template <typename T>
  using Lanes = std::array<T, kCapacity>;

  alignas(64) std::array<Lanes<float>, 3> edge;  // in
  alignas(64) Lanes<float> offset_x, offset_y, offset_z, footprint, normal_x, normal_y, normal_z;
  alignas(64) Lanes<float> axis_x, axis_y, axis_z, minor;
};

// `t`: the terms of each lane's triangle, t.area(l), t.q(k, l) and so on (RunTerms,
// GatheredTerms); `s`: the lanes' edge numerators in, their attributes out (SurfaceChunk,
// SurfaceLanes).
template <typename Terms, typename Lanes>
void interpolate(const Terms& t, Lanes& s, std::size_t count) {
  // Lane l reads its own inputs and writes its own outputs (distinct arrays): no iteration
  // depends on another. Said to the compiler, which would otherwise version the loop on a
  // run-time check per pair of arrays, and with this many outputs gives up vectorizing it.
#if defined(__clang__)
#pragma clang loop vectorize(assume_safety)
#elif defined(__GNUC__)
#pragma GCC ivdep
#endif
  for (std::size_t l = 0; l < count; ++l) {
    const float inv_area = 1.0f / t.area(l);
    const float step = static_cast<float>(kSubpixelScale) * inv_area;
    float sum_q = 0.0f, dq_dx = 0.0f, dq_dy = 0.0f;
    float sx = 0.0f, sy = 0.0f, sz = 0.0f;  // sum b q P
    float dx_x = 0.0f, dx_y = 0.0f, dx_z = 0.0f, dy_x = 0.0f, dy_y = 0.0f, dy_z = 0.0f;
    float mx = 0.0f, my = 0.0f, mz = 0.0f;  // sum b q N
    for (std::size_t k = 0; k < 3; ++k) {
      const float weight = s.edge[k][l] * inv_area;
      const float q_k = t.q(k, l);
      const float weight_q = weight * q_k;
      const float weight_q_dx = -t.edge_dy(k, l) * step * q_k;
      const float weight_q_dy = t.edge_dx(k, l) * step * q_k;
      sum_q += weight_q;
      dq_dx += weight_q_dx;
      dq_dy += weight_q_dy;
      sx += weight_q * t.ox(k, l);
      sy += weight_q * t.oy(k, l);
      sz += weight_q * t.oz(k, l);
      dx_x += weight_q_dx * t.ox(k, l);
      dx_y += weight_q_dx * t.oy(k, l);
      dx_z += weight_q_dx * t.oz(k, l);
      dy_x += weight_q_dy * t.ox(k, l);
      dy_y += weight_q_dy * t.oy(k, l);
      dy_z += weight_q_dy * t.oz(k, l);
      mx += weight_q * t.nx(k, l);
      my += weight_q * t.ny(k, l);
      mz += weight_q * t.nz(k, l);
    }
    const bool has_q = (sum_q > 0.0f) & finite_lane(sum_q);
    const float inv_q = 1.0f / sum_q;
    const float cx = sx * inv_q, cy = sy * inv_q, cz = sz * inv_q;
    const float ddx_x = (dx_x - cx * dq_dx) * inv_q;
    const float ddx_y = (dx_y - cy * dq_dx) * inv_q;
    const float ddx_z = (dx_z - cz * dq_dx) * inv_q;
    const float ddy_x = (dy_x - cx * dq_dy) * inv_q;
    const float ddy_y = (dy_y - cy * dq_dy) * inv_q;
    const float ddy_z = (dy_z - cz * dq_dy) * inv_q;
    const float along_x = (ddx_x * ddx_x + ddx_y * ddx_y) + ddx_z * ddx_z;
    const float along_y = (ddy_x * ddy_x + ddy_y * ddy_y) + ddy_z * ddy_z;
    const bool y_longer = along_x < along_y;
    const float longer = y_longer ? along_y : along_x;  // std::max
    const float shorter = y_longer ? along_x : along_y;
    const float size = std::sqrt(longer);
    // Non-finite offsets only come from absurd inputs: stay at a vertex, never NaN.
    const bool keep = has_q & finite_lane(cx) & finite_lane(cy) & finite_lane(cz);
    constexpr float kInfinity = std::numeric_limits<float>::infinity();
    s.offset_x[l] = keep ? cx : 0.0f;
    s.offset_y[l] = keep ? cy : 0.0f;
    s.offset_z[l] = keep ? cz : 0.0f;
    const float kept_size = keep ? size : kInfinity;
    const float footprint = kept_size != kept_size ? kInfinity : kept_size;  // NaN -> +inf
    s.footprint[l] = footprint;
    // The long side's vector where the footprint is finite; else no direction (one tap). A NaN
    // short side is left to the writers (no_direction()): a test for it here costs the loop its
    // vectorization.
    const bool directed = footprint < kInfinity;
    const float long_x = y_longer ? ddy_x : ddx_x;
    const float long_y = y_longer ? ddy_y : ddx_y;
    const float long_z = y_longer ? ddy_z : ddx_z;
    const float minor = std::sqrt(shorter);
    s.axis_x[l] = directed ? long_x : 0.0f;
    s.axis_y[l] = directed ? long_y : 0.0f;
    s.axis_z[l] = directed ? long_z : 0.0f;
    s.minor[l] = directed ? minor : footprint;
    // The unit normal: sum b q N normalised, or the first vertex's normal where that has no
    // length, or +z.
    const float length = std::sqrt((mx * mx + my * my) + mz * mz);
    const float fx = t.nx(0, l), fy = t.ny(0, l), fz = t.nz(0, l);
    const float fallback_length = std::sqrt((fx * fx + fy * fy) + fz * fz);
    const bool has_sum = (length > 0.0f) & finite_lane(length);
    const bool has_fallback = fallback_length > 0.0f;
    const float ux = has_fallback ? fx / fallback_length : 0.0f;
    const float uy = has_fallback ? fy / fallback_length : 0.0f;
    const float uz = has_fallback ? fz / fallback_length : 1.0f;
    s.normal_x[l] = has_sum ? mx / length : ux;
    s.normal_y[l] = has_sum ? my / length : uy;
    s.normal_z[l] = has_sum ? mz / length : uz;
  }
}

// One triangle's terms in every lane (a run).
struct RunTerms {
  const TriangleTerms& t;
  float area(std::size_t) const { return t.area; }
  float q(std::size_t k, std::size_t) const { return t.q[k]; }
  float ox(std::size_t k, std::size_t) const { return t.ox[k]; }
  float oy(std::size_t k, std::size_t) const { return t.oy[k]; }
  float oz(std::size_t k, std::size_t) const { return t.oz[k]; }
  float nx(std::size_t k, std::size_t) const { return t.nx[k]; }
  float ny(std::size_t k, std::size_t) const { return t.ny[k]; }
  float nz(std::size_t k, std::size_t) const { return t.nz[k]; }
  float edge_dy(std::size_t k, std::size_t) const { return t.edge_dy[k]; }
  float edge_dx(std::size_t k, std::size_t) const { return t.edge_dx[k]; }
};

// Each lane's own triangle's terms, gathered into SurfaceLanes (pixels of short runs).
struct GatheredTerms {
  const SurfaceLanes& s;
  float area(std::size_t l) const { return s.area[l]; }
  float q(std::size_t k, std::size_t l) const { return s.q[k][l]; }
  float ox(std::size_t k, std::size_t l) const { return s.ox[k][l]; }
  float oy(std::size_t k, std::size_t l) const { return s.oy[k][l]; }
  float oz(std::size_t k, std::size_t l) const { return s.oz[k][l]; }
  float nx(std::size_t k, std::size_t l) const { return s.nx[k][l]; }
  float ny(std::size_t k, std::size_t l) const { return s.ny[k][l]; }
  float nz(std::size_t k, std::size_t l) const { return s.nz[k][l]; }
  float edge_dy(std::size_t k, std::size_t l) const { return s.edge_dy[k][l]; }
  float edge_dx(std::size_t k, std::size_t l) const { return s.edge_dx[k][l]; }
};

// A run of pixels: the triangle's terms taken once, the pixels across the
// lanes, written plane by plane.
void resolve_long_run(const SurfaceRun& run, SurfaceChunk& chunk, const GBufferPlanes& target) {
  const ScreenTriangle& t = *run.triangle;
  const TriangleTerms terms = triangle_terms(t);
  // Per pixel to the right, edge k's function steps by an exact integer, so each pixel's
  // numerator is the one its own centre gives.
  const std::array<int64_t, 3> first = edge_numerators(t, run.x, run.y);
  const auto n = static_cast<std::size_t>(run.count);
  // Lanes computed for whole blocks (the lanes past `count` are never written out): a vector
  // loop's remainder would otherwise run a lane at a time.
  const std::size_t lanes = whole_blocks(n, SurfaceChunk::kBlock);
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t a = (k + 1) % 3, b = (k + 2) % 3;
    const int64_t e = first[k], de = -(int64_t{t.y[b]} - int64_t{t.y[a]}) * kSubpixelScale;
    for (std::size_t l = 0; l < lanes; ++l) {
      chunk.edge[k][l] = static_cast<float>(e + de * static_cast<int64_t>(l));
    }
  }
  interpolate(RunTerms{terms}, chunk, lanes);
  // Plane by plane, each in a loop of its own, the run's fields read once beforehand: a store
  // through the flags' uint8_t* may alias anything, so a loop writing every plane read the
  // run's depth pointer, flags and object again after it and ran a pixel at a time.
  const std::size_t i = run.target;
  const uint8_t run_flags = run.flags;
  const uint32_t run_object_id = run.object_id;
  std::copy_n(run.depth, n, target.depth + i);
  std::fill_n(target.flags + i, n, run_flags);
  std::fill_n(target.object_id + i, n, run_object_id);
  std::copy_n(chunk.footprint.data(), n, target.footprint + i);
  float* __restrict minor = target.footprint_minor + i;
  glm::vec3* __restrict axis = target.footprint_axis + i;
  for (std::size_t l = 0; l < n; ++l) {
    const bool none = no_direction(chunk.minor[l]);
    minor[l] = none ? chunk.footprint[l] : chunk.minor[l];
    axis[l] = none ? glm::vec3(0.0f) : glm::vec3(chunk.axis_x[l], chunk.axis_y[l], chunk.axis_z[l]);
  }
  glm::vec3* __restrict normal = target.normal + i;
  for (std::size_t l = 0; l < n; ++l) {
    normal[l] = glm::vec3(chunk.normal_x[l], chunk.normal_y[l], chunk.normal_z[l]);
  }
  glm::dvec3* __restrict position = target.texture_position + i;
  const glm::dvec3 origin = t.texture_origin;
  for (std::size_t l = 0; l < n; ++l) {
    position[l] =
        origin + glm::dvec3(glm::vec3(chunk.offset_x[l], chunk.offset_y[l], chunk.offset_z[l]));
  }
}

void resolve_surface_runs_target(const SurfaceRun* runs, std::size_t run_count,
                                 const GBufferPlanes& target) {
  SurfaceChunk chunk;
  for (std::size_t r = 0; r < run_count; ++r) resolve_long_run(runs[r], chunk, target);
}

uint64_t run_starts_target(const ScreenTriangle* const* winners, int count) {
  // Each pixel's winner against its left neighbour's, a vector of pointers at a time, compared
  // as their bits (Highway's loads may alias anything). A vector may read past the row: into
  // the next row, or the plane's padding after the last one; bits past `count` are dropped.
  namespace hn = hwy::HWY_NAMESPACE;
  constexpr std::size_t kMaxLanes = 8;
  static_assert(kPlanePadding >= kMaxLanes - 1 && kTileSize <= 64);
  const hn::CappedTag<uintptr_t, kMaxLanes> d;
  const auto lanes = static_cast<int>(hn::Lanes(d));
  const auto* bits = reinterpret_cast<const uintptr_t*>(winners);
  uint64_t starts = 1;
  for (int i = 1; i < count; i += lanes) {
    const auto differs = hn::Ne(hn::LoadU(d, bits + i), hn::LoadU(d, bits + i - 1));
    uint8_t mask[8] = {};  // lane j's bit is bit j % 8 of byte j / 8
    hn::StoreMaskBits(d, differs, mask);
    for (int b = 0; b * 8 < lanes; ++b) starts |= uint64_t{mask[b]} << (i + 8 * b);
  }
  return count >= 64 ? starts : starts & ((uint64_t{1} << count) - 1);
}

#if HWY_TARGET != HWY_SCALAR
// Rows r0..r3 of a 4 x 4 block to its columns, in place (r0 then holds lane 0 of every row,
// and so on): lanes moved, never changed, so floats keep their bits.
template <typename D>
void transpose4(D d, hwy::HWY_NAMESPACE::Vec<D>& r0, hwy::HWY_NAMESPACE::Vec<D>& r1,
                hwy::HWY_NAMESPACE::Vec<D>& r2, hwy::HWY_NAMESPACE::Vec<D>& r3) {
  namespace hn = hwy::HWY_NAMESPACE;
  const hn::Repartition<uint64_t, D> d64;
  const auto low01 = hn::BitCast(d64, hn::InterleaveLower(d, r0, r1));
  const auto low23 = hn::BitCast(d64, hn::InterleaveLower(d, r2, r3));
  const auto high01 = hn::BitCast(d64, hn::InterleaveUpper(d, r0, r1));
  const auto high23 = hn::BitCast(d64, hn::InterleaveUpper(d, r2, r3));
  r0 = hn::BitCast(d, hn::InterleaveLower(d64, low01, low23));
  r1 = hn::BitCast(d, hn::InterleaveUpper(d64, low01, low23));
  r2 = hn::BitCast(d, hn::InterleaveLower(d64, high01, high23));
  r3 = hn::BitCast(d, hn::InterleaveUpper(d64, high01, high23));
}

// Four int64 lanes (low and high halves in 32-bit lanes) as float, rounded once as a
// conversion from int64 rounds: each is below 2^53, so exact in double first.
template <typename DF>
hwy::HWY_NAMESPACE::Vec<DF> int64_to_float(
    DF df, hwy::HWY_NAMESPACE::Vec<hwy::HWY_NAMESPACE::RebindToSigned<DF>> low,
    hwy::HWY_NAMESPACE::Vec<hwy::HWY_NAMESPACE::RebindToSigned<DF>> high) {
  namespace hn = hwy::HWY_NAMESPACE;
  static_assert(std::endian::native == std::endian::little);
  const hn::RebindToSigned<DF> di;
  const hn::Repartition<int64_t, DF> di64;
  const hn::Repartition<double, DF> dd;
  const hn::Half<DF> dh;
  const auto first = hn::ConvertTo(dd, hn::BitCast(di64, hn::InterleaveLower(di, low, high)));
  const auto second = hn::ConvertTo(dd, hn::BitCast(di64, hn::InterleaveUpper(di, low, high)));
  return hn::Combine(df, hn::DemoteTo(dh, second), hn::DemoteTo(dh, first));
}

// a * b - c * d of int32 lanes, exact in double (each product below 2^51), then rounded to
// float once: the float of the int64 result.
template <typename DI>
hwy::HWY_NAMESPACE::Vec<hwy::HWY_NAMESPACE::RebindToFloat<DI>> cross_to_float(
    DI, hwy::HWY_NAMESPACE::Vec<DI> a, hwy::HWY_NAMESPACE::Vec<DI> b, hwy::HWY_NAMESPACE::Vec<DI> c,
    hwy::HWY_NAMESPACE::Vec<DI> d) {
  namespace hn = hwy::HWY_NAMESPACE;
  const hn::RebindToFloat<DI> df;
  const hn::Half<DI> dih;
  const hn::Half<decltype(df)> dfh;
  const hn::Repartition<double, DI> dd;
  const auto half = [&](auto take) {
    const auto p = hn::Mul(hn::PromoteTo(dd, take(a)), hn::PromoteTo(dd, take(b)));
    const auto q = hn::Mul(hn::PromoteTo(dd, take(c)), hn::PromoteTo(dd, take(d)));
    return hn::DemoteTo(dfh, hn::Sub(p, q));
  };
  const auto lower = half([&](auto v) { return hn::LowerHalf(dih, v); });
  const auto upper = half([&](auto v) { return hn::UpperHalf(dih, v); });
  return hn::Combine(df, upper, lower);
}
#endif

// The planes that the floats of a triangle's attribute block go to, in its order: 1/w of the
// three vertices, then each vertex's texture offset (x, y, z), then each vertex's normal; the
// three floats read past them (whole blocks of four) go to `spare`.
std::array<float*, kAttributeSlots> attribute_planes(SurfaceLanes& s) {
  std::array<float*, kAttributeSlots> planes{};
  for (std::size_t k = 0; k < 3; ++k) {
    planes[k] = s.q[k].data();
    planes[3 + 3 * k] = s.ox[k].data();
    planes[4 + 3 * k] = s.oy[k].data();
    planes[5 + 3 * k] = s.oz[k].data();
    planes[12 + 3 * k] = s.nx[k].data();
    planes[13 + 3 * k] = s.ny[k].data();
    planes[14 + 3 * k] = s.nz[k].data();
  }
  for (std::size_t j = kAttributeFloats; j < planes.size(); ++j) planes[j] = s.spare.data();
  return planes;
}

static_assert(SurfaceLanes::kCapacity % 4 == 0);  // groups of four lanes write up to it

void gather_surface_lanes_target(const ScreenTriangle* const* triangles, const int* x, const int* y,
                                 std::size_t count, SurfaceLanes& s) {
#if HWY_TARGET == HWY_SCALAR
  for (std::size_t l = 0; l < count; ++l) s.set_lane(l, *triangles[l], x[l], y[l]);
#else
  namespace hn = hwy::HWY_NAMESPACE;
  const hn::FixedTag<float, 4> d;
  const hn::RebindToSigned<decltype(d)> di;
  const std::array<float*, kAttributeSlots> planes = attribute_planes(s);
  for (std::size_t l0 = 0; l0 < count; l0 += 4) {
    // A group short of four repeats its last lane; the lanes past `count` are never read.
    std::array<const ScreenTriangle*, 4> t{};
    std::array<int32_t, 4> px{}, py{};
    for (std::size_t i = 0; i < 4; ++i) {
      const std::size_t l = std::min(l0 + i, count - 1);
      t[i] = triangles[l];
      px[i] = x[l];
      py[i] = y[l];
    }
    // The positions: x0 x1 x2 y0 | y1 y2, then the double area's low and high halves. No
    // arrays of vectors: on some targets their constructors cannot be inlined here.
    const auto row = [&](std::size_t i, std::size_t half) {
      return hn::LoadU(di, reinterpret_cast<const int32_t*>(t[i]) + 4 * half);
    };
    auto x0 = row(0, 0), x1 = row(1, 0), x2 = row(2, 0), y0 = row(3, 0);
    auto y1 = row(0, 1), y2 = row(1, 1), area_low = row(2, 1), area_high = row(3, 1);
    transpose4(di, x0, x1, x2, y0);
    transpose4(di, y1, y2, area_low, area_high);
    hn::StoreU(int64_to_float(d, area_low, area_high), d, s.area.data() + l0);
    // The pixel centres in fixed point, as edge_numerators() takes them. Every difference
    // below stays within int32: positions are clamped to 2^24 in magnitude
    // (subpixel_position()) and centres lie within a frame of at most RasterView::kMaxSize.
    const auto half_pixel = hn::Set(di, static_cast<int32_t>(kSubpixelScale / 2));
    const auto cx = hn::Add(hn::ShiftLeft<kSubpixelBits>(hn::LoadU(di, px.data())), half_pixel);
    const auto cy = hn::Add(hn::ShiftLeft<kSubpixelBits>(hn::LoadU(di, py.data())), half_pixel);
    // Edge k runs from vertex a = k + 1 to b = k + 2, as edge_numerators() takes it.
    const auto edge = [&](std::size_t k, auto ax, auto ay, auto bx, auto by) {
      const auto dx = hn::Sub(bx, ax), dy = hn::Sub(by, ay);
      hn::StoreU(hn::ConvertTo(d, dy), d, s.edge_dy[k].data() + l0);
      hn::StoreU(hn::ConvertTo(d, dx), d, s.edge_dx[k].data() + l0);
      const auto numerator = cross_to_float(di, dx, hn::Sub(cy, ay), dy, hn::Sub(cx, ax));
      hn::StoreU(numerator, d, s.edge[k].data() + l0);
    };
    edge(0, x1, y1, x2, y2);
    edge(1, x2, y2, x0, y0);
    edge(2, x0, y0, x1, y1);
    for (std::size_t b = 0; b < kAttributeBlocks; ++b) {
      const auto attributes = [&](std::size_t i) {
        const char* from = reinterpret_cast<const char*>(t[i]) + offsetof(ScreenTriangle, inv_w);
        return hn::LoadU(d, reinterpret_cast<const float*>(from) + 4 * b);
      };
      auto c0 = attributes(0), c1 = attributes(1), c2 = attributes(2), c3 = attributes(3);
      transpose4(d, c0, c1, c2, c3);
      float* const* to = planes.data() + 4 * b;
      hn::StoreU(c0, d, to[0] + l0);
      hn::StoreU(c1, d, to[1] + l0);
      hn::StoreU(c2, d, to[2] + l0);
      hn::StoreU(c3, d, to[3] + l0);
    }
  }
#endif
}

void interpolate_surfaces_target(SurfaceLanes& lanes, std::size_t count) {
  interpolate(GatheredTerms{lanes}, lanes, count);
}

}  // namespace soltex::raster_internal::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex::raster_internal {

HWY_EXPORT(draw_unclipped_target);
HWY_EXPORT(draw_small_target);
HWY_EXPORT(draw_bin_target);
HWY_EXPORT(resolve_surface_runs_target);
HWY_EXPORT(interpolate_surfaces_target);
HWY_EXPORT(gather_surface_lanes_target);
HWY_EXPORT(run_starts_target);

void draw_unclipped(const ScreenTriangle& t, const SpanDraw& span, float* depth,
                    const ScreenTriangle** winner, RasterStats& stats) {
  HWY_DYNAMIC_DISPATCH(draw_unclipped_target)(t, span, depth, winner, stats);
}

void draw_small(const ScreenTriangle& t, const SpanDraw& span, float* depth,
                const ScreenTriangle** winner, RasterStats& stats) {
  HWY_DYNAMIC_DISPATCH(draw_small_target)(t, span, depth, winner, stats);
}

void draw_bin(const BinDraw& bin, float* depth, const ScreenTriangle** winner, RasterStats& stats) {
  HWY_DYNAMIC_DISPATCH(draw_bin_target)(bin, depth, winner, stats);
}

uint64_t run_starts(const ScreenTriangle* const* winners, int count) {
  return HWY_DYNAMIC_DISPATCH(run_starts_target)(winners, count);
}

int64_t tile_kernels_compiled_targets() {
  return HWY_TARGETS;
}

void gather_surface_lanes(const ScreenTriangle* const* triangles, const int* x, const int* y,
                          std::size_t count, SurfaceLanes& lanes) {
  assert(count <= SurfaceLanes::kCapacity);
  HWY_DYNAMIC_DISPATCH(gather_surface_lanes_target)(triangles, x, y, count, lanes);
}

void interpolate_surfaces(SurfaceLanes& lanes, std::size_t count) {
  HWY_DYNAMIC_DISPATCH(interpolate_surfaces_target)(lanes, count);
}

void resolve_surface_runs(std::span<const SurfaceRun> runs, const GBufferPlanes& target) {
  HWY_DYNAMIC_DISPATCH(resolve_surface_runs_target)(runs.data(), runs.size(), target);
}

}  // namespace soltex::raster_internal
#endif
