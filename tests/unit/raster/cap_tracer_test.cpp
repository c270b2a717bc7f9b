// CapTracer::trace_run() (a run of pixels in vector lanes) against CapTracer::trace() pixel by
// pixel: the same hits and the same samples, bit for bit, over rows that cross two clip
// planes, rays that never enter, and a run on a tile's last row.
#include "cap_tracer.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <vector>

namespace soltex::raster_internal {
namespace {

uint64_t bits(double v) {
  return std::bit_cast<uint64_t>(v);
}
uint32_t bits(float v) {
  return std::bit_cast<uint32_t>(v);
}

TEST(CapTracer, RunInLanesMatchesPixelByPixelBitForBit) {
  constexpr int kWidth = 160, kHeight = 96;
  const glm::dmat4 projection =
      glm::perspective(glm::radians(50.0), double{kWidth} / kHeight, 0.1, 100.0);
  const glm::dmat4 view =
      glm::lookAt(glm::dvec3(0.3, 0.8, 4.0), glm::dvec3(0.0), glm::dvec3(0.0, 1.0, 0.0));
  // Two planes through the middle of the view, one tilted away: some rays enter through
  // one, some through the other, some start inside both, and a plane seen edge-on misses.
  const std::vector<glm::dvec4> planes = {
      {0.5, 0.4, 1.0, -0.2}, {-1.0, 0.2, -0.1, 0.05}, {0.0, 0.0, 1.0, -4.5}};
  RasterView raster_view;
  raster_view.width = kWidth;
  raster_view.height = kHeight;
  raster_view.view_projection = glm::mat4(projection * view);
  raster_view.clip_planes = planes;
  const CapTracer tracer(raster_view);
  const glm::dmat4 texture_from_world =
      glm::scale(glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(1e6, -3.0, 0.25)), 0.4,
                             glm::dvec3(0.2, 1.0, 0.3)),
                 glm::dvec3(2.0, 0.5, 1.5));

  int hits = 0, misses = 0;
  for (const uint32_t mask : {0b011u, 0b111u, 0b010u}) {
    for (const int y : {0, 17, 40, 63, 95}) {
      // Runs of every length from one tile's first column, and one starting mid-tile.
      for (const auto& [x0, x_begin, x_end] :
           {std::tuple{0, 0, 64}, std::tuple{64, 70, 75}, std::tuple{128, 128, 129}}) {
        CapRayRows lanes_rows, pixel_rows;
        lanes_rows.begin(x0, y);
        pixel_rows.begin(x0, y);
        CapRayLanes rays;
        CapPixelLanes lanes;
        tracer.trace_run(x_begin, x_end, y, texture_from_world, mask, lanes_rows, rays, lanes);
        for (int x = x_begin; x < x_end; ++x) {
          const auto k = static_cast<std::size_t>(x - x_begin);
          CapSample sample;
          const bool hit = tracer.trace(x, y, texture_from_world, mask, pixel_rows, sample);
          ASSERT_EQ(lanes.hit[k] != 0, hit) << "pixel " << x << ", " << y << " mask " << mask;
          if (!hit) {
            ++misses;
            continue;
          }
          ++hits;
          EXPECT_EQ(bits(lanes.texture_x[k]), bits(sample.texture_position.x));
          EXPECT_EQ(bits(lanes.texture_y[k]), bits(sample.texture_position.y));
          EXPECT_EQ(bits(lanes.texture_z[k]), bits(sample.texture_position.z));
          EXPECT_EQ(bits(lanes.normal_x[k]), bits(sample.normal.x));
          EXPECT_EQ(bits(lanes.normal_y[k]), bits(sample.normal.y));
          EXPECT_EQ(bits(lanes.normal_z[k]), bits(sample.normal.z));
          EXPECT_EQ(bits(lanes.depth[k]), bits(sample.depth)) << "pixel " << x << ", " << y;
          EXPECT_EQ(bits(lanes.footprint[k]), bits(sample.footprint)) << "pixel " << x << ", " << y;
        }
      }
    }
  }
  // Both outcomes were compared.
  EXPECT_GT(hits, 100);
  EXPECT_GT(misses, 10);
}

}  // namespace
}  // namespace soltex::raster_internal
