#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>

#include "screen_triangle.h"
#include "soltex/raster/gbuffer.h"
#include "soltex/raster/raster_stats.h"

// The per-pixel loops of drawing and resolving a tile, dispatched at run time to the widest
// vector target the CPU has (tile_kernels.cpp). Each is plain per-lane arithmetic that the
// compiler runs in vector lanes; every target does the same operations in the same order per
// lane, so each gives the same bits (and the same winners) as the baseline build.
namespace soltex::raster_internal {

// One triangle over rows [first_y, last_y] and columns [first_x, last_x] of a tile whose
// pixel (tile_x0, tile_y0) is at depth[0] and winner[0] (rows kTileSize apart), without clip
// forms or coverage counts: a pixel whose centre is inside (edge functions `row` at
// (first_x, first_y), stepped by step_x and step_y), nearer than the stored depth and not
// beyond the far plane takes the triangle's depth and becomes its winner.
struct SpanDraw {
  int first_x, last_x, first_y, last_y;
  int tile_x0, tile_y0;
  std::array<int64_t, 3> row, step_x, step_y;
};
void draw_unclipped(const ScreenTriangle& t, const SpanDraw& span, float* depth,
                    const ScreenTriangle** winner, RasterStats& stats);

// The same for a small triangle (extents of at most kSmallExtent, fits_int32()), its edge
// functions in 32-bit lanes: exact there, so the same fragments win as in the 64-bit loops.
// The planes must hold kPlanePadding elements past the tile's last pixel (read, and written
// back unchanged).
inline constexpr int kSmallLanes = 8;
void draw_small(const ScreenTriangle& t, const SpanDraw& span, float* depth,
                const ScreenTriangle** winner, RasterStats& stats);

// The pixels of the tile [tile_x0, tile_x1) x [tile_y0, tile_y1) that `t` may cover, and its edge
// functions at the first of them, as TileRasterizer::draw() steps them; false when its bounds
// miss the tile.
inline bool span_of(const ScreenTriangle& t, int tile_x0, int tile_y0, int tile_x1, int tile_y1,
                    SpanDraw& span) {
  span.first_x = std::max(t.min_px, tile_x0);
  span.last_x = std::min(t.max_px, tile_x1 - 1);
  span.first_y = std::max(t.min_py, tile_y0);
  span.last_y = std::min(t.max_py, tile_y1 - 1);
  if (span.first_x > span.last_x || span.first_y > span.last_y) return false;
  span.tile_x0 = tile_x0;
  span.tile_y0 = tile_y0;
  const int64_t px = int64_t{span.first_x} * kSubpixelScale + kSubpixelScale / 2;
  const int64_t py = int64_t{span.first_y} * kSubpixelScale + kSubpixelScale / 2;
  for (std::size_t k = 0; k < 3; ++k) {
    // Edge k, opposite vertex k; the top-left rule as a bias: a centre on a top or left edge
    // (value 0) is in, on any other edge it is out.
    const std::size_t a = (k + 1) % 3, b = (k + 2) % 3;
    const int64_t ax = t.x[a], ay = t.y[a], bx = t.x[b], by = t.y[b];
    const int64_t bias = is_top_left(ax, ay, bx, by) ? 0 : -1;
    span.row[k] = edge_function(ax, ay, bx, by, px, py) + bias;
    span.step_x[k] = -(by - ay) * kSubpixelScale;
    span.step_y[k] = (bx - ax) * kSubpixelScale;
  }
  return true;
}

// Whether every edge function of `t` (with its top-left bias) stays within int32 at the pixel
// centres of its bounds and up to kSmallLanes - 1 pixels right of them: each is a sum of two
// products of coordinate differences, each within the triangle's extent (or that extent and
// the lanes past it), so extents of at most 64 pixels bound it by (64 + 71) * 64 * 2^16 < 2^30.
inline constexpr int64_t kSmallExtent = 64 * kSubpixelScale;
inline constexpr int64_t kSmallEdgeBound =
    kSmallExtent * kSmallExtent +
    kSmallExtent * (kSmallExtent + (kSmallLanes - 1) * kSubpixelScale);
static_assert(kSmallEdgeBound < INT32_MAX);
inline bool fits_int32(const ScreenTriangle& t) {
  const auto [min_x, max_x] = std::minmax({t.x[0], t.x[1], t.x[2]});
  const auto [min_y, max_y] = std::minmax({t.y[0], t.y[1], t.y[2]});
  return int64_t{max_x} - min_x <= kSmallExtent && int64_t{max_y} - min_y <= kSmallExtent;
}

// A tile's bin of one chunk: triangles[items[0 .. count)], drawn in that order as
// TileRasterizer::draw() draws each (without coverage counts); those draw_small() cannot take
// (a clip form to test, or too large for int32 edges) go to other(context, triangle).
struct BinDraw {
  const ScreenTriangle* triangles;
  const uint32_t* items;
  std::size_t count;
  int tile_x0, tile_y0, tile_x1, tile_y1;
  void (*other)(void* context, const ScreenTriangle& t);
  void* context;
};
// Triangles ahead whose first line is asked for: a tile's triangles lie scattered over the chunk.
inline constexpr std::size_t kBinPrefetchAhead = 8;
void draw_bin(const BinDraw& bin, float* depth, const ScreenTriangle** winner, RasterStats& stats);

// A footprint whose short side came out NaN (derivatives of absurd inputs) has no direction:
// its pixel takes one tap, as a cap's does.
inline bool no_direction(float minor) {
  return minor != minor;
}

// The G-buffer's planes as raw pointers, taken once per tile: a store through uint8_t* (the
// flags) may alias anything, so through the vectors every store would reload every data pointer.
struct GBufferPlanes {
  explicit GBufferPlanes(GBuffer& g)
      : depth(g.depth.data()),
        flags(g.flags.data()),
        object_id(g.object_id.data()),
        texture_position(g.texture_position.data()),
        normal(g.normal.data()),
        footprint(g.footprint.data()),
        footprint_axis(g.footprint_axis.data()),
        footprint_minor(g.footprint_minor.data()) {}

