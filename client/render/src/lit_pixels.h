#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <vector>

#include "material_inputs.h"
#include "soltex/common/texture_sampler.h"
#include "soltex/raster/gbuffer.h"
#include "soltex/render/image.h"
#include "soltex/render/shading.h"

namespace soltex::render {

inline constexpr glm::vec3 kBackground{0.12f, 0.12f, 0.14f};

// A shaded colour seen through the texture's opacity: blended towards the background.
inline glm::vec3 over_background(const glm::vec3& colour, float opacity) {
  return opacity < 1.0f ? kBackground + opacity * (colour - kBackground) : colour;
}

inline void set_pixel(Image& image, int x, int y, const glm::vec3& colour, float opacity) {
  const glm::vec3 seen = over_background(colour, opacity);
  image.set(x, y, seen.r, seen.g, seen.b);
}

// Lit pixels in any order (TileShader::shade_pixels()'s) waiting to be shaded together: where
// they are, their texture values, and the batch that shade_batch() lights. A tile shaded in
// scan order uses LitTile instead.
struct LitPixels {
  ShadeBatch batch;
  ShadeBatch::Lanes<int> x, y;
  ShadeBatch::Lanes<std::size_t> index;  // in the G-buffer
  ShadeBatch::Lanes<float> opacity;

  void add(int lane, int px, int py, std::size_t i, const SurfaceInputs& surface, float shininess) {
    const auto l = static_cast<std::size_t>(lane);
    x[l] = px;
    y[l] = py;
    index[l] = i;
    opacity[l] = surface.opacity;
    batch.albedo_r[l] = surface.albedo.r;
    batch.albedo_g[l] = surface.albedo.g;
    batch.albedo_b[l] = surface.albedo.b;
    batch.specular[l] = surface.specular;
    batch.shininess[l] = shininess;
  }

  // Writes the batch's colours, seen through their opacity, to their pixels of `image`, as
  // set_pixel() writes them (lighting_kernels.cpp: the bytes made in vector lanes).
  void write(Image& image) const;
};

struct SurfaceUnprojection;

// The lit pixels of one shading tile (at most kSide x kSide), kept by their place in it (row
// r, column c at r * kSide + c): their texture values, written in whatever order the lookups
// finish, then lit in scan order straight from the G-buffer's planes (light()): no pixel
// positions kept per pixel, no gather by index, each row's bytes written where they lie.
struct LitTile {
  static constexpr int kSide = 32;
  static constexpr std::size_t kPixels = static_cast<std::size_t>(kSide) * kSide;

  // The tile: frame pixels [x0, x0 + width) x [y0, y0 + height), pixel (x0, y0) at G-buffer
  // index `first`, rows `row_stride` apart there.
  int x0 = 0, y0 = 0, width = 0, height = 0;
  std::size_t first = 0, row_stride = 0;
  // Zeroed once: a pixel not lit in this tile keeps finite values of an earlier one, which
  // light() computes over (within a row's span of lit pixels) but never writes. A row more
  // than the tile: light() copies kSide values from any column of any row.
  template <typename T>
  using Plane = std::array<T, kPixels + kSide>;
  alignas(64) Plane<float> albedo_r{}, albedo_g{}, albedo_b{};
  alignas(64) Plane<float> specular{}, shininess{}, opacity{};
  alignas(64) std::array<uint8_t, kPixels> lit{};  // 1: lit from these values; light() clears

  // Bit c: pixel c of row r is lit. Eight 0-or-1 bytes at a time: the multiplication moves
  // byte i's bit to bit 56 + i, and no two partial products meet (so nothing carries).
  uint32_t row_mask(std::size_t r) const {
    static_assert(std::endian::native == std::endian::little);
    uint32_t mask = 0;
    for (std::size_t word = 0; word < kSide / 8; ++word) {
      uint64_t bytes;
      std::memcpy(&bytes, &lit[r * kSide + 8 * word], sizeof bytes);
      mask |= static_cast<uint32_t>((bytes * 0x0102040810204080ull) >> 56) << (8 * word);
    }
    return mask;
  }
  std::size_t slot(int x, int y) const {
    return static_cast<std::size_t>(y - y0) * kSide + static_cast<std::size_t>(x - x0);
  }
  // add() in two parts, for a colour-only material: what every pixel of it shares, for
  // `count` pixels from `at` at once (contiguous stores), before its lookups come in; then
  // each pixel's albedo as its lookup does.
  void add_shared(std::size_t at, std::size_t count, float specular_in, float shininess_in) {
    const auto first = static_cast<std::ptrdiff_t>(at);
    const auto n = static_cast<std::ptrdiff_t>(count);
    std::fill(specular.begin() + first, specular.begin() + first + n, specular_in);
    std::fill(shininess.begin() + first, shininess.begin() + first + n, shininess_in);
    std::fill(opacity.begin() + first, opacity.begin() + first + n, 1.0f);
    std::fill(lit.begin() + first, lit.begin() + first + n, uint8_t{1});
  }
  void add_albedo(std::size_t at, const float* rgb) {
    albedo_r[at] = rgb[0];
    albedo_g[at] = rgb[1];
    albedo_b[at] = rgb[2];
  }
  void add(std::size_t at, const SurfaceInputs& surface, float shininess_in) {
    albedo_r[at] = surface.albedo.r;
    albedo_g[at] = surface.albedo.g;
    albedo_b[at] = surface.albedo.b;
    specular[at] = surface.specular;
    shininess[at] = shininess_in;
    opacity[at] = surface.opacity;
    lit[at] = 1;
  }

  // Lights the tile's lit pixels as SurfaceUnprojection::fill(), shade_batch() and
  // LitPixels::write() would, bit for bit, and clears `lit`; `scratch` holds the lanes
  // (lighting_kernels.cpp, runtime-dispatched once per tile).
  void light(const SurfaceUnprojection& u, const PreparedLights& lights, const GBuffer& g,
             ShadeBatch& scratch, Image& image);
};

// The lighting inputs of a batch's pixels: the world position unprojected from depth (relative
// to the eye through `inverse_vp`, the eye added back in double), the direction to the viewer,
// and the unit normal turned to face the viewer (seen from inside: flipped).
struct SurfaceUnprojection {
  SurfaceUnprojection(const glm::dmat4& inverse_vp, const glm::dvec3& eye, int width, int height);

  glm::dmat4 inverse_vp;
  glm::dvec3 eye;
  int width;
  int height;
  // Each column's and row's pixel centre in normalised device coordinates, made once per
  // frame: the same two double divisions every pixel of a column or row would otherwise make.
  std::vector<double> ndc_x, ndc_y;
  // Per object id, world space from its texture space, and one identity more for pixels of no
  // object. Point lights need each pixel's world position, which the G-buffer's double
  // texture position gives exactly: unprojected from its float window depth instead, it
  // erred by a quarter of a unit two units away with a near plane of 1e-6 (depth keeps
  // about 24 bits of 1 - near / distance), and point-lit walls broke into blocks.
  std::vector<glm::dmat4> world_from_texture{glm::dmat4(1.0)};
  // Adds object `id`'s map (ids in order from 0), keeping the identity last.
  void add_object(const glm::dmat4& world_from_object, const glm::dmat4& texture_from_object);

  // Writes the batch's position, to_viewer and normal lanes from the G-buffer's texture
  // position, depth and normal at the pixels `lit` holds (lighting_kernels.cpp: runtime-dispatched,
  // every target the same IEEE operations in the same order, so the same bits).
  void fill(const GBuffer& g, LitPixels& lit) const;
};

}  // namespace soltex::render
