#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <memory>
#include <span>

#include "soltex/common/trilinear_u8.h"

// One brick as the sparse cache keeps it: (B + 1)^3 samples of 8 bits per channel.
//
// Layout: channel-interleaved (R, G, B, opacity, specular of one sample side by side), x
// fastest, then y, then z. A trilinear lookup reads 8 corners; interleaved, each pair of
// x-neighbours is one contiguous run of 2 * channels bytes, so an RGB lookup touches 4 short
// runs (usually 4 cache lines) and loads each with one instruction. Channel-planar storage,
// as the codec produces it, would touch 4 runs per channel (12 lines for RGB). Insertion
// converts planar to interleaved once; lookups happen per pixel.
namespace soltex {

class CachedBrick {
 public:
  static constexpr int kMaxChannels = 5;  // R, G, B, opacity, specular

  // `planar`: `channels` planes of (brick_size + 1)^3 samples each, x fastest, in channel
  // order R, G, B, opacity, specular (those present), as the brick codec decodes them.
  // Throws std::invalid_argument when brick_size is not 8 or 16, channels is outside
  // [1, kMaxChannels] or planar has the wrong size.
  CachedBrick(int brick_size, int channels, std::span<const uint8_t> planar);

  CachedBrick(CachedBrick&&) noexcept = default;
  CachedBrick& operator=(CachedBrick&&) noexcept = default;

  int brick_size() const { return brick_size_; }
  int samples_per_axis() const { return brick_size_ + 1; }
  int channels() const { return channels_; }

  // Bytes of sample storage, the load padding included.
  std::size_t sample_bytes() const { return sample_bytes_; }
  static std::size_t sample_bytes(int brick_size, int channels);

  std::ptrdiff_t y_stride() const { return y_stride_; }
  std::ptrdiff_t z_stride() const { return z_stride_; }

  // The first channel of local sample (x, y, z), each in [0, brick_size].
  const uint8_t* sample(int x, int y, int z) const {
    return samples_.get() + z * z_stride_ + y * y_stride_ + x * channels_;
  }
  uint8_t at(int x, int y, int z, int channel) const { return sample(x, y, z)[channel]; }

  // Trilinear interpolation in cell `cell` (each coordinate in [0, brick_size - 1]) at
  // fractions `frac` in [0, 1]; writes channels() values in [0, 1]. `out` must hold
  // kMaxChannels floats (the 4-channel path stores 4 lanes at once).
  void trilinear(const glm::ivec3& cell, const glm::vec3& frac, float* out) const {
    // RGB inline (the common case, and the one kept small enough to inline into a sampler);
    // other channel counts through one call.
    if (channels_ == 3) {
      trilinear_u8<3>(sample(cell.x, cell.y, cell.z), y_stride_, z_stride_, frac.x, frac.y, frac.z,
                      out);
      return;
    }
    trilinear_other(cell, frac, out);
  }

  // The sample nearest to cell + frac: writes channels() values in [0, 1].
  void nearest(const glm::ivec3& cell, const glm::vec3& frac, float* out) const {
    const uint8_t* s = sample(cell.x + (frac.x >= 0.5f ? 1 : 0), cell.y + (frac.y >= 0.5f ? 1 : 0),
                              cell.z + (frac.z >= 0.5f ? 1 : 0));
    for (int c = 0; c < channels_; ++c) out[c] = static_cast<float>(s[c]) * (1.0f / 255.0f);
  }

 private:
  void trilinear_other(const glm::ivec3& cell, const glm::vec3& frac, float* out) const;

  int brick_size_;
  int channels_;
  std::ptrdiff_t y_stride_;
  std::ptrdiff_t z_stride_;
  std::size_t sample_bytes_;
  std::unique_ptr<uint8_t[]> samples_;
};

}  // namespace soltex