  float* depth;
  uint8_t* flags;
  uint32_t* object_id;
  glm::dvec3* texture_position;
  glm::vec3* normal;
  float* footprint;
  glm::vec3* footprint_axis;
  float* footprint_minor;
};

// One triangle's data for interpolating its attributes, in float (see
// resolve_surface_runs_target in tile_kernels.cpp): the double area; per vertex k, 1/w, the
// texture offset and the normal; per edge k (opposite vertex k), its steps.
struct TriangleTerms {
  float area;
  std::array<float, 3> q, ox, oy, oz, nx, ny, nz, edge_dy, edge_dx;
};

inline TriangleTerms triangle_terms(const ScreenTriangle& t) {
  TriangleTerms terms;
  terms.area = static_cast<float>(t.double_area);
  for (std::size_t k = 0; k < 3; ++k) {
    // Edge k runs from vertex k + 1 to vertex k + 2 (as drawing takes it).
    const std::size_t a = (k + 1) % 3, b = (k + 2) % 3;
    terms.edge_dy[k] = static_cast<float>(int64_t{t.y[b]} - int64_t{t.y[a]});
    terms.edge_dx[k] = static_cast<float>(int64_t{t.x[b]} - int64_t{t.x[a]});
    terms.q[k] = t.inv_w[k];
    terms.ox[k] = t.texture_offset[k].x;
    terms.oy[k] = t.texture_offset[k].y;
    terms.oz[k] = t.texture_offset[k].z;
    terms.nx[k] = t.normal[k].x;
    terms.ny[k] = t.normal[k].y;
    terms.nz[k] = t.normal[k].z;
  }
  return terms;
}

// Vertex k's barycentric numerator, the edge function opposite it, at pixel (x, y)'s centre:
// an exact integer.
inline std::array<int64_t, 3> edge_numerators(const ScreenTriangle& t, int x, int y) {
  const int64_t px = int64_t{x} * kSubpixelScale + kSubpixelScale / 2;
  const int64_t py = int64_t{y} * kSubpixelScale + kSubpixelScale / 2;
  std::array<int64_t, 3> e{};
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t a = (k + 1) % 3, b = (k + 2) % 3;
    e[k] = edge_function(t.x[a], t.y[a], t.x[b], t.y[b], px, py);
  }
  return e;
}

