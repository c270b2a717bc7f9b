#pragma once

#include <array>
#include <cstdint>
#include <glm/vec2.hpp>
#include <memory>
#include <vector>

#include "soltex/raster/edge_surfaces.h"
#include "soltex/raster/gbuffer.h"
#include "soltex/raster/rasterizer.h"
#include "soltex/render/image.h"

// Edge anti-aliasing (RenderOptions::edge_antialias): the frame is drawn and shaded one sample
// per pixel as always; then only the pixels where that one sample cannot speak for the whole
// pixel get N x N coverage samples. Those are the pixels beside a change of surface (object,
// facing, cap) or a break in depth, found from what each pixel's centre sees. Their samples
// are grouped by surface (Rasterizer::sample_edges()), each extra surface shaded once, and the
// pixel becomes the coverage-weighted average of its surfaces' colours. Textures are already
// filtered over each pixel's footprint; what one sample per pixel gets wrong is geometry, and
// that lives at the edges, a few percent of the covered pixels.
namespace soltex::render {

class TileShader;

// The edge pixels of the G-buffer tile's pixels [x0, x1) x [y0, y1) (pixel (x, y) at
// g.index(x - origin_x, y - origin_y)), appended to `out` in row order: those beside (left,
// right, above, below, within the tile) a pixel whose centre sees another surface (object,
// facing, cap, or nothing), and those at a break in depth: the second difference of window
// depth (affine on screen across any one plane) along x or y, relative to the pixel's inverse
// view depth, above kDepthBreak; `near` and `far` are the camera's. Within the tile only: the
// frame's tiles are drawn in any order, and a change of surface right on a tile's border is
// seen from the pixels beside it inside each tile, unless it runs along the border.
inline constexpr float kDepthBreak = 0.05f;
void find_edge_pixels(const GBuffer& g, int origin_x, int origin_y, int x0, int y0, int x1, int y1,
                      float near, float far, std::vector<glm::ivec2>& out);

// An edge pixel's colour: its surfaces' 8-bit colours weighted by their sample counts (the
// centre's colour, the background's, the extra surfaces'), averaged and rounded half up as
// box_downsample() averages sub-pixels.
void blend_edge_pixel(const EdgePixel& pixel, int sample_count, const uint8_t* centre,
                      const uint8_t* background,
                      const std::array<const uint8_t*, EdgePixel::kExtraSurfaces>& extra,
                      uint8_t* out);

class EdgeAntialiasing {
 public:
  // Starts a frame of width x height pixels, drawn with the camera's near and far planes, with
  // grid x grid samples at each edge pixel, over `threads` render threads.
  void begin_frame(int width, int height, double near, double far, int grid, int threads);

  // Right after the raster tile of pixels [x0, x1) x [y0, y1) is shaded from `g` (pixel (x, y)
  // at g.index(x - origin_x, y - origin_y)) into `image`, on the render thread `worker` that
  // drew it: its edge pixels resampled (Rasterizer::sample_edges()), their extra surfaces
  // shaded by `shader`, and blended into `image`.
  void antialias_tile(Rasterizer& rasterizer, TileShader& shader, const GBuffer& g, int origin_x,
                      int origin_y, int x0, int y0, int x1, int y1, int worker, Image& image);

  // Pixels blended this frame.
  std::size_t blended() const;

 private:
  struct Worker {
    std::vector<glm::ivec2> pixels;
    std::vector<glm::ivec2> layer_pixels;
    EdgeSurfaces surfaces;
    std::vector<std::array<uint8_t, 3 * EdgePixel::kExtraSurfaces>> colours;
    std::size_t blended = 0;
  };
  void shade_layers(TileShader& shader, Worker& worker);

  float near_ = 0.1f, far_ = 100.0f;
  int grid_ = 4;
  Image layer_;  // extra surfaces shaded here, at their pixels
  std::vector<Worker> workers_;
};

}  // namespace soltex::render
