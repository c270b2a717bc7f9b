#include "soltex/common/cached_brick.h"

#include <stdexcept>
#include <string>

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
  uint8_t* out = samples_.get();
  for (std::size_t i = 0; i < plane; ++i) {
    for (int c = 0; c < channels; ++c) {
      *out++ = planar[static_cast<std::size_t>(c) * plane + i];
    }
  }
}

}  // namespace soltex
