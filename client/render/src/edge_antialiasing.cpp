#include "edge_antialiasing.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "lit_pixels.h"
#include "tile_shader.h"

namespace soltex::render {

namespace {

constexpr int kTileSize = Rasterizer::kTileSize;
constexpr uint32_t kNoSurface = 0xffffffffu;

// The background as the frame writes it (Image::set() of kBackground).
std::array<uint8_t, 3> background_bytes() {
  Image one(1, 1);
  one.set(0, 0, kBackground.r, kBackground.g, kBackground.b);
  return {one.rgb[0], one.rgb[1], one.rgb[2]};
}

}  // namespace

void find_edge_pixels(const GBuffer& g, int origin_x, int origin_y, int x0, int y0, int x1, int y1,
                      float near, float far, std::vector<glm::ivec2>& out) {
  const int width = x1 - x0, height = y1 - y0;
  // The tile's surfaces and depths with a border of one pixel all round, so that every pixel
  // has four neighbours: the border repeats the surface beside it (no change of surface across
  // the tile's edge) and extends the depth linearly (no second difference either).
  constexpr int kStride = kTileSize + 2;
  std::array<uint32_t, kStride * kStride> key;
  std::array<float, kStride * kStride> depth;
  const auto at = [](int px, int py) { return static_cast<std::size_t>(py * kStride + px); };
  uint8_t drawn = 0;  // most tiles around one object are empty: a quick look first
  for (int ly = 0; ly < height; ++ly) {
    const uint8_t* flags = g.flags.data() + g.index(x0 - origin_x, y0 + ly - origin_y);
    for (int lx = 0; lx < width; ++lx) drawn |= flags[lx];
  }
  if ((drawn & GBuffer::kCovered) == 0) return;
  for (int ly = 0; ly < height; ++ly) {
    const std::size_t first = g.index(x0 - origin_x, y0 + ly - origin_y);
    const uint8_t* flags = g.flags.data() + first;
    const uint32_t* object = g.object_id.data() + first;
    uint32_t* keys = key.data() + at(1, ly + 1);
    for (int lx = 0; lx < width; ++lx) {
      const uint8_t f = flags[lx];
      const uint32_t sides = static_cast<uint32_t>(f & (GBuffer::kBackFace | GBuffer::kCap)) >> 1;
      keys[lx] = (f & GBuffer::kCovered) != 0 ? (object[lx] << 2) | sides : kNoSurface;
    }
    std::copy_n(g.depth.data() + first, width, depth.data() + at(1, ly + 1));
  }
  const auto extend = [&](std::size_t pad, std::size_t edge, std::size_t inner, bool has_inner) {
    key[pad] = key[edge];
    depth[pad] = has_inner ? 2.0f * depth[edge] - depth[inner] : depth[edge];
  };
  for (int py = 1; py <= height; ++py) {
    extend(at(0, py), at(1, py), at(2, py), width > 1);
    extend(at(width + 1, py), at(width, py), at(width - 1, py), width > 1);
  }
  for (int px = 0; px <= width + 1; ++px) {
    extend(at(px, 0), at(px, 1), at(px, 2), height > 1);
    extend(at(px, height + 1), at(px, height), at(px, height - 1), height > 1);
  }
  // Inverse view depth 1/d = (far - z (far - near)) / (far near) is affine on screen across a
  // plane, as window depth z is; its second difference relative to 1/d at the pixel, above
  // kDepthBreak, is a fold or a jump in the surface, not its slope.
  const float span = far - near;
  std::array<uint8_t, kTileSize> edge_row;
  for (int py = 1; py <= height; ++py) {
    // Selects, not branches: the loop runs in vector lanes.
    for (int px = 1; px <= width; ++px) {
      const std::size_t i = at(px, py);
      const uint32_t k = key[i];
      const bool changes =
          (k != key[i - 1]) | (k != key[i + 1]) | (k != key[i - kStride]) | (k != key[i + kStride]);
      const float z = depth[i];
      const float along_x = std::fabs((depth[i - 1] + depth[i + 1]) - 2.0f * z);
      const float along_y = std::fabs((depth[i - kStride] + depth[i + kStride]) - 2.0f * z);
      const float second = along_x < along_y ? along_y : along_x;
      const bool fold = (second * span > kDepthBreak * (far - z * span)) & (k != kNoSurface);
      edge_row[static_cast<std::size_t>(px - 1)] = static_cast<uint8_t>(changes | fold);
    }
    for (int lx = 0; lx < width; ++lx) {
      if (edge_row[static_cast<std::size_t>(lx)] != 0) out.emplace_back(x0 + lx, y0 + py - 1);
    }
  }
}

void blend_edge_pixel(const EdgePixel& pixel, int sample_count, const uint8_t* centre,
                      const uint8_t* background,
                      const std::array<const uint8_t*, EdgePixel::kExtraSurfaces>& extra,
                      uint8_t* out) {
  const auto count = static_cast<unsigned>(sample_count);
  std::array<unsigned, 3> sum{};
  for (std::size_t c = 0; c < 3; ++c) {
    sum[c] = pixel.centre * unsigned{centre[c]} + pixel.background * unsigned{background[c]};
    for (std::size_t j = 0; j < extra.size(); ++j) {
      if (pixel.extra[j] > 0) sum[c] += pixel.extra[j] * unsigned{extra[j][c]};
    }
  }
  for (std::size_t c = 0; c < 3; ++c) {
    out[c] = static_cast<uint8_t>((2 * sum[c] + count) / (2 * count));
  }
}

void EdgeAntialiasing::begin_frame(int width, int height, double near, double far, int grid,
                                   int threads) {
  near_ = static_cast<float>(near);
  far_ = static_cast<float>(far);
  grid_ = grid;
  if (layer_.width != width || layer_.height != height) layer_ = Image(width, height);
  workers_.resize(static_cast<std::size_t>(threads));
  for (Worker& worker : workers_) worker.blended = 0;
}

std::size_t EdgeAntialiasing::blended() const {
  std::size_t blended = 0;
  for (const Worker& worker : workers_) blended += worker.blended;
  return blended;
}

void EdgeAntialiasing::antialias_tile(Rasterizer& rasterizer, TileShader& shader, const GBuffer& g,
                                      int origin_x, int origin_y, int x0, int y0, int x1, int y1,
                                      int worker_index, Image& image) {
  Worker& worker = workers_[static_cast<std::size_t>(worker_index)];
  worker.pixels.clear();
  find_edge_pixels(g, origin_x, origin_y, x0, y0, x1, y1, near_, far_, worker.pixels);
  if (worker.pixels.empty()) return;
  rasterizer.sample_edges(x0, y0, worker.pixels, grid_, worker_index, worker.surfaces);
  const EdgeSurfaces& surfaces = worker.surfaces;
  if (surfaces.pixels.empty()) return;
  // The extra surfaces are the same pixels again: the frame's counts stay those of its pixels.
  const TileCounts counted = shader.counts();
  shade_layers(shader, worker);
  const std::chrono::steady_clock::duration shading = shader.counts().shading;
  shader.counts() = counted;
  shader.counts().shading = shading;
  static const std::array<uint8_t, 3> background = background_bytes();
  for (std::size_t p = 0; p < surfaces.pixels.size(); ++p) {
    const EdgePixel& pixel = surfaces.pixels[p];
    std::array<const uint8_t*, EdgePixel::kExtraSurfaces> extra{};
    for (std::size_t j = 0; j < extra.size(); ++j) extra[j] = worker.colours[p].data() + 3 * j;
    uint8_t* out = image.pixel(pixel.x, pixel.y);
    blend_edge_pixel(pixel, surfaces.sample_count, out, background.data(), extra, out);
  }
  worker.blended += surfaces.pixels.size();
}

// Each layer's surfaces shaded at their pixels, then their colours copied out per pixel.
void EdgeAntialiasing::shade_layers(TileShader& shader, Worker& worker) {
  const EdgeSurfaces& surfaces = worker.surfaces;
  worker.colours.resize(surfaces.pixels.size());
  for (std::size_t j = 0; j < EdgePixel::kExtraSurfaces; ++j) {
    worker.layer_pixels.clear();
    for (const EdgePixel& p : surfaces.pixels) {
      if (p.extra[j] > 0) worker.layer_pixels.emplace_back(p.x, p.y);
    }
    if (worker.layer_pixels.empty()) break;  // a pixel's surfaces fill layers in order
    shader.shade_pixels(surfaces.layers[j], surfaces.x0, surfaces.y0, worker.layer_pixels, layer_);
    for (std::size_t p = 0; p < surfaces.pixels.size(); ++p) {
      const EdgePixel& pixel = surfaces.pixels[p];
      if (pixel.extra[j] == 0) continue;
      std::memcpy(worker.colours[p].data() + 3 * j, layer_.pixel(pixel.x, pixel.y), 3);
    }
  }
}

}  // namespace soltex::render
