// Runtime dispatch of the per-batch lighting loops: the lighting inputs unprojected from the
// G-buffer (SurfaceUnprojection::fill) and the lights' terms (shade_batch). Highway compiles
// this file once per target (hwy/foreach_target.h re-includes it) and HWY_DYNAMIC_DISPATCH
// calls the widest one the CPU supports, once per batch. The loops are plain per-lane
// arithmetic written so that the compiler runs them in vector lanes (selects, no branches, no
// calls); each target only widens those lanes. Every target does the same IEEE operations in
// the same order per lane (no contraction: -ffp-contract=off holds for every target), so each
// gives the bits of the baseline build; tests/unit/render/shading_test.cpp compares
// shade_batch() with the scalar shade() lane by lane.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "lighting_kernels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

// After Highway: lit_pixels.h reaches the sampler's per-target kernels (-inl.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "lit_pixels.h"
#include "soltex/render/shading.h"
#include "specular_power.h"

HWY_BEFORE_NAMESPACE();
namespace soltex::render_internal::HWY_NAMESPACE {

using render::LitPixels;
using render::SurfaceUnprojection;

void unproject_target(const SurfaceUnprojection& u, const GBuffer& g, LitPixels& lit) {
  ShadeBatch& b = lit.batch;
  const auto count = static_cast<std::size_t>(b.count);
  // Gathered first, so that the arithmetic below runs over plain arrays.
  alignas(64) ShadeBatch::Lanes<double> ndc_x, ndc_y;
  alignas(64) ShadeBatch::Lanes<float> depth, nx, ny, nz;
  alignas(64) ShadeBatch::Lanes<uint8_t> back;
  for (std::size_t l = 0; l < count; ++l) {
    const std::size_t i = lit.index[l];
    ndc_x[l] = u.ndc_x[static_cast<std::size_t>(lit.x[l])];
    ndc_y[l] = u.ndc_y[static_cast<std::size_t>(lit.y[l])];
    depth[l] = g.depth[i];
    nx[l] = g.normal[i].x;
    ny[l] = g.normal[i].y;
    nz[l] = g.normal[i].z;
    back[l] = g.back_face(i) ? 1 : 0;
  }
  const glm::dmat4& m = u.inverse_vp;
  const glm::dvec3& eye = u.eye;
  for (std::size_t l = 0; l < count; ++l) {
    const double ndc_z = static_cast<double>(depth[l]) * 2.0 - 1.0;
    // glm's matrix-vector product: (m0 x + m1 y) + (m2 z + m3 w), with w = 1.
    const double hx = (m[0].x * ndc_x[l] + m[1].x * ndc_y[l]) + (m[2].x * ndc_z + m[3].x * 1.0);
    const double hy = (m[0].y * ndc_x[l] + m[1].y * ndc_y[l]) + (m[2].y * ndc_z + m[3].y * 1.0);
    const double hz = (m[0].z * ndc_x[l] + m[1].z * ndc_y[l]) + (m[2].z * ndc_z + m[3].z * 1.0);
    const double hw = (m[0].w * ndc_x[l] + m[1].w * ndc_y[l]) + (m[2].w * ndc_z + m[3].w * 1.0);
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

// light_term() across the batch, for a light whose direction and radiance are in the batch's
// light_* and radiance_* lanes; adds it to the colour lanes.
void add_light_term(ShadeBatch& b) {
  const int count = b.count;
  // Diffuse, and the half vector's cosine, in vector loops.
  for (int i = 0; i < count; ++i) {
    const float n_dot_l = (b.normal_x[i] * b.light_x[i] + b.normal_y[i] * b.light_y[i]) +
                          b.normal_z[i] * b.light_z[i];
    const float hx = b.light_x[i] + b.to_viewer_x[i];
    const float hy = b.light_y[i] + b.to_viewer_y[i];
    const float hz = b.light_z[i] + b.to_viewer_z[i];
    const float inverse_length = 1.0f / std::sqrt((hx * hx + hy * hy) + hz * hz);
    b.n_dot_l[i] = n_dot_l;
    b.n_dot_h[i] = (b.normal_x[i] * (hx * inverse_length) + b.normal_y[i] * (hy * inverse_length)) +
                   b.normal_z[i] * (hz * inverse_length);
  }
  // The highlight's power in every lane (a vector loop), kept where light_term() computes it.
  for (int i = 0; i < count; ++i) {
    const float n_dot_h = b.n_dot_h[i];
    const float power = specular_power(n_dot_h, b.shininess[i]);
    // & rather than &&: no branches, or the loop stays scalar.
    const bool wanted = (b.n_dot_l[i] > 0.0f) & (b.specular[i] > 0.0f) & (n_dot_h > 0.0f);
    b.highlight[i] = wanted ? b.specular[i] * power : 0.0f;
  }
  for (int i = 0; i < count; ++i) {
    const float n_dot_l = b.n_dot_l[i];
    const float r = b.albedo_r[i] * b.radiance_r[i] * n_dot_l;
    const float g = b.albedo_g[i] * b.radiance_g[i] * n_dot_l;
    const float bl = b.albedo_b[i] * b.radiance_b[i] * n_dot_l;
    // Every sum computed, then selected: additions under a condition would keep the loop scalar.
    // light_term() adds the highlight only where it computed one.
    const bool has_highlight = n_dot_l > 0.0f && b.specular[i] > 0.0f && b.n_dot_h[i] > 0.0f;
    const float r_total = has_highlight ? r + b.radiance_r[i] * b.highlight[i] : r;
    const float g_total = has_highlight ? g + b.radiance_g[i] * b.highlight[i] : g;
    const float b_total = has_highlight ? bl + b.radiance_b[i] * b.highlight[i] : bl;
    const bool lit = n_dot_l > 0.0f;
    b.colour_r[i] = lit ? b.colour_r[i] + r_total : b.colour_r[i];
    b.colour_g[i] = lit ? b.colour_g[i] + g_total : b.colour_g[i];
    b.colour_b[i] = lit ? b.colour_b[i] + b_total : b.colour_b[i];
  }
}

void shade_batch_target(const PreparedLights& lights, ShadeBatch& b) {
  const int count = b.count;
  for (int i = 0; i < count; ++i) {
    b.colour_r[i] = b.albedo_r[i] * lights.ambient.r;
    b.colour_g[i] = b.albedo_g[i] * lights.ambient.g;
    b.colour_b[i] = b.albedo_b[i] * lights.ambient.b;
  }
  for (const auto& d : lights.directional) {
    for (int i = 0; i < count; ++i) {
      b.light_x[i] = d.to_light.x;
      b.light_y[i] = d.to_light.y;
      b.light_z[i] = d.to_light.z;
      b.radiance_r[i] = d.radiance.r;
      b.radiance_g[i] = d.radiance.g;
      b.radiance_b[i] = d.radiance.b;
    }
    add_light_term(b);
  }
  for (const auto& p : lights.point) {
    const glm::dvec3 light = p.position;
    const glm::vec3 radiance = p.radiance;
    for (int i = 0; i < count; ++i) {
      const double ox = light.x - b.position_x[i];
      const double oy = light.y - b.position_y[i];
      const double oz = light.z - b.position_z[i];
      const double dot = (ox * ox + oy * oy) + oz * oz;
      const double distance2 = dot < 1e-12 ? 1e-12 : dot;  // std::max(dot, 1e-12)
      const double distance = std::sqrt(distance2);
      b.light_x[i] = static_cast<float>(ox / distance);
      b.light_y[i] = static_cast<float>(oy / distance);
      b.light_z[i] = static_cast<float>(oz / distance);
      const auto d2 = static_cast<float>(distance2);
      b.radiance_r[i] = radiance.r / d2;
      b.radiance_g[i] = radiance.g / d2;
      b.radiance_b[i] = radiance.b / d2;
    }
    add_light_term(b);
  }
}

// LitPixels::write()'s bytes: per lane what set_pixel() gives (over_background(), then
// Image's rounding), with selects for its branches. bytes[3 l + c]: lane l's channel c.
void colour_bytes_target(const LitPixels& lit, uint8_t* bytes) {
  const ShadeBatch& b = lit.batch;
  const auto count = static_cast<std::size_t>(b.count);
  alignas(64) ShadeBatch::Lanes<uint8_t> red, green, blue;
  const glm::vec3 background = render::kBackground;
  const auto to_byte = [](float v) {
    const float rounded = (v > 1.0f ? 1.0f : v) * 255.0f + 0.5f;  // std::min(v, 1.0f)
    const auto byte = static_cast<uint8_t>(static_cast<int32_t>(v > 0.0f ? rounded : 0.0f));
    return byte;
  };
  for (std::size_t l = 0; l < count; ++l) {
    const float opacity = lit.opacity[l];
    const bool blend = opacity < 1.0f;
    const float r = background.r + opacity * (b.colour_r[l] - background.r);
    const float g = background.g + opacity * (b.colour_g[l] - background.g);
    const float bl = background.b + opacity * (b.colour_b[l] - background.b);
    red[l] = to_byte(blend ? r : b.colour_r[l]);
    green[l] = to_byte(blend ? g : b.colour_g[l]);
    blue[l] = to_byte(blend ? bl : b.colour_b[l]);
  }
  for (std::size_t l = 0; l < count; ++l) {
    bytes[3 * l] = red[l];
    bytes[3 * l + 1] = green[l];
    bytes[3 * l + 2] = blue[l];
  }
}

}  // namespace soltex::render_internal::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex {
namespace render_internal {

HWY_EXPORT(unproject_target);
HWY_EXPORT(shade_batch_target);
HWY_EXPORT(colour_bytes_target);

// Dispatched from this namespace, where the kernels' per-target namespaces are: a build with
// one target only (-march=native) calls that target's kernel directly by the same name.
namespace {

void unproject(const render::SurfaceUnprojection& u, const GBuffer& g, render::LitPixels& lit) {
  HWY_DYNAMIC_DISPATCH(unproject_target)(u, g, lit);
}

void shade_lanes(const PreparedLights& lights, ShadeBatch& batch) {
  HWY_DYNAMIC_DISPATCH(shade_batch_target)(lights, batch);
}

void colour_bytes(const render::LitPixels& lit, uint8_t* bytes) {
  HWY_DYNAMIC_DISPATCH(colour_bytes_target)(lit, bytes);
}

}  // namespace
}  // namespace render_internal

render::SurfaceUnprojection::SurfaceUnprojection(const glm::dmat4& inverse_vp_in,
                                                 const glm::dvec3& eye_in, int width_in,
                                                 int height_in)
    : inverse_vp(inverse_vp_in), eye(eye_in), width(width_in), height(height_in) {
  const double w = width, h = height;
  ndc_x.resize(static_cast<std::size_t>(std::max(width, 0)));
  ndc_y.resize(static_cast<std::size_t>(std::max(height, 0)));
  for (std::size_t x = 0; x < ndc_x.size(); ++x) {
    ndc_x[x] = (static_cast<int>(x) + 0.5) / w * 2.0 - 1.0;
  }
  for (std::size_t y = 0; y < ndc_y.size(); ++y) {
    ndc_y[y] = 1.0 - (static_cast<int>(y) + 0.5) / h * 2.0;
  }
}

void render::LitPixels::write(Image& image) const {
  alignas(64) std::array<uint8_t, 3 * ShadeBatch::kCapacity> bytes;
  render_internal::colour_bytes(*this, bytes.data());
  for (std::size_t l = 0; l < static_cast<std::size_t>(batch.count); ++l) {
    uint8_t* pixel = image.pixel(x[l], y[l]);
    pixel[0] = bytes[3 * l];
    pixel[1] = bytes[3 * l + 1];
    pixel[2] = bytes[3 * l + 2];
  }
}

void render::SurfaceUnprojection::fill(const GBuffer& g, LitPixels& lit) const {
  render_internal::unproject(*this, g, lit);
}

void shade_batch(const PreparedLights& lights, ShadeBatch& batch) {
  render_internal::shade_lanes(lights, batch);
}

}  // namespace soltex
#endif
