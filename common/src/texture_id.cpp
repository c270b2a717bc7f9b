#include "soltex/common/texture_id.h"

#include <xxhash.h>

#include <bit>
#include <cstdio>
#include <cstring>

#include "soltex/common/overloaded.h"

namespace soltex {
namespace {

// Bumped whenever the encoding or the meaning of a texture changes, bricks' bytes included: a
// brick URL is cached as immutable, so new bytes need a new name. v2: wood's band limit counts
// the twist. v3: colours are the ramp averaged over the field's spread within a sample's box.
constexpr char kFormatTag[] = "soltex.texture.v3";

class CanonicalWriter {
 public:
  void u8(uint8_t v) { bytes_.push_back(v); }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void i32(int32_t v) { u32(static_cast<uint32_t>(v)); }
  void f64(double v) { u64(std::bit_cast<uint64_t>(v == 0.0 ? 0.0 : v)); }
  void f32(float v) { u32(std::bit_cast<uint32_t>(v == 0.0f ? 0.0f : v)); }
  void vec(const glm::dvec3& v) {
    f64(v.x);
    f64(v.y);
    f64(v.z);
  }
  void text(const char* s) {
    const std::size_t n = std::strlen(s);
    u32(static_cast<uint32_t>(n));
    for (std::size_t i = 0; i < n; ++i) bytes_.push_back(static_cast<uint8_t>(s[i]));
  }
  void fractal(const FractalParams& f) {
    f64(f.scale);
    i32(f.octave_min);
    i32(f.octave_max);
    u8(static_cast<uint8_t>(f.basis));
    u8(f.signed_octaves ? 1 : 0);
  }
  void append_graph(const GraphField& graph) { graph.append_canonical(bytes_); }
  std::vector<uint8_t> take() { return std::move(bytes_); }

 private:
  std::vector<uint8_t> bytes_;
};

void append_pattern(CanonicalWriter& w, const Pattern& pattern) {
  std::visit(Overloaded{
                 [&](const StripesParams& p) {
                   w.f64(p.width);
                   w.f64(p.offset);
                   w.u8(static_cast<uint8_t>(p.axis));
                 },
                 [&](const CheckerParams& p) {
                   w.vec(p.size);
                   w.f64(p.offset);
                   w.u8(p.three_d ? 1 : 0);
                 },
                 [&](const ColourCubeParams& p) { w.f64(p.period); },
                 [&](const RingsParams& p) {
                   w.f64(p.thickness);
                   w.f64(p.base);
                   w.f64(p.amplitude);
                 },
                 [&](const WoodParams& p) {
                   for (double v : {p.ring_spacing, p.tilt_y, p.tilt_z, p.twist, p.jitter,
                                    p.jitter_scale, p.grain_fraction}) {
                     w.f64(v);
                   }
                 },
                 [&](const NoiseParams& p) {
                   w.f64(p.scale);
                   w.u8(static_cast<uint8_t>(p.basis));
                 },
                 [&](const TurbulenceParams& p) { w.fractal(p.fractal); },
                 [&](const MarbleParams& p) {
                   w.f64(p.frequency);
                   w.f64(p.amplitude);
                   w.u8(static_cast<uint8_t>(p.ripple));
                   w.u8(static_cast<uint8_t>(p.axis));
                   w.fractal(p.turbulence);
                 },
             },
             pattern);
}

void append_ramp_and_channels(CanonicalWriter& w, const TextureSpec& spec) {
  w.u32(static_cast<uint32_t>(spec.ramp.keys.size()));
  for (const RampKey& key : spec.ramp.keys) {
    w.f32(key.position);
    w.f32(key.colour.r);
    w.f32(key.colour.g);
    w.f32(key.colour.b);
  }
  w.u8(static_cast<uint8_t>((spec.channels.colour ? 1 : 0) | (spec.channels.opacity ? 2 : 0) |
                            (spec.channels.specular ? 4 : 0)));
  w.f32(spec.opacity.low);
  w.f32(spec.opacity.high);
  w.f32(spec.specular.low);
  w.f32(spec.specular.high);
}

}  // namespace

std::vector<uint8_t> canonical_encoding(const TextureSpec& spec, const Volume& volume,
                                        int brick_size, const MipSettings& mip) {
  CanonicalWriter w;
  w.text(kFormatTag);
  if (spec.graph) {
    w.text("graph");
    w.append_graph(*spec.graph);
  } else {
    w.text(pattern_name(spec.pattern));
    append_pattern(w, spec.pattern);
  }
  append_ramp_and_channels(w, spec);
  w.vec(volume.min);
  w.vec(volume.max);
  w.i32(volume.finest_level_log2);
  w.i32(brick_size);
  w.u8(static_cast<uint8_t>(mip.mode));
  w.i32(mip.mode == MipMode::supersampled ? mip.supersample : 0);
  return w.take();
}

uint64_t texture_id(const TextureSpec& spec, const Volume& volume, int brick_size,
                    const MipSettings& mip) {
  const std::vector<uint8_t> bytes =
      canonical_encoding(validated(spec), validated(volume), brick_size, mip);
  return XXH64(bytes.data(), bytes.size(), 0);
}

std::string texture_id_hex(uint64_t id) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(id));
  return buffer;
}

}  // namespace soltex
