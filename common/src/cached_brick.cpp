#include "soltex/common/cached_brick.h"

#include <stdexcept>
#include <string>

#include "channel_interleave.h"

namespace soltex {
namespace {

std::size_t samples_per_channel(int brick_size) {
  const auto n = static_cast<std::size_t>(brick_size) + 1;
  return n * n * n;
}

}  // namespace

std::size_t CachedBrick::sample_bytes(int brick_size, int channels) {
  return samples_per_channel(brick_size) * static_cast<std::size_t>(channels) +
         kTrilinearLoadPadding;
}

CachedBrick::CachedBrick(int brick_size, int channels, std::span<const uint8_t> planar)
    : brick_size_(brick_size), channels_(channels), y_stride_(0), z_stride_(0), sample_bytes_(0) {
  if (brick_size != 8 && brick_size != 16) {
    throw std::invalid_argument("CachedBrick: brick_size = " + std::to_string(brick_size) +
                                " must be 8 or 16");
  }
  if (channels < 1 || channels > kMaxChannels) {
    throw std::invalid_argument("CachedBrick: channels = " + std::to_string(channels) +
                                " must be in [1, " + std::to_string(kMaxChannels) + "]");
  }
  const std::size_t plane = samples_per_channel(brick_size);
  const std::size_t expected = plane * static_cast<std::size_t>(channels);
  if (planar.size() != expected) {
    throw std::invalid_argument("CachedBrick: " + std::to_string(planar.size()) +
                                " planar samples, a brick of size " + std::to_string(brick_size) +
                                " with " + std::to_string(channels) + " channels has " +
                                std::to_string(expected));
  }
  const int n = brick_size + 1;
  y_stride_ = static_cast<std::ptrdiff_t>(n) * channels;
  z_stride_ = y_stride_ * n;
  sample_bytes_ = sample_bytes(brick_size, channels);
  // Value-initialised, so the padding read by the 8-byte row loads is defined.
  samples_ = std::make_unique<uint8_t[]>(sample_bytes_);
  interleave_channels(planar.data(), plane, channels, samples_.get());
}

void CachedBrick::trilinear_other(const glm::ivec3& cell, const glm::vec3& frac, float* out) const {
  const uint8_t* s = sample(cell.x, cell.y, cell.z);
  switch (channels_) {
    case 1:
      trilinear_u8<1>(s, y_stride_, z_stride_, frac.x, frac.y, frac.z, out);
      return;
    case 2:
      trilinear_u8<2>(s, y_stride_, z_stride_, frac.x, frac.y, frac.z, out);
      return;
    case 3:
      trilinear_u8<3>(s, y_stride_, z_stride_, frac.x, frac.y, frac.z, out);
      return;
    case 4:
      trilinear_u8<4>(s, y_stride_, z_stride_, frac.x, frac.y, frac.z, out);
      return;
    default:
      trilinear_u8<5>(s, y_stride_, z_stride_, frac.x, frac.y, frac.z, out);
      return;
  }
}

}  // namespace soltex
