#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
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

// The lit pixels of a tile waiting to be shaded together: where they are, their texture
// values, and the batch that shade_batch() lights.
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

  // Writes the batch's position, to_viewer and normal lanes from the G-buffer's depth and
  // normal at the pixels `lit` holds (lighting_kernels.cpp: runtime-dispatched, every target
  // the same IEEE operations in the same order, so the same bits).
  void fill(const GBuffer& g, LitPixels& lit) const;
};

}  // namespace soltex::render
