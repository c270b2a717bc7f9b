#pragma once

#include <cstddef>
#include <cstdint>

// Planar channel bytes (channel after channel, `plane` samples each) into interleaved samples
// (all of a sample's channels together), as CachedBrick stores them. Runtime-dispatched: a
// received brick's 3 × 4,913 bytes went one by one.
namespace soltex {

void interleave_channels(const uint8_t* planar, std::size_t plane, int channels, uint8_t* out);

// The Highway targets compiled into the kernel, and the one it dispatches to now (for tests that
// run each in turn).
int64_t interleave_compiled_targets();
int64_t interleave_dispatched_target();

}  // namespace soltex
