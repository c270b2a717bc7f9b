#pragma once

#include <cstddef>

namespace soltex::raster_internal {

// `count` lanes rounded up to whole blocks of `block`: the vector loops run whole blocks, as
// a loop's remainder would run a lane at a time.
constexpr std::size_t whole_blocks(std::size_t count, std::size_t block) {
  return (count + block - 1) / block * block;
}

}  // namespace soltex::raster_internal