// The attributes of up to kCapacity pixels each of its own triangle (the pixels of short
// runs), perspective-correct as resolve_surface_runs() computes them: the lanes' inputs,
// gathered from each pixel's triangle, and their results.
struct SurfaceLanes {
  static constexpr int kCapacity = 64;
  template <typename T>
  using Lanes = std::array<T, kCapacity>;

  // In: vertex k's barycentric numerator at the pixel centre, edge k's steps, the double
  // area; vertex k's 1/w, texture offset and normal.
  alignas(64) std::array<Lanes<float>, 3> edge, edge_dy, edge_dx;
  alignas(64) Lanes<float> area;
  alignas(64) std::array<Lanes<float>, 3> q, ox, oy, oz, nx, ny, nz;
  // Out: the texture offset from the triangle's origin, the footprint (and its long side's
  // vector, its short side's length), the unit normal.
  alignas(64) Lanes<float> offset_x, offset_y, offset_z, footprint, normal_x, normal_y, normal_z;
  alignas(64) Lanes<float> axis_x, axis_y, axis_z, minor;

  // Lane l's inputs: pixel (x, y) of triangle t. The definition that gather_surface_lanes()
  // computes for many lanes at once.
  void set_lane(std::size_t l, const ScreenTriangle& t, int x, int y) {
    const TriangleTerms terms = triangle_terms(t);
    const std::array<int64_t, 3> numerators = edge_numerators(t, x, y);
    for (std::size_t k = 0; k < 3; ++k) {
      edge[k][l] = static_cast<float>(numerators[k]);
      edge_dy[k][l] = terms.edge_dy[k];
      edge_dx[k][l] = terms.edge_dx[k];
      q[k][l] = terms.q[k];
      ox[k][l] = terms.ox[k];
      oy[k][l] = terms.oy[k];
      oz[k][l] = terms.oz[k];
      nx[k][l] = terms.nx[k];
      ny[k][l] = terms.ny[k];
      nz[k][l] = terms.nz[k];
    }
    area[l] = terms.area;
  }

  // Receives the floats a block read past the normals (gather_surface_lanes()).
  alignas(64) Lanes<float> spare;
};

// set_lane(l, *triangles[l], x[l], y[l]) for every lane l < count (count <= kCapacity): the
// same bits, four lanes at a time. Each triangle's positions, area and attributes are read as
// blocks of four values and transposed, instead of loaded and stored one by one, and the edge
// numerators are computed in lanes; lanes from count up to the next multiple of four may be
// written too (interpolate_surfaces() ignores them).
void gather_surface_lanes(const ScreenTriangle* const* triangles, const int* x, const int* y,
                          std::size_t count, SurfaceLanes& lanes);
void interpolate_surfaces(SurfaceLanes& lanes, std::size_t count);

// The runs of one row of a tile's winners (count <= 64 pixels): bit i is set where pixel i
// sees another triangle (or none) than pixel i - 1; bit 0 always. The plane must hold
// kPlanePadding elements past the row's last pixel (read and ignored).
uint64_t run_starts(const ScreenTriangle* const* winners, int count);

// For tests: the Highway targets compiled into tile_kernels.cpp.
int64_t tile_kernels_compiled_targets();

// Pixels of one row of a tile that all see the same triangle (no cap): resolved together, so
// that the triangle's data is read once per run rather than once per pixel, and the
// arithmetic runs across the run's pixels in vector lanes.
struct SurfaceRun {
  const ScreenTriangle* triangle;
  int x, y;            // the first pixel, in the frame
  int count;           // pixels, at most kTileSize
  std::size_t target;  // the first pixel's index in the target planes
  const float* depth;  // the run's window depths, as drawn
  uint32_t object_id;  // GBuffer::object_id
  uint8_t flags;       // GBuffer::flags
};

// Writes each run's pixels to `target`: depth, flags and object as given, and the triangle's
// attributes perspective-correct at each pixel centre (see resolve_surface_runs_target in
// tile_kernels.cpp).
void resolve_surface_runs(std::span<const SurfaceRun> runs, const GBufferPlanes& target);

}  // namespace soltex::raster_internal
