#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

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

  void write(Image& image) const {
    for (std::size_t l = 0; l < static_cast<std::size_t>(batch.count); ++l) {
      set_pixel(image, x[l], y[l], {batch.colour_r[l], batch.colour_g[l], batch.colour_b[l]},
                opacity[l]);
    }
  }
};

// The lighting inputs of a batch's pixels: the world position unprojected from depth (relative
// to the eye through `inverse_vp`, the eye added back in double), the direction to the viewer,
// and the unit normal turned to face the viewer (seen from inside: flipped).
struct SurfaceUnprojection {
  glm::dmat4 inverse_vp;
  glm::dvec3 eye;
  int width;
  int height;

  void fill(const GBuffer& g, LitPixels& lit) const {
    ShadeBatch& b = lit.batch;
    const auto count = static_cast<std::size_t>(b.count);
    // Gathered first, so that the arithmetic below runs over plain arrays.
    alignas(64) ShadeBatch::Lanes<float> depth, nx, ny, nz;
    alignas(64) ShadeBatch::Lanes<uint8_t> back;
    for (std::size_t l = 0; l < count; ++l) {
      const std::size_t i = lit.index[l];
      depth[l] = g.depth[i];
      nx[l] = g.normal[i].x;
      ny[l] = g.normal[i].y;
      nz[l] = g.normal[i].z;
      back[l] = g.back_face(i) ? 1 : 0;
    }
    const glm::dmat4& m = inverse_vp;
    const double w = width, h = height;
    for (std::size_t l = 0; l < count; ++l) {
      const double ndc_x = (lit.x[l] + 0.5) / w * 2.0 - 1.0;
      const double ndc_y = 1.0 - (lit.y[l] + 0.5) / h * 2.0;
      const double ndc_z = static_cast<double>(depth[l]) * 2.0 - 1.0;
      // glm's matrix-vector product: (m0 x + m1 y) + (m2 z + m3 w), with w = 1.
      const double hx = (m[0].x * ndc_x + m[1].x * ndc_y) + (m[2].x * ndc_z + m[3].x * 1.0);
      const double hy = (m[0].y * ndc_x + m[1].y * ndc_y) + (m[2].y * ndc_z + m[3].y * 1.0);
      const double hz = (m[0].z * ndc_x + m[1].z * ndc_y) + (m[2].z * ndc_z + m[3].z * 1.0);
      const double hw = (m[0].w * ndc_x + m[1].w * ndc_y) + (m[2].w * ndc_z + m[3].w * 1.0);
      const double rx = hx / hw, ry = hy / hw, rz = hz / hw;
      b.position_x[l] = eye.x + rx;
      b.position_y[l] = eye.y + ry;
      b.position_z[l] = eye.z + rz;
      const auto vx = static_cast<float>(-rx);
      const auto vy = static_cast<float>(-ry);
      const auto vz = static_cast<float>(-rz);
      const float length = std::sqrt((vx * vx + vy * vy) + vz * vz);
      // Quotients first, selected after: a division under a condition would keep the loop
      // scalar (it might trap), a selection does not.
      const float qx = vx / length, qy = vy / length, qz = vz / length;
      const bool has_length = length > 0.0f;
      const float tx = has_length ? qx : 0.0f;
      const float ty = has_length ? qy : 0.0f;
      const float tz = has_length ? qz : 1.0f;
      const float n_length = std::sqrt((nx[l] * nx[l] + ny[l] * ny[l]) + nz[l] * nz[l]);
      const float mx = nx[l] / n_length, my = ny[l] / n_length, mz = nz[l] / n_length;
      const bool has_normal = n_length > 0.0f;
      const float ux = has_normal ? mx : tx;
      const float uy = has_normal ? my : ty;
      const float uz = has_normal ? mz : tz;
      const bool flip = back[l] != 0 || ((ux * tx + uy * ty) + uz * tz) < 0.0f;
      b.normal_x[l] = flip ? -ux : ux;
      b.normal_y[l] = flip ? -uy : uy;
      b.normal_z[l] = flip ? -uz : uz;
      b.to_viewer_x[l] = tx;
      b.to_viewer_y[l] = ty;
      b.to_viewer_z[l] = tz;
    }
  }
};

}  // namespace soltex::render
