#pragma once

#include <array>
#include <cstdint>
#include <glm/vec2.hpp>
#include <span>
#include <vector>

#include "screen_triangle.h"
#include "soltex/raster/edge_surfaces.h"
#include "tile_rasterizer.h"

// Sub-pixel visibility at a tile's edge pixels: the tile's triangles drawn again, in the same
// order, into N x N samples of those pixels only (plus each pixel's centre, which sees what the
// frame's G-buffer holds there), with the same integer edge functions, top-left rule, float
// depth, clip forms and strict depth test as TileRasterizer; then each pixel's samples grouped
// by the triangle they see. A triangle whose bounds reach no edge pixel costs a few compares.
namespace soltex::raster_internal {

class EdgeSampler {
 public:
  static constexpr int kMaxGrid = kMaxEdgeGrid;

  // Starts the tile of pixels [x0, x1) x [y0, y1) with its edge pixels (frame positions inside
  // the tile, each once), `grid` x `grid` samples each (1..kMaxGrid).
  // `beyond_planes`: as TileRasterizer::begin()'s, so that a sample past the kept region of a
  // solid cut by several planes sees the solid's cap as the tile's pixels do.
  void begin(int x0, int y0, int x1, int y1, std::span<const glm::ivec2> pixels, int grid,
             uint32_t beyond_planes = 0);

  // Draws the triangle's samples at the edge pixels (a triangle binned into this tile).
  void draw(const ScreenTriangle& triangle, std::span<const AffineForm> clip_forms);

  // Groups each edge pixel's samples into surfaces and writes them to `out` (its layers resized
  // to the tile).
  void resolve(const TileFrame& frame, EdgeSurfaces& out) const;

  // Sample s of a pixel, s < grid * grid, in row-major order: its offset from the pixel's
  // top-left corner, in fixed-point units (1 / kSubpixelScale of a pixel).
  static glm::ivec2 sample_offset(int s, int grid);

 private:
  struct Surface {
    const ScreenTriangle* triangle = nullptr;
    int count = 0;
    int sum_x = 0, sum_y = 0;  // of the samples' offsets, for the middle of the group
  };
  std::size_t slot_sample(std::size_t slot, int s) const {
    return slot * static_cast<std::size_t>(samples_) + static_cast<std::size_t>(s);
  }
  void draw_at(const ScreenTriangle& t, const AffineForm* forms, int x, int y, std::size_t slot);
  // Depth and clip tests of sample s of the pixel in `slot` (at pixel x, y) for `t`.
  void test_sample(const ScreenTriangle& t, const AffineForm* forms, int x, int y, std::size_t slot,
                   int s);
  // What sample s sees: its kept fragment, else a back face past the kept region (whose
  // solid's cap it may see), else nothing.
  const ScreenTriangle* seen(std::size_t slot, int s) const;
  int group(std::size_t slot, std::array<Surface, EdgePixel::kExtraSurfaces>& extra,
            EdgePixel& pixel) const;
  int nearest_sample(std::size_t slot, const Surface& surface) const;

  int x0_ = 0, y0_ = 0, x1_ = 0, y1_ = 0;
  int grid_ = 1;
  int samples_ = 2;                             // grid * grid, and the centre last
  std::array<uint64_t, kTileSize> row_mask_{};  // bit x - x0: pixel (x, y0 + row) is an edge pixel
  uint64_t rows_ = 0;                           // bit y - y0: row y holds an edge pixel
  uint64_t columns_ = 0;                        // bit x - x0: column x holds one
  std::array<int32_t, kTileSize * kTileSize> slot_{};  // the edge pixel's index, at its pixels
  std::vector<glm::ivec2> pixels_;
  std::vector<glm::ivec2> offsets_;    // per sample, fixed point from the pixel's corner
  std::vector<glm::vec2> offsets_px_;  // the same in pixels, as float
  std::vector<float> depth_;           // per slot and sample
  std::vector<const ScreenTriangle*> winner_;
  uint32_t beyond_planes_ = 0;
  std::vector<float> beyond_depth_;  // per slot and sample, where beyond_planes_ is not 0
  std::vector<const ScreenTriangle*> beyond_winner_;
};

}  // namespace soltex::raster_internal
