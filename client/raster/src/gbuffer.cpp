#include "soltex/raster/gbuffer.h"

namespace soltex {

void GBuffer::resize(int new_width, int new_height, bool count_coverage) {
  width = new_width;
  height = new_height;
  const std::size_t pixels = pixel_count();
  depth.resize(pixels);
  flags.resize(pixels);
  object_id.resize(pixels);
  texture_position.resize(pixels);
  normal.resize(pixels);
  footprint.resize(pixels);
  footprint_axis.resize(pixels);
  footprint_minor.resize(pixels);
  coverage_count.resize(count_coverage ? pixels : 0);
}

}  // namespace soltex
