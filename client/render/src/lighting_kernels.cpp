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
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "lit_pixels.h"
#include "soltex/render/shading.h"
#include "specular_power.h"

HWY_BEFORE_NAMESPACE();
namespace soltex::render_internal::HWY_NAMESPACE {

using render::LitPixels;
using render::LitTile;
using render::SurfaceUnprojection;

// The G-buffer's lighting inputs of a batch's lanes, as unproject_lanes() reads them.
struct UnprojectInputs {
  alignas(64) ShadeBatch::Lanes<double> ndc_x, ndc_y;
  alignas(64) ShadeBatch::Lanes<float> depth, nx, ny, nz;
  alignas(64) ShadeBatch::Lanes<uint8_t> back;
  // Read for positions only (point lights): the texture position and the index of its map
  // to world space in SurfaceUnprojection::world_from_texture.
  alignas(64) ShadeBatch::Lanes<glm::dvec3> texture_position;
  alignas(64) ShadeBatch::Lanes<uint32_t> map;
};

// The index of `object_id`'s map in u.world_from_texture: the identity for no object.
uint32_t map_of(const SurfaceUnprojection& u, uint32_t object_id) {
  const auto identity = static_cast<uint32_t>(u.world_from_texture.size() - 1);
  return object_id < identity ? object_id : identity;
}

// The world positions of the lanes, from their texture positions: exact in double, where
// the window depth is a float (see SurfaceUnprojection::world_from_texture).
// Lanes in runs of one map (a tile's pixels are mostly one object's), each run with its
// matrix in registers. The products as glm's matrix-vector one orders them, w = 1.
void world_positions(const SurfaceUnprojection& u, const UnprojectInputs& in, ShadeBatch& b) {
  const auto count = static_cast<std::size_t>(b.count);
  for (std::size_t begin = 0, end = 0; begin < count; begin = end) {
    end = begin + 1;
    while (end < count && in.map[end] == in.map[begin]) ++end;
    const glm::dmat4 m = u.world_from_texture[in.map[begin]];
    for (std::size_t l = begin; l < end; ++l) {
      const glm::dvec3& t = in.texture_position[l];
      b.position_x[l] = (m[0].x * t.x + m[1].x * t.y) + (m[2].x * t.z + m[3].x);
      b.position_y[l] = (m[0].y * t.x + m[1].y * t.y) + (m[2].y * t.z + m[3].y);
      b.position_z[l] = (m[0].z * t.x + m[1].z * t.y) + (m[2].z * t.z + m[3].z);
    }
  }
}

// The batch's position, to_viewer and normal lanes from `in` (SurfaceUnprojection::fill()).
// Restrict: with `in` and the batch possibly one, the loop would stay scalar. kPositions:
// whether the position lanes are written (only point lights read them).
template <bool kPositions>
HWY_NOINLINE void unproject_lanes(const SurfaceUnprojection& u,
                                  const UnprojectInputs& __restrict in, ShadeBatch& __restrict b) {
  const auto count = static_cast<std::size_t>(b.count);
  const auto& ndc_x = in.ndc_x;
  const auto& ndc_y = in.ndc_y;
  const auto& depth = in.depth;
  const auto& nx = in.nx;
  const auto& ny = in.ny;
  const auto& nz = in.nz;
  const auto& back = in.back;
  const glm::dmat4 m = u.inverse_vp;
  for (std::size_t l = 0; l < count; ++l) {
    const double ndc_z = static_cast<double>(depth[l]) * 2.0 - 1.0;
    // glm's matrix-vector product: (m0 x + m1 y) + (m2 z + m3 w), with w = 1.
    const double hx = (m[0].x * ndc_x[l] + m[1].x * ndc_y[l]) + (m[2].x * ndc_z + m[3].x * 1.0);
    const double hy = (m[0].y * ndc_x[l] + m[1].y * ndc_y[l]) + (m[2].y * ndc_z + m[3].y * 1.0);
    const double hz = (m[0].z * ndc_x[l] + m[1].z * ndc_y[l]) + (m[2].z * ndc_z + m[3].z * 1.0);
    const double hw = (m[0].w * ndc_x[l] + m[1].w * ndc_y[l]) + (m[2].w * ndc_z + m[3].w * 1.0);
    // A point on the pixel's ray from the eye: its direction is exact whatever the depth's
    // rounding, its distance is not (positions come from world_positions()).
    const double rx = hx / hw, ry = hy / hw, rz = hz / hw;
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
  if constexpr (kPositions) world_positions(u, in, b);
}

void unproject_target(const SurfaceUnprojection& u, const GBuffer& g, LitPixels& lit) {
  const auto count = static_cast<std::size_t>(lit.batch.count);
  // Gathered first, so that the arithmetic runs over plain arrays.
  UnprojectInputs in;
  for (std::size_t l = 0; l < count; ++l) {
    const std::size_t i = lit.index[l];
    in.ndc_x[l] = u.ndc_x[static_cast<std::size_t>(lit.x[l])];
    in.ndc_y[l] = u.ndc_y[static_cast<std::size_t>(lit.y[l])];
    in.depth[l] = g.depth[i];
    in.nx[l] = g.normal[i].x;
    in.ny[l] = g.normal[i].y;
    in.nz[l] = g.normal[i].z;
    in.back[l] = g.back_face(i) ? 1 : 0;
    in.texture_position[l] = g.texture_position[i];
    in.map[l] = map_of(u, g.object_id[i]);
  }
  unproject_lanes<true>(u, in, lit.batch);
}

// A light's direction and radiance per lane: a point light's in the batch's light_* and
// radiance_* lanes, a directional light's the same in every lane (no lanes filled with it).
struct LaneLight {
  const ShadeBatch& b;
  float light_x(int i) const { return b.light_x[i]; }
  float light_y(int i) const { return b.light_y[i]; }
  float light_z(int i) const { return b.light_z[i]; }
  float radiance_r(int i) const { return b.radiance_r[i]; }
  float radiance_g(int i) const { return b.radiance_g[i]; }
  float radiance_b(int i) const { return b.radiance_b[i]; }
};
struct UniformLight {
  glm::vec3 to_light, radiance;
  float light_x(int) const { return to_light.x; }
  float light_y(int) const { return to_light.y; }
  float light_z(int) const { return to_light.z; }
  float radiance_r(int) const { return radiance.r; }
  float radiance_g(int) const { return radiance.g; }
  float radiance_b(int) const { return radiance.b; }
};

// light_term() across the batch for `light`; adds it to the colour lanes.
template <class Light>
void add_light_term(ShadeBatch& b, const Light light) {
  const int count = b.count;
  // Diffuse, and the half vector's cosine, in vector loops.
  for (int i = 0; i < count; ++i) {
    const float n_dot_l = (b.normal_x[i] * light.light_x(i) + b.normal_y[i] * light.light_y(i)) +
                          b.normal_z[i] * light.light_z(i);
    const float hx = light.light_x(i) + b.to_viewer_x[i];
    const float hy = light.light_y(i) + b.to_viewer_y[i];
    const float hz = light.light_z(i) + b.to_viewer_z[i];
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
    const float r = b.albedo_r[i] * light.radiance_r(i) * n_dot_l;
    const float g = b.albedo_g[i] * light.radiance_g(i) * n_dot_l;
    const float bl = b.albedo_b[i] * light.radiance_b(i) * n_dot_l;
    // Every sum computed, then selected: additions under a condition would keep the loop scalar.
    // light_term() adds the highlight only where it computed one.
    const bool has_highlight = n_dot_l > 0.0f && b.specular[i] > 0.0f && b.n_dot_h[i] > 0.0f;
    const float r_total = has_highlight ? r + light.radiance_r(i) * b.highlight[i] : r;
    const float g_total = has_highlight ? g + light.radiance_g(i) * b.highlight[i] : g;
    const float b_total = has_highlight ? bl + light.radiance_b(i) * b.highlight[i] : bl;
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
  for (const auto& d : lights.directional) add_light_term(b, UniformLight{d.to_light, d.radiance});
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
    add_light_term(b, LaneLight{b});
  }
}

// LitPixels::write()'s bytes: per lane what set_pixel() gives (over_background(), then
// Image's rounding), with selects for its branches. bytes[3 l + c]: lane l's channel c.
void colour_bytes_lanes(const ShadeBatch& b, const float* opacity_lanes, uint8_t* bytes) {
  const auto count = static_cast<std::size_t>(b.count);
  alignas(64) ShadeBatch::Lanes<uint8_t> red, green, blue;
  const glm::vec3 background = render::kBackground;
  const auto to_byte = [](float v) {
    const float rounded = (v > 1.0f ? 1.0f : v) * 255.0f + 0.5f;  // std::min(v, 1.0f)
    const auto byte = static_cast<uint8_t>(static_cast<int32_t>(v > 0.0f ? rounded : 0.0f));
    return byte;
  };
  for (std::size_t l = 0; l < count; ++l) {
    const float opacity = opacity_lanes[l];
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

void colour_bytes_target(const LitPixels& lit, uint8_t* bytes) {
  colour_bytes_lanes(lit.batch, lit.opacity.data(), bytes);
}

// LitTile::light(): each row's span from its first to its last lit pixel goes into the lanes as
// it lies in the G-buffer and the tile's planes (contiguous reads), rows after rows while they
// fit a batch; the batch is unprojected, lit and made bytes as a LitPixels batch is, and only
// the lit pixels' bytes are written. A span's pixels that are not lit (another object's, an
// unlit one's, the background) are computed too, from whatever their planes hold, and dropped.
void light_tile_target(const SurfaceUnprojection& u, const PreparedLights& lights, const GBuffer& g,
                       LitTile& t, ShadeBatch& b, Image& image) {
  constexpr std::size_t kSide = LitTile::kSide;
  struct Span {
    std::size_t row, begin, count, lane;
    uint32_t mask;  // bit c: pixel begin + c is lit
    bool all_lit;
  };
  std::array<Span, kSide> spans;
  std::size_t pending = 0, lanes = 0;
  UnprojectInputs in;
  alignas(64) ShadeBatch::Lanes<float> opacity;
  alignas(64) std::array<uint8_t, 3 * ShadeBatch::kCapacity> bytes;
  const auto light_pending = [&] {
    b.count = static_cast<int>(lanes);
    if (lights.point.empty()) {
      unproject_lanes<false>(u, in, b);
    } else {
      unproject_lanes<true>(u, in, b);
    }
    shade_batch_target(lights, b);
    colour_bytes_lanes(b, opacity.data(), bytes.data());
    for (std::size_t s = 0; s < pending; ++s) {
      const Span& span = spans[s];
      uint8_t* out =
          image.pixel(t.x0 + static_cast<int>(span.begin), t.y0 + static_cast<int>(span.row));
      const uint8_t* from = &bytes[3 * span.lane];
      if (span.all_lit) {
        for (std::size_t c = 0; c < 3 * span.count; ++c) out[c] = from[c];
        continue;
      }
      for (uint32_t m = span.mask; m != 0; m &= m - 1) {
        const auto p = static_cast<std::size_t>(3 * std::countr_zero(m));
        out[p] = from[p];
        out[p + 1] = from[p + 1];
        out[p + 2] = from[p + 2];
      }
    }
    pending = lanes = 0;
    b.count = 0;  // the batch is a LitPixels' too, whose count says what it holds
  };
  for (std::size_t r = 0; r < static_cast<std::size_t>(t.height); ++r) {
    const uint32_t mask = t.row_mask(r);
    if (mask == 0) continue;
    const auto begin = static_cast<std::size_t>(std::countr_zero(mask));
    const std::size_t end = kSide - static_cast<std::size_t>(std::countl_zero(mask));
    const std::size_t n = end - begin;
    if (lanes + kSide > static_cast<std::size_t>(ShadeBatch::kCapacity)) light_pending();
    spans[pending++] =
        Span{r, begin, n, lanes, mask >> begin, static_cast<std::size_t>(std::popcount(mask)) == n};
    const std::size_t gi = t.first + r * t.row_stride + begin;
    const std::size_t si = r * kSide + begin;
    const double ndc_y = u.ndc_y[static_cast<std::size_t>(t.y0) + r];
    // Planes to lanes by memcpy (a loop over the tile's planes and the batch's, which the
    // compiler cannot tell apart, stays scalar); whole rows of the tile's planes, a fixed size
    // the compiler makes a few vector moves (the lanes past the span are overwritten or unused).
    const auto copy_row = [](float* to, const float* from) {
      std::memcpy(to, from, kSide * sizeof(float));
    };
    std::memcpy(&in.ndc_x[lanes], &u.ndc_x[static_cast<std::size_t>(t.x0) + begin],
                n * sizeof(double));
    std::memcpy(&in.depth[lanes], &g.depth[gi], n * sizeof(float));
    copy_row(&b.albedo_r[lanes], &t.albedo_r[si]);
    copy_row(&b.albedo_g[lanes], &t.albedo_g[si]);
    copy_row(&b.albedo_b[lanes], &t.albedo_b[si]);
    copy_row(&b.specular[lanes], &t.specular[si]);
    copy_row(&b.shininess[lanes], &t.shininess[si]);
    copy_row(&opacity[lanes], &t.opacity[si]);
    for (std::size_t l = 0; l < n; ++l) {
      const std::size_t at = lanes + l;
      in.ndc_y[at] = ndc_y;
      in.nx[at] = g.normal[gi + l].x;
      in.ny[at] = g.normal[gi + l].y;
      in.nz[at] = g.normal[gi + l].z;
      in.back[at] = (g.flags[gi + l] & GBuffer::kBackFace) != 0 ? 1 : 0;
    }
    if (!lights.point.empty()) {
      for (std::size_t l = 0; l < n; ++l) {
        in.texture_position[lanes + l] = g.texture_position[gi + l];
        in.map[lanes + l] = map_of(u, g.object_id[gi + l]);
      }
    }
    lanes += n;
  }
  if (lanes > 0) light_pending();
  std::fill_n(t.lit.begin(), static_cast<std::size_t>(t.height) * kSide, uint8_t{0});
}

}  // namespace soltex::render_internal::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex {
namespace render_internal {

HWY_EXPORT(unproject_target);
HWY_EXPORT(shade_batch_target);
HWY_EXPORT(colour_bytes_target);
HWY_EXPORT(light_tile_target);

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

void light_tile(const render::SurfaceUnprojection& u, const PreparedLights& lights,
                const GBuffer& g, render::LitTile& tile, ShadeBatch& scratch, Image& image) {
  HWY_DYNAMIC_DISPATCH(light_tile_target)(u, lights, g, tile, scratch, image);
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

void render::LitTile::light(const SurfaceUnprojection& u, const PreparedLights& lights,
                            const GBuffer& g, ShadeBatch& scratch, Image& image) {
  render_internal::light_tile(u, lights, g, *this, scratch, image);
}

void render::SurfaceUnprojection::add_object(const glm::dmat4& world_from_object,
                                             const glm::dmat4& texture_from_object) {
  world_from_texture.insert(world_from_texture.end() - 1,
                            world_from_object * glm::inverse(texture_from_object));
}

void render::SurfaceUnprojection::fill(const GBuffer& g, LitPixels& lit) const {
  render_internal::unproject(*this, g, lit);
}

void shade_batch(const PreparedLights& lights, ShadeBatch& batch) {
  render_internal::shade_lanes(lights, batch);
}

}  // namespace soltex
#endif
