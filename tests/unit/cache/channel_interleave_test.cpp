// interleave_channels (common/src/channel_interleave.cpp) on every Highway target the CPU runs,
// against the sample-by-sample definition, and CachedBrick's samples through it.

#include "channel_interleave.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "../texture/dispatch_targets.h"
#include "soltex/common/cached_brick.h"

namespace soltex {
namespace {

std::vector<uint8_t> random_bytes(std::size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint8_t> bytes(n);
  for (uint8_t& b : bytes) b = static_cast<uint8_t>(rng());
  return bytes;
}

TEST(ChannelInterleave, EveryTargetInterleavesAsTheDefinition) {
  const std::vector<int64_t> targets = test::targets_to_run(interleave_compiled_targets());
  ASSERT_FALSE(targets.empty());
  for (const int64_t target : targets) {
    const test::ForcedTarget forced(target);
    ASSERT_EQ(interleave_dispatched_target(), target) << hwy::TargetName(target);
    // A brick of 16 (17^3 samples), of 8, and planes shorter and longer than any vector.
    for (const std::size_t plane :
         {std::size_t{4913}, std::size_t{729}, std::size_t{1}, std::size_t{15}, std::size_t{65}}) {
      for (int channels = 1; channels <= CachedBrick::kMaxChannels; ++channels) {
        const auto count = static_cast<std::size_t>(channels);
        const std::vector<uint8_t> planar = random_bytes(plane * count, plane + count);
        // One byte past the end must stay as it was.
        std::vector<uint8_t> out(plane * count + 1, 0xA5);
        interleave_channels(planar.data(), plane, channels, out.data());
        for (std::size_t i = 0; i < plane; ++i) {
          for (std::size_t c = 0; c < count; ++c) {
            ASSERT_EQ(out[i * count + c], planar[c * plane + i])
                << hwy::TargetName(target) << " plane " << plane << " channels " << channels
                << " sample " << i << " channel " << c;
          }
        }
        EXPECT_EQ(out.back(), 0xA5) << hwy::TargetName(target);
      }
    }
  }
}

TEST(ChannelInterleave, CachedBrickHoldsEachSamplesChannelsTogether) {
  const int n = 17;
  const std::size_t plane = static_cast<std::size_t>(n) * n * n;
  const std::vector<uint8_t> planar = random_bytes(3 * plane, 7);
  const CachedBrick brick(16, 3, planar);
  for (int z = 0; z < n; z += 5) {
    for (int y = 0; y < n; y += 3) {
      for (int x = 0; x < n; ++x) {
        const std::size_t i = (static_cast<std::size_t>(z) * n + y) * n + x;
        const uint8_t* s = brick.sample(x, y, z);
        for (std::size_t c = 0; c < 3; ++c) ASSERT_EQ(s[c], planar[c * plane + i]);
      }
    }
  }
}

}  // namespace
}  // namespace soltex
