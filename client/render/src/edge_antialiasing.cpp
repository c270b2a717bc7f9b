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
  std::array<uint32_t, kTileSize * kTileSize> key;
  std::array<float, kTileSize * kTileSize> depth;
  const auto at = [](int lx, int ly) { return static_cast<std::size_t>(ly * kTileSize + lx); };
  uint8_t drawn = 0;
  for (int ly = 0; ly < height; ++ly) {
    const std::size_t first = g.index(x0 - origin_x, y0 + ly - origin_y);
    const uint8_t* flags = g.flags.data() + first;
    const uint32_t* object = g.object_id.data() + first;
    const float* z = g.depth.data() + first;
    uint32_t* keys = key.data() + at(0, ly);
    for (int lx = 0; lx < width; ++lx) {
      const uint8_t f = flags[lx];
      const uint32_t sides = static_cast<uint32_t>(f & (GBuffer::kBackFace | GBuffer::kCap)) >> 1;
      keys[lx] = (f & GBuffer::kCovered) != 0 ? (object[lx] << 2) | sides : kNoSurface;
      drawn |= f;
    }
    std::copy_n(z, width, depth.data() + at(0, ly));
  }
  if ((drawn & GBuffer::kCovered) == 0) return;
  // Bit lx of mask[ly]: pixel (x0 + lx, y0 + ly) is an edge pixel.
  std::array<uint64_t, kTileSize> mask{};
  for (int ly = 0; ly < height; ++ly) {
    uint64_t right = 0, below = 0;  // bit lx: differs from the pixel right of it, below it
    for (int lx = 0; lx + 1 < width; ++lx) {
      right |= static_cast<uint64_t>(key[at(lx, ly)] != key[at(lx + 1, ly)]) << lx;
    }
    if (ly + 1 < height) {
      for (int lx = 0; lx < width; ++lx) {
        below |= static_cast<uint64_t>(key[at(lx, ly)] != key[at(lx, ly + 1)]) << lx;
      }
      mask[static_cast<std::size_t>(ly + 1)] |= below;
    }
    mask[static_cast<std::size_t>(ly)] |= right | (right << 1) | below;
  }
  // Inverse view depth 1/d = (far - z (far - near)) / (far near) is affine on screen across a
  // plane, as window depth z is; its second difference relative to 1/d at the pixel, above
  // kDepthBreak, is a fold or a jump in the surface, not its slope.
  const float span = far - near;
  const auto breaks = [&](float before, float here, float after) {
    const float second = (before + after) - 2.0f * here;
    return std::fabs(second) * span > kDepthBreak * (far - here * span);
  };
  for (int ly = 0; ly < height; ++ly) {
    uint64_t& row = mask[static_cast<std::size_t>(ly)];
    for (int lx = 0; lx < width; ++lx) {
      const std::size_t i = at(lx, ly);
      if (((row >> lx) & 1u) != 0 || key[i] == kNoSurface) continue;
      const float z = depth[i];
      const bool fold =
          (lx > 0 && lx + 1 < width && breaks(depth[i - 1], z, depth[i + 1])) ||
          (ly > 0 && ly + 1 < height && breaks(depth[i - kTileSize], z, depth[i + kTileSize]));
      row |= static_cast<uint64_t>(fold) << lx;
    }
  }
  for (int ly = 0; ly < height; ++ly) {
    for (uint64_t bits = mask[static_cast<std::size_t>(ly)]; bits != 0; bits &= bits - 1) {
      out.emplace_back(x0 + std::countr_zero(bits), y0 + ly);
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
  shade_layers(shader, worker, x1, y1);
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

// Each layer shaded where it holds surfaces: the rows of each 32 x 32 piece of the tile that
// hold one, then its colours copied out per pixel.
void EdgeAntialiasing::shade_layers(TileShader& shader, Worker& worker, int x1, int y1) {
  const EdgeSurfaces& surfaces = worker.surfaces;
  worker.colours.resize(surfaces.pixels.size());
  constexpr int kPiece = TileShader::kTile;
  constexpr int kPieces = kTileSize / kPiece;
  for (std::size_t j = 0; j < EdgePixel::kExtraSurfaces; ++j) {
    std::array<int, kPieces * kPieces> first{}, last{};
    first.fill(kTileSize);
    last.fill(-1);
    for (const EdgePixel& p : surfaces.pixels) {
      if (p.extra[j] == 0) continue;
      const int lx = p.x - surfaces.x0, ly = p.y - surfaces.y0;
      const auto piece = static_cast<std::size_t>((ly / kPiece) * kPieces + lx / kPiece);
      first[piece] = std::min(first[piece], ly);
      last[piece] = std::max(last[piece], ly);
    }
    for (std::size_t piece = 0; piece < first.size(); ++piece) {
      if (last[piece] < 0) continue;
      const int tx = surfaces.x0 + static_cast<int>(piece % kPieces) * kPiece;
      shader.shade(surfaces.layers[j], surfaces.x0, surfaces.y0, tx, surfaces.y0 + first[piece],
                   std::min(x1, tx + kPiece), std::min(y1, surfaces.y0 + last[piece] + 1), layer_);
    }
    for (std::size_t p = 0; p < surfaces.pixels.size(); ++p) {
      const EdgePixel& pixel = surfaces.pixels[p];
      if (pixel.extra[j] == 0) continue;
      std::memcpy(worker.colours[p].data() + 3 * j, layer_.pixel(pixel.x, pixel.y), 3);
    }
  }
}

}  // namespace soltex::render
