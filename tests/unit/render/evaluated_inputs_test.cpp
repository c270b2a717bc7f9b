// evaluated_inputs() in vector lanes against texture_surface.h's functions pixel by pixel:
// the same point and box, bit for bit, including a zero normal, non-positive, NaN and infinite
// footprints, and a singular-free but skewed normal map.
#include "evaluated_inputs.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <random>

#include "texture_surface.h"

namespace soltex::render {
namespace {

uint64_t bits(double v) {
  return std::bit_cast<uint64_t>(v);
}

TEST(EvaluatedInputs, MatchInsetAndSurfaceFootprintBitForBit) {
  const glm::dmat3 normal_from_world(0.7, -0.2, 0.1, 0.3, 1.4, -0.5, -0.05, 0.25, 0.9);
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  const float kInfinity = std::numeric_limits<float>::infinity();
  const float kNaN = std::numeric_limits<float>::quiet_NaN();
  const float special[] = {0.0f, -0.0f, -0.01f, kNaN, kInfinity, 1e-30f, 3.0f};
  EvaluatedLanes lanes;
  const std::size_t count = EvaluatedLanes::kCapacity - 3;  // a remainder for every target
  for (std::size_t l = 0; l < count; ++l) {
    lanes.position_x[l] = 1e6 * unit(random);
    lanes.position_y[l] = unit(random);
    lanes.position_z[l] = -1e-3 * unit(random);
    const bool zero_normal = l % 11 == 0;
    lanes.normal_x[l] = zero_normal ? 0.0f : unit(random);
    lanes.normal_y[l] = zero_normal ? 0.0f : unit(random);
    lanes.normal_z[l] = zero_normal ? 0.0f : unit(random);
    lanes.footprint[l] =
        l % 5 == 0 ? special[(l / 5) % std::size(special)] : 0.05f * (unit(random) + 1.0f);
  }
  evaluated_inputs(normal_from_world, lanes, count);

  // TextureSurface's map, through the scalar functions TileShader used pixel by pixel.
  const auto normal = [&](const glm::vec3& world) {
    const glm::dvec3 n = normal_from_world * glm::dvec3(world);
    const double length = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
    return length > 0.0 ? n / length : glm::dvec3(0.0);
  };
  for (std::size_t l = 0; l < count; ++l) {
    const glm::dvec3 n = normal({lanes.normal_x[l], lanes.normal_y[l], lanes.normal_z[l]});
    const double footprint = lanes.footprint[l];
    const glm::dvec3 p(lanes.position_x[l], lanes.position_y[l], lanes.position_z[l]);
    const glm::dvec3 point = inset(p, n, kEvaluatedInset * footprint);
    const SampleFootprint box = surface_footprint(footprint, n);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(bits(lanes.points[l][c]), bits(point[c])) << "lane " << l << " axis " << c;
      EXPECT_EQ(bits(lanes.footprints[l].box[c]), bits(box.box[c])) << "lane " << l;
    }
    EXPECT_EQ(bits(lanes.footprints[l].width), bits(box.width)) << "lane " << l;
  }
}

}  // namespace
}  // namespace soltex::render
