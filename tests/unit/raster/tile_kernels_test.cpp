// The tile kernels (client/raster/src/tile_kernels.cpp) on every Highway target the CPU runs:
// narrow spans drawn in vector lanes (draw_narrow) against the scalar loop of
// TileRasterizer::draw(), which a render that counts coverage takes for every triangle; a row's
// run starts against the pixel-by-pixel comparison.

#include "tile_kernels.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "../texture/dispatch_targets.h"
#include "raster_test_scenes.h"
#include "soltex/raster/rasterizer.h"
#include "tile_rasterizer.h"
#include "vertex_kernels.h"

namespace soltex {
namespace {

constexpr int kWidth = 200;
constexpr int kHeight = 150;

// Small triangles at random depths over the whole view, overlapping one another, crossing tile
// borders and the image's edges, in both windings, with slivers and some too big for the
// narrow path; and a fine sphere in front of part of them.
raster_test::Mesh crowd_of_small_triangles(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> centre_x(-10.0f, kWidth + 10.0f);
  std::uniform_real_distribution<float> centre_y(-10.0f, kHeight + 10.0f);
  std::uniform_real_distribution<float> depth(-0.9f, 0.9f);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  raster_test::Mesh mesh;
  for (int i = 0; i < 6000; ++i) {
    const float size = i % 50 == 0 ? 40.0f : (i % 7 == 0 ? 0.4f : 5.0f);
    const glm::vec3 centre(centre_x(rng), centre_y(rng), depth(rng));
    const auto first = static_cast<uint32_t>(mesh.positions.size());
    for (int k = 0; k < 3; ++k) {
      mesh.positions.push_back(centre +
                               glm::vec3(size * unit(rng), size * unit(rng), 0.05f * unit(rng)));
    }
    mesh.add_triangle(first, first + 1, first + 2);
  }
  return mesh;
}

GBuffer render(const RasterView& view, const std::vector<RasterObject>& objects, bool scalar) {
  Rasterizer rasterizer({.threads = 2, .count_coverage = scalar});
  GBuffer g;
  rasterizer.render(view, objects, g);
  return g;
}

template <typename T>
bool same_bytes(const GBufferPlane<T>& a, const GBufferPlane<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(NarrowDraw, EveryTargetDrawsNarrowSpansAsTheScalarLoop) {
  // Vertex and tile kernels are dispatched from the same target list.
  const std::vector<int64_t> targets =
      test::targets_to_run(raster_internal::vertex_kernels_compiled_targets());
  ASSERT_FALSE(targets.empty());
  const raster_test::Mesh crowd = crowd_of_small_triangles(11);
  const raster_test::Mesh sphere = raster_test::uv_sphere(120, 240, 30.0f);
  std::vector<RasterObject> objects(2);
  objects[0].mesh = crowd.view();
  objects[0].object_id = 1;
  objects[1].mesh = sphere.view();
  objects[1].model = glm::translate(glm::mat4(1.0f), glm::vec3(90.0f, 70.0f, 0.0f));
  objects[1].model = glm::scale(objects[1].model, glm::vec3(1.0f, 1.0f, 0.01f));
  objects[1].object_id = 2;
  objects[1].cull_back_faces = true;
  RasterView view;
  view.width = kWidth;
  view.height = kHeight;
  view.view_projection = raster_test::pixel_ortho(kWidth, kHeight);
  for (const int64_t target : targets) {
    const test::ForcedTarget forced(target);
    const std::string name = hwy::TargetName(target);
    const GBuffer lanes = render(view, objects, false);
    const GBuffer scalar = render(view, objects, true);
    EXPECT_TRUE(same_bytes(lanes.depth, scalar.depth)) << name;
    EXPECT_TRUE(same_bytes(lanes.flags, scalar.flags)) << name;
    EXPECT_TRUE(same_bytes(lanes.object_id, scalar.object_id)) << name;
    EXPECT_TRUE(same_bytes(lanes.texture_position, scalar.texture_position)) << name;
    EXPECT_TRUE(same_bytes(lanes.normal, scalar.normal)) << name;
    EXPECT_TRUE(same_bytes(lanes.footprint, scalar.footprint)) << name;
  }
}

TEST(RunStarts, EveryTargetFindsTheRunsOfARow) {
  const std::vector<int64_t> targets =
      test::targets_to_run(raster_internal::vertex_kernels_compiled_targets());
  // A tile's winner plane, padded as TileRasterizer's: runs of every length from 1 to 64,
  // empty pixels among them, rows of every width.
  std::array<raster_internal::ScreenTriangle, 5> triangles;
  std::vector<const raster_internal::ScreenTriangle*> plane(
      raster_internal::kTileSize * raster_internal::kTileSize + raster_internal::kPlanePadding);
  std::mt19937_64 rng(5);
  for (std::size_t i = 0; i < plane.size();) {
    const std::size_t length = 1 + rng() % (rng() % 4 == 0 ? 64 : 4);
    const auto* winner = rng() % 6 == 0 ? nullptr : &triangles[rng() % triangles.size()];
    for (std::size_t k = 0; k < length && i < plane.size(); ++k) plane[i++] = winner;
  }
  for (const int64_t target : targets) {
    const test::ForcedTarget forced(target);
    for (int row = 0; row < raster_internal::kTileSize; ++row) {
      const auto* winners = plane.data() + row * raster_internal::kTileSize;
      for (int count = 1; count <= raster_internal::kTileSize; ++count) {
        uint64_t expected = 1;
        for (int i = 1; i < count; ++i) {
          expected |= uint64_t{winners[i] != winners[i - 1]} << i;
        }
        ASSERT_EQ(raster_internal::run_starts(winners, count), expected)
            << hwy::TargetName(target) << " row " << row << " count " << count;
      }
    }
  }
}

}  // namespace
}  // namespace soltex
