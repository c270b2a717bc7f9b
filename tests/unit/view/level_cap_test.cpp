#include "level_cap.h"

#include <gtest/gtest.h>

#include <climits>
#include <vector>

namespace soltex::view {
namespace {

constexpr uint64_t kFine = 0xF1;    // prepared at 2^8, bricks of 16: levels 0..4
constexpr uint64_t kCoarse = 0xC0;  // prepared at 2^6: levels 0..2

BrickLayout layout(int finest_log2) {
  Volume volume;
  volume.finest_level_log2 = finest_log2;
  return BrickLayout(volume, 16);
}

LevelCap two_textures() {
  LevelCap cap;
  cap.add_texture(kFine, layout(8), 3);
  cap.add_texture(kCoarse, layout(6), 3);
  return cap;
}

net::BrickWant want(uint64_t texture, int level, glm::ivec3 brick, uint32_t pixels = 1) {
  return {{texture, level, brick}, pixels};
}

std::vector<uint8_t> samples() {
  return std::vector<uint8_t>(17 * 17 * 17 * 3, 128);
}

TEST(LevelCap, StartsUncappedAndPassesWantsThrough) {
  const LevelCap cap = two_textures();
  EXPECT_EQ(cap.finest_log2(), 8);
  EXPECT_FALSE(cap.active());
  const std::vector<net::BrickWant> wants{want(kFine, 0, {15, 3, 7}), want(kCoarse, 0, {1, 2, 3})};
  const std::vector<net::BrickWant> out = cap.apply(wants);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].key, wants[0].key);
  EXPECT_EQ(out[1].key, wants[1].key);
}

// A brick below the cap becomes the brick the renderer falls back to: the one at the cap's
// level that contains it (each level halves the cells, so its index halves per level).
TEST(LevelCap, ReplacesABrickBelowTheCapByItsAncestorAtTheCap) {
  LevelCap cap = two_textures();
  cap.set_cap_log2(6);  // 2^6 samples: level 2 of the 2^8 texture, level 0 of the 2^6 one
  EXPECT_TRUE(cap.active());
  const std::vector<net::BrickWant> out =
      cap.apply({want(kFine, 0, {15, 3, 7}), want(kFine, 1, {5, 2, 0}), want(kFine, 3, {1, 0, 1}),
                 want(kCoarse, 0, {3, 2, 1})});
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0].key, (BrickKey{kFine, 2, {3, 0, 1}}));
  EXPECT_EQ(out[1].key, (BrickKey{kFine, 2, {2, 1, 0}}));
  EXPECT_EQ(out[2].key, (BrickKey{kFine, 3, {1, 0, 1}}));    // coarser than the cap: kept
  EXPECT_EQ(out[3].key, (BrickKey{kCoarse, 0, {3, 2, 1}}));  // not finer than the cap
  for (const net::BrickWant& w : out) {
    EXPECT_TRUE(layout(w.key.texture == kFine ? 8 : 6).contains(w.key.level, w.key.brick));
  }
}

TEST(LevelCap, MergesBricksWithTheSameAncestorAndAddsTheirPixels) {
  LevelCap cap = two_textures();
  cap.set_cap_log2(7);
  const std::vector<net::BrickWant> out = cap.apply(
      {want(kFine, 0, {0, 0, 0}, 10), want(kFine, 0, {1, 1, 1}, 20), want(kFine, 0, {2, 0, 0}, 5)});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].key, (BrickKey{kFine, 1, {0, 0, 0}}));
  EXPECT_EQ(out[0].screen_pixels, 30u);
  EXPECT_EQ(out[1].key, (BrickKey{kFine, 1, {1, 0, 0}}));
  EXPECT_EQ(out[1].screen_pixels, 5u);
}

TEST(LevelCap, ACapBelowTheBrickSizeStopsAtTheCoarsestLevel) {
  LevelCap cap = two_textures();
  cap.set_cap_log2(1);
  const std::vector<net::BrickWant> out = cap.apply({want(kFine, 0, {15, 15, 15})});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].key, (BrickKey{kFine, 4, {0, 0, 0}}));  // 2^8 / 16: level 4 is one brick
}

TEST(LevelCap, UnknownTexturesPassThroughAndCostNothing) {
  LevelCap cap = two_textures();
  cap.set_cap_log2(5);
  const std::vector<net::BrickWant> wants{want(0x99, 0, {9, 9, 9})};
  EXPECT_EQ(cap.apply(wants)[0].key, wants[0].key);
  EXPECT_EQ(cap.cache_bytes(wants), 0u);
  EXPECT_EQ(cap.cache_bytes({want(kFine, 0, {0, 0, 0})}), BrickCache::charged_bytes(16, 3));
}

TEST(LevelCap, NotResidentDropsWhatTheCacheHolds) {
  BrickCache cache(8u << 20);
  ASSERT_TRUE(cache.insert({kFine, 2, {0, 0, 0}}, 16, 3, samples()));
  const std::vector<net::BrickWant> left =
      not_resident({want(kFine, 2, {0, 0, 0}), want(kFine, 2, {1, 0, 0})}, cache);
  ASSERT_EQ(left.size(), 1u);
  EXPECT_EQ(left[0].key, (BrickKey{kFine, 2, {1, 0, 0}}));
}

// Refining lifts the cap as far as the cache holds what the finer levels ask for, and
// never further: a picture that had to evict its own bricks would never converge.
TEST(LevelCap, NextCapGoesAsFarAsTheCacheBudgetHolds) {
  LevelCap cap = two_textures();
  cap.set_cap_log2(5);
  // A frame wanting 64 bricks at level 0 of the 2^8 texture: 64 at 2^8, 8 at 2^7, 1 at 2^6.
  std::vector<net::BrickWant> misses;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) misses.push_back(want(kFine, 0, {x, y, z}));
  const std::size_t brick = BrickCache::charged_bytes(16, 3);

  BrickCache roomy(1000 * brick);
  EXPECT_EQ(next_cap(cap, misses, roomy, INT_MAX), 8);  // headless: all the way at once
  EXPECT_EQ(next_cap(cap, misses, roomy, 1), 6);        // the window: one level at a time

  BrickCache tight(20 * brick);  // 8 bricks fit in 90 % of it, 64 do not
  EXPECT_EQ(next_cap(cap, misses, tight, 100), 7);

  BrickCache tiny(brick / 2);  // not even one brick more
  EXPECT_EQ(next_cap(cap, misses, tiny, 100), 5);

  cap.set_cap_log2(8);
  EXPECT_EQ(next_cap(cap, misses, roomy, 100), 8);  // uncapped: nothing to lift
}

}  // namespace
}  // namespace soltex::view
