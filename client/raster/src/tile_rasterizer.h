#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "cap_tracer.h"
#include "object_frame.h"
#include "screen_triangle.h"
#include "soltex/raster/gbuffer.h"
#include "soltex/raster/raster_stats.h"

// Rasterizing into one tile, then resolving it into the G-buffer.
//
// Drawing keeps only depth and the winning triangle per pixel (a visibility buffer), so the
// attributes (texture position, normal, footprint; or a traced cap) are computed once per
// pixel, for the surface that is finally seen, however many triangles were drawn over it.
// One TileRasterizer per thread; a tile is drawn by one thread only.
namespace soltex::raster_internal {

inline constexpr int kTileSize = 64;
// Elements past a tile's last pixel in its depth and winner planes: run_starts() and
// draw_small() read up to seven past a row's end, a vector's worth (tile_kernels.h).
inline constexpr std::size_t kPlanePadding = 7;

// What resolving needs of the frame.
struct TileFrame {
  std::span<const ObjectFrame> objects;
  const CapTracer* caps = nullptr;  // null when the frame has no clip planes
};

class TileRasterizer {
 public:
  // Starts the tile of pixels [x0, x1) x [y0, y1), at most kTileSize on a side.
  // `beyond_planes`: the frame's objects' ObjectFrame::beyond_planes together; where it is not
  // 0, the tile also keeps each pixel's nearest fragment cut away by those planes alone.
  void begin(int x0, int y0, int x1, int y1, uint32_t beyond_planes = 0);

  // Draws the triangle's pixels in this tile. `clip_forms`: the frame's clip-form array of the
  // triangle's chunk (used when triangle.clip_mask != 0). `coverage`: the G-buffer's coverage
  // counts, or null.
  void draw(const ScreenTriangle& triangle, std::span<const AffineForm> clip_forms,
            uint32_t* coverage, int coverage_stride, RasterStats& stats);

  // draw() of triangles[items[k]] for each k in order: a tile's bin of one chunk. The small
  // triangles of a fine mesh are drawn in one dispatched loop, without draw()'s call and
  // set-up per triangle.
  void draw_bin(const ScreenTriangle* triangles, std::span<const uint32_t> items,
                std::span<const AffineForm> clip_forms, uint32_t* coverage, int coverage_stride,
                RasterStats& stats);

  // Writes every pixel of the tile to `target`, whose pixel (x, y) of the frame is at
  // target.index(x - origin_x, y - origin_y): the frame's G-buffer (origin 0, 0), or a
  // tile-sized one (origin x0, y0).
  void resolve(const TileFrame& frame, GBuffer& target, int origin_x, int origin_y,
               RasterStats& stats) const;

  // Whether the tile drawn last starts at pixel (x0, y0).
  bool began_at(int x0, int y0) const { return x0_ == x0 && y0_ == y0; }

 private:
  // Whether a fragment at tile pixel `pixel` is nearer than slot 0's, or than slot 1's and of
  // another object than slot 0's (the two slots below).
  bool beyond_nearer(std::size_t pixel, float depth, const ScreenTriangle& t) const;
  // Keeps such a fragment in its slot.
  void keep_beyond(std::size_t pixel, float depth, const ScreenTriangle& t);
  // Slot `slot`'s row from tile pixel `from`, or null where nothing is kept past the region.
  const ScreenTriangle* const* beyond_row(int slot, std::ptrdiff_t from) const;

  int x0_ = 0, y0_ = 0, x1_ = 0, y1_ = 0;
  std::array<float, kTileSize * kTileSize + kPlanePadding> depth_{};
  std::array<const ScreenTriangle*, kTileSize * kTileSize + kPlanePadding> winner_{};
  // Where beyond_planes_ is not 0: per pixel, the nearest fragment of an object with beyond
  // planes, kept or past the kept region (cut away by planes keeping the eye, and by no
  // other), in slot 0, and the nearest of another object than that one in slot 1. A back face
  // there means the ray crossed the kept region inside that solid, which then shows a cap
  // where the ray entered the region, unless what the pixel keeps lies in front of it. Two
  // slots: one object's cut-away part in front of another's solid would otherwise hide the
  // other's back face.
  uint32_t beyond_planes_ = 0;
  std::array<std::array<float, kTileSize * kTileSize>, 2> beyond_depth_{};
  std::array<std::array<const ScreenTriangle*, kTileSize * kTileSize>, 2> beyond_winner_{};
};

}  // namespace soltex::raster_internal
