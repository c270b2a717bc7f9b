// The tile kernels (client/raster/src/tile_kernels.cpp) on every Highway target the CPU runs:
// a row's run starts against the pixel-by-pixel comparison, drawing in vector lanes against
// the rasterizer's fragment-by-fragment loop, and the short runs' gathered lanes against
// SurfaceLanes::set_lane().

#include "tile_kernels.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "../texture/dispatch_targets.h"
#include "raster_test_scenes.h"
#include "soltex/raster/rasterizer.h"
#include "tile_rasterizer.h"

namespace soltex {
namespace {

TEST(RunStarts, EveryTargetFindsTheRunsOfARow) {
  const std::vector<int64_t> targets =
      test::targets_to_run(raster_internal::tile_kernels_compiled_targets());
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

// Triangles from under a pixel to several tiles wide (so both the 32-bit and 64-bit lanes draw),
// at random depths and facing both ways, overlapping: drawn in vector lanes on each target (a
// tile's bin at a time, the large ones handed back to TileRasterizer::draw()), they leave the
// G-buffer and fragment counts that counting coverage gives, which draws every fragment one
// at a time.
TEST(DrawKernels, EveryTargetDrawsWhatTheFragmentLoopDraws) {
  const std::vector<int64_t> targets =
      test::targets_to_run(raster_internal::tile_kernels_compiled_targets());
  constexpr int kWidth = 200, kHeight = 150;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  raster_test::Mesh mesh;
  for (uint32_t i = 0; i < 3000; ++i) {
    // Sizes spread over a log scale: a third from 0.3 to 600 pixels (tiles wholly inside some,
    // cut at one corner by others), the rest mostly small.
    const float size = 0.3f * std::pow(i % 3 == 0 ? 2000.0f : 700.0f,
                                       i % 3 == 0 ? unit(rng) : unit(rng) * unit(rng));
    const glm::vec2 centre(unit(rng) * kWidth, unit(rng) * kHeight);
    // Half of them flat at one of four depths, so that equal depths meet (the first one keeps
    // the pixel); the others sloped.
    const float flat = i % 2 == 0 ? -0.25f * static_cast<float>(rng() % 4) : 1.0f;
    for (int k = 0; k < 3; ++k) {
      const glm::vec2 p = centre + size * glm::vec2(unit(rng) - 0.5f, unit(rng) - 0.5f);
      mesh.positions.push_back({p.x, p.y, flat <= 0.0f ? flat : -unit(rng)});
    }
    mesh.add_triangle(3 * i, 3 * i + 1, 3 * i + 2);
  }
  RasterObject object;
  object.mesh = mesh.view();
  object.closed = false;
  const RasterView view{kWidth, kHeight, raster_test::pixel_ortho(kWidth, kHeight), {}};
  GBuffer reference;
  Rasterizer counting({.threads = 1, .count_coverage = true});
  const RasterStats expected = counting.render(view, std::span(&object, 1), reference);
  ASSERT_GT(expected.fragments_depth_passed, 20000u);
  for (const int64_t target : targets) {
    const test::ForcedTarget forced(target);
    Rasterizer rasterizer({.threads = 1});
    GBuffer g;
    const RasterStats stats = rasterizer.render(view, std::span(&object, 1), g);
    SCOPED_TRACE(hwy::TargetName(target));
    raster_test::expect_same_buffer(g, reference);
    EXPECT_EQ(stats.fragments_rasterized, expected.fragments_rasterized);
    EXPECT_EQ(stats.fragments_depth_passed, expected.fragments_depth_passed);
  }
}

// Lanes of triangles with positions anywhere in the clamped range, areas up to the largest
// the range allows, and attributes of every bit pattern (NaN, infinities, subnormals among
// them), at pixels across the largest frame, in batches of every size: gathered on each
// target, every lane up to the batch's size holds set_lane()'s bits.
TEST(SurfaceLanes, EveryTargetGathersWhatSetLaneSets) {
  using raster_internal::ScreenTriangle;
  using raster_internal::SurfaceLanes;
  const std::vector<int64_t> targets =
      test::targets_to_run(raster_internal::tile_kernels_compiled_targets());
  std::mt19937_64 rng(17);
  constexpr int32_t kLimit = 1 << 24;  // subpixel_position()'s clamp
  const auto position = [&] {
    return rng() % 8 == 0 ? (rng() % 2 == 0 ? kLimit : -kLimit)
                          : static_cast<int32_t>(rng() % (2 * kLimit + 1)) - kLimit;
  };
  const auto any_float = [&] { return std::bit_cast<float>(static_cast<uint32_t>(rng())); };
  std::vector<ScreenTriangle> triangles(4 * SurfaceLanes::kCapacity);  // zeroed
  for (ScreenTriangle& t : triangles) {
    for (std::size_t k = 0; k < 3; ++k) {
      t.x[k] = position();
      t.y[k] = position();
      t.inv_w[k] = any_float();
      t.texture_offset[k] = glm::vec3(any_float(), any_float(), any_float());
      t.normal[k] = glm::vec3(any_float(), any_float(), any_float());
    }
    // Any value an area of such positions can take (below 2^51 in magnitude), odd ones
    // included, so that rounding to float is exercised.
    t.double_area = static_cast<int64_t>(rng() % (uint64_t{1} << 52)) - (int64_t{1} << 51);
  }
  const auto planes = [](const SurfaceLanes& s) {
    std::vector<const std::array<float, SurfaceLanes::kCapacity>*> all = {&s.area};
    for (std::size_t k = 0; k < 3; ++k) {
      for (const auto* plane : {&s.edge[k], &s.edge_dy[k], &s.edge_dx[k], &s.q[k], &s.ox[k],
                                &s.oy[k], &s.oz[k], &s.nx[k], &s.ny[k], &s.nz[k]}) {
        all.push_back(plane);
      }
    }
    return all;
  };
  for (const int64_t target : targets) {
    const test::ForcedTarget forced(target);
    SCOPED_TRACE(hwy::TargetName(target));
    for (std::size_t count = 0; count <= SurfaceLanes::kCapacity; ++count) {
      std::vector<const ScreenTriangle*> lane_triangle(count);
      std::vector<int> x(count), y(count);
      auto expected = std::make_unique<SurfaceLanes>();
      auto gathered = std::make_unique<SurfaceLanes>();
      for (std::size_t l = 0; l < count; ++l) {
        lane_triangle[l] = &triangles[rng() % triangles.size()];
        x[l] = static_cast<int>(rng() % RasterView::kMaxSize);
        y[l] = static_cast<int>(rng() % RasterView::kMaxSize);
        expected->set_lane(l, *lane_triangle[l], x[l], y[l]);
      }
      raster_internal::gather_surface_lanes(lane_triangle.data(), x.data(), y.data(), count,
                                            *gathered);
      const auto want = planes(*expected), got = planes(*gathered);
      for (std::size_t p = 0; p < want.size(); ++p) {
        for (std::size_t l = 0; l < count; ++l) {
          ASSERT_EQ(std::bit_cast<uint32_t>((*got[p])[l]), std::bit_cast<uint32_t>((*want[p])[l]))
              << "plane " << p << " lane " << l << " of " << count;
        }
      }
    }
  }
}

}  // namespace
}  // namespace soltex
