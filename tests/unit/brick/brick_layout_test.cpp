#include "soltex/common/brick_layout.h"

#include <gtest/gtest.h>

#include "soltex/common/spec_error.h"

namespace soltex {
namespace {

Volume unit_volume(int finest_level_log2) {
  Volume v;
  v.min = glm::dvec3(-1.0);
  v.max = glm::dvec3(1.0);
  v.finest_level_log2 = finest_level_log2;
  return v;
}

TEST(BrickLayout, LevelsRunFromFinestToOneBrick) {
  const BrickLayout layout(unit_volume(8), 16);
  EXPECT_EQ(layout.brick_shift(), 4);
  EXPECT_EQ(layout.samples_per_axis(), 17);
  EXPECT_EQ(layout.samples_per_brick(), 17 * 17 * 17);
  EXPECT_EQ(layout.level_count(), 5);  // 256, 128, 64, 32, 16 cells
  EXPECT_EQ(layout.cells_per_axis(0), 256);
  EXPECT_EQ(layout.cells_per_axis(4), 16);
  EXPECT_EQ(layout.bricks_per_axis(0), 16);
  EXPECT_EQ(layout.bricks_per_axis(layout.coarsest_level()), 1);
  EXPECT_EQ(layout.brick_count(0), 4096u);
}

TEST(BrickLayout, SpacingDoublesExactlyPerLevel) {
  const BrickLayout layout(unit_volume(9), 8);
  for (int l = 1; l < layout.level_count(); ++l) {
    EXPECT_EQ(layout.spacing(l), 2.0 * layout.spacing(l - 1));
  }
  EXPECT_EQ(layout.spacing(0).x, 2.0 / 512.0);
  EXPECT_EQ(layout.filter_width(2), 4.0 * 2.0 / 512.0);
}

TEST(BrickLayout, GlobalLocalSplitOfSampleIndices) {
  const BrickLayout layout(unit_volume(8), 16);
  // Sample index i of a level belongs to brick i >> 4 at local index i & 15; the last sample
  // of a brick (local 16) is the first of the next.
  const Grid g0 = layout.sample_grid(0, {0, 0, 0});
  const Grid g1 = layout.sample_grid(0, {1, 0, 0});
  EXPECT_EQ(g1.first.x, 16);
  EXPECT_EQ(g0.point(16, 0, 0), g1.point(0, 0, 0));
  EXPECT_EQ(g0.point(0, 0, 0), glm::dvec3(-1.0));
  const Grid last = layout.sample_grid(0, {15, 15, 15});
  EXPECT_EQ(last.point(16, 16, 16), glm::dvec3(1.0));
}

TEST(BrickLayout, ContainsChecksLevelAndCoordinates) {
  const BrickLayout layout(unit_volume(8), 16);
  EXPECT_TRUE(layout.contains(0, {15, 0, 15}));
  EXPECT_FALSE(layout.contains(0, {16, 0, 0}));
  EXPECT_FALSE(layout.contains(0, {-1, 0, 0}));
  EXPECT_TRUE(layout.contains(4, {0, 0, 0}));
  EXPECT_FALSE(layout.contains(4, {1, 0, 0}));
  EXPECT_FALSE(layout.contains(5, {0, 0, 0}));
  EXPECT_FALSE(layout.contains(-1, {0, 0, 0}));
}

TEST(BrickLayout, SampleCoordinate) {
  const BrickLayout layout(unit_volume(8), 16);
  EXPECT_EQ(layout.sample_coordinate(glm::dvec3(0.0), 0), glm::dvec3(128.0));
  EXPECT_EQ(layout.sample_coordinate(glm::dvec3(1.0), 2), glm::dvec3(64.0));
}

TEST(BrickLayout, RejectsBadBrickSizesAndTooSmallVolumes) {
  try {
    BrickLayout layout(unit_volume(8), 12);
    FAIL();
  } catch (const SpecError& e) {
    EXPECT_EQ(e.field(), "brick_size");
    EXPECT_STREQ(e.what(), "brick_size = 12: must be 8 or 16");
  }
  try {
    BrickLayout layout(unit_volume(3), 16);
    FAIL();
  } catch (const SpecError& e) {
    EXPECT_EQ(e.field(), "volume.finest_level_log2");
  }
  EXPECT_NO_THROW(BrickLayout(unit_volume(3), 8));
}

}  // namespace
}  // namespace soltex
