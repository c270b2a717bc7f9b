#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "soltex/raster/gbuffer.h"

// What covers each sub-pixel sample of chosen pixels (edge pixels: silhouettes, depth and object
// boundaries) of a rendered frame, grouped into surfaces: the frame shades each pixel once, at
// its centre, and an edge pixel's colour becomes the coverage-weighted average of the colours of
// the few surfaces its samples see, each shaded once (as MSAA resolves, but only where the
// centre sample does not speak for the whole pixel).
namespace soltex {

// Samples per axis of an edge pixel: 1 to this.
inline constexpr int kMaxEdgeGrid = 8;

// One edge pixel: of its N x N samples, how many see the surface its centre sees (shaded by the
// frame already), how many see nothing (the background; zero when the centre sees nothing,
// whose group already holds them), and how many each extra surface, drawn in layer j of
// EdgeSurfaces at this pixel.
struct EdgePixel {
  static constexpr int kExtraSurfaces = 3;
  int x = 0, y = 0;  // in the frame
  uint16_t centre = 0;
  uint16_t background = 0;
  std::array<uint16_t, kExtraSurfaces> extra{};
};

// The edge pixels of one raster tile, pixels [x0, x1) x [y0, y1) of the frame.
struct EdgeSurfaces {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int sample_count = 0;  // N * N: what each pixel's counts add up to
  std::vector<EdgePixel> pixels;
  // Tile-sized (Rasterizer::kTileSize on a side): the frame's pixel (x, y) at index(x - x0,
  // y - y0). Layer j is covered exactly at the pixels with an extra surface j, and holds that
  // surface's attributes at the sample nearest the middle of its samples (its depth, normal,
  // texture position; a cap where the surface is a cap). Elsewhere only `flags` (zero) and
  // `object_id` (GBuffer::kNoObject) are written.
  std::array<GBuffer, EdgePixel::kExtraSurfaces> layers;
};

}  // namespace soltex
