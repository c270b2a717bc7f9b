#include "soltex/render/shading.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <glm/geometric.hpp>
#include <limits>
#include <random>

namespace soltex {
namespace {

uint32_t bits(float v) {
  return std::bit_cast<uint32_t>(v);
}

PreparedLights test_lights() {
  PreparedLights lights;
  lights.ambient = glm::vec3(0.18f, 0.17f, 0.2f);
  lights.directional.push_back({glm::normalize(glm::vec3(0.4f, 1.0f, 0.5f)), {0.85f, 0.8f, 0.7f}});
  lights.directional.push_back({glm::normalize(glm::vec3(-1.0f, 0.2f, 0.1f)), {0.2f, 0.3f, 0.4f}});
  lights.point.push_back({glm::dvec3(2.0, 1.5, 2.5), {2.4f, 2.5f, 3.0f}});
  lights.point.push_back({glm::dvec3(1e6 + 0.25, -3.0, 1e6), {1e12f, 1e12f, 1e12f}});
  return lights;
}

// Random unit vectors, random albedo, specular 0 or not, and the edge cases shade() branches on:
// a point at a light's position, normals facing away, a zero-length half vector.
TEST(ShadeBatch, EqualsShadeBitForBit) {
  const PreparedLights lights = test_lights();
  std::mt19937 random(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), positive(0.0f, 1.0f);
  std::uniform_real_distribution<double> place(-5.0, 5.0);
  const auto direction = [&] {
    const glm::vec3 v(unit(random), unit(random), unit(random));
    return glm::length(v) > 0.0f ? glm::normalize(v) : glm::vec3(0.0f, 0.0f, 1.0f);
  };
  for (int round = 0; round < 40; ++round) {
    ShadeBatch batch;
    batch.count = ShadeBatch::kCapacity - round;
    struct Input {
      glm::vec3 albedo;
      float specular, shininess;
      glm::dvec3 position;
      glm::vec3 normal, to_viewer;
    };
    std::vector<Input> inputs;
    for (int i = 0; i < batch.count; ++i) {
      Input in{{positive(random), positive(random), positive(random)},
               i % 3 == 0 ? 0.0f : positive(random),
               1.0f + 100.0f * positive(random),
               {place(random), place(random), place(random)},
               direction(),
               direction()};
      if (i % 17 == 1) in.position = lights.point[0].position;
      if (i % 19 == 2) in.position = lights.point[1].position + glm::dvec3(1e-3);
      if (i % 23 == 3) in.to_viewer = -lights.directional[0].to_light;
      if (i % 29 == 4) in.normal = -in.to_viewer;
      inputs.push_back(in);
      const auto l = static_cast<std::size_t>(i);
      batch.albedo_r[l] = in.albedo.r;
      batch.albedo_g[l] = in.albedo.g;
      batch.albedo_b[l] = in.albedo.b;
      batch.specular[l] = in.specular;
      batch.shininess[l] = in.shininess;
      batch.position_x[l] = in.position.x;
      batch.position_y[l] = in.position.y;
      batch.position_z[l] = in.position.z;
      batch.normal_x[l] = in.normal.x;
      batch.normal_y[l] = in.normal.y;
      batch.normal_z[l] = in.normal.z;
      batch.to_viewer_x[l] = in.to_viewer.x;
      batch.to_viewer_y[l] = in.to_viewer.y;
      batch.to_viewer_z[l] = in.to_viewer.z;
    }
    shade_batch(lights, batch);
    for (int i = 0; i < batch.count; ++i) {
      const Input& in = inputs[static_cast<std::size_t>(i)];
      const glm::vec3 expected =
          shade(lights, in.albedo, in.specular, in.shininess, in.position, in.normal, in.to_viewer);
      const auto l = static_cast<std::size_t>(i);
      ASSERT_EQ(bits(batch.colour_r[l]), bits(expected.r)) << "lane " << i;
      ASSERT_EQ(bits(batch.colour_g[l]), bits(expected.g)) << "lane " << i;
      ASSERT_EQ(bits(batch.colour_b[l]), bits(expected.b)) << "lane " << i;
    }
  }
}

}  // namespace
}  // namespace soltex
