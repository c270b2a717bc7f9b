// Seams at every level: the faces neighbouring bricks share hold the same samples, and lookups
// either side of a face agree.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/texture_sampler.h"

namespace soltex {
namespace {

TextureSpec marble_all_channels() {
  TextureSpec spec;
  spec.pattern = MarbleParams{};
  spec.channels = {true, true, true};
  spec.opacity = {0.2f, 0.9f};
  spec.specular = {0.0f, 0.6f};
  return validated(spec);
}

struct SeamCase {
  const char* name;
  Volume volume;
  MipSettings mip;
};

std::vector<SeamCase> seam_cases() {
  const Volume origin{glm::dvec3(-1.0), glm::dvec3(1.0), 6};
  const Volume negative{glm::dvec3(-3.0, -5.0, -1.5), glm::dvec3(-1.0, -3.0, 0.5), 6};
  const Volume far{glm::dvec3(1e9 - 1.0, -1e9 - 1.0, 1e6),
                   glm::dvec3(1e9 + 1.0, -1e9 + 1.0, 1e6 + 2.0), 6};
  return {{"origin, band-limited", origin, {MipMode::band_limited, 2}},
          {"origin, point", origin, {MipMode::point, 2}},
          {"origin, supersampled", origin, {MipMode::supersampled, 2}},
          {"negative, band-limited", negative, {MipMode::band_limited, 2}},
          {"far, band-limited", far, {MipMode::band_limited, 2}}};
}

// Every brick of every level, evaluated: [level][brick index].
using Bricks = std::vector<std::vector<std::vector<float>>>;

Bricks evaluate_all(const TextureEvaluator& texture, const BrickLayout& layout,
                    const MipSettings& mip) {
  Bricks bricks(static_cast<std::size_t>(layout.level_count()));
  const std::size_t size = static_cast<std::size_t>(layout.samples_per_brick()) *
                           static_cast<std::size_t>(texture.spec().channels.sample_count());
  for (int level = 0; level < layout.level_count(); ++level) {
    const int n = layout.bricks_per_axis(level);
    for (int z = 0; z < n; ++z) {
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
          std::vector<float> out(size);
          evaluate_brick(texture, layout, level, {x, y, z}, mip, out);
          bricks[static_cast<std::size_t>(level)].push_back(std::move(out));
        }
      }
    }
  }
  return bricks;
}

// Expected: for every pair of neighbouring bricks at every level, along every axis, every
// channel's samples on the shared face are the same float, bit for bit (each is computed from
// its global lattice index alone).
TEST(BrickSeams, SharedFacesAreBitIdenticalAtEveryLevel) {
  for (const SeamCase& c : seam_cases()) {
    SCOPED_TRACE(c.name);
    const TextureEvaluator texture(marble_all_channels());
    const BrickLayout layout(c.volume, 8);
    const Bricks bricks = evaluate_all(texture, layout, c.mip);
    const int s = layout.samples_per_axis(), b = layout.brick_size();
    const std::size_t plane = static_cast<std::size_t>(layout.samples_per_brick());
    const int channels = texture.spec().channels.sample_count();
    std::size_t faces = 0;
    for (int level = 0; level < layout.level_count(); ++level) {
      const int n = layout.bricks_per_axis(level);
      const auto at = [&](const glm::ivec3& brick) -> const std::vector<float>& {
        return bricks[static_cast<std::size_t>(level)]
                     [static_cast<std::size_t>((brick.z * n + brick.y) * n + brick.x)];
      };
      for (int axis = 0; axis < 3; ++axis) {
        glm::ivec3 step(0);
        step[axis] = 1;
        for (int z = 0; z < n; ++z) {
          for (int y = 0; y < n; ++y) {
            for (int x = 0; x < n; ++x) {
              const glm::ivec3 lo(x, y, z), hi = lo + step;
              if (hi[axis] >= n) continue;
              ++faces;
              const std::vector<float>& a = at(lo);
              const std::vector<float>& d = at(hi);
              for (int u = 0; u < s; ++u) {
                for (int v = 0; v < s; ++v) {
                  // The face coordinate on `axis`, the two free ones on the others.
                  const glm::ivec3 in_lo = axis == 0   ? glm::ivec3(b, u, v)
                                           : axis == 1 ? glm::ivec3(u, b, v)
                                                       : glm::ivec3(u, v, b);
                  glm::ivec3 in_hi = in_lo;
                  in_hi[axis] = 0;
                  const auto index = [&](const glm::ivec3& i) {
                    return static_cast<std::size_t>((i.z * s + i.y) * s + i.x);
                  };
                  for (int ch = 0; ch < channels; ++ch) {
                    const float va = a[static_cast<std::size_t>(ch) * plane + index(in_lo)];
                    const float vd = d[static_cast<std::size_t>(ch) * plane + index(in_hi)];
                    ASSERT_EQ(std::memcmp(&va, &vd, sizeof va), 0)
                        << "level " << level << " axis " << axis << " bricks (" << x << ", " << y
                        << ", " << z << ") channel " << ch << ": " << va << " vs " << vd;
                  }
                }
              }
            }
          }
        }
      }
    }
    // Per axis, n^2 (n - 1) faces at each level with n bricks per axis: 8, 4, 2, 1.
    EXPECT_EQ(faces, 3u * (64 * 7 + 16 * 3 + 4 * 1 + 0));
  }
}

// Through the cache, as a renderer reads it: quantized bricks of every level, sampled
// trilinearly a hair either side of each shared face (delta = 1e-4 of the level's spacing,
// still far above double's resolution at 1e9). Both lookups interpolate the same face
// samples; they can differ by the interpolant's slope over 2 delta (at most one full range
// per cell: 2e-4) plus the float kernel's rounding (a few 2^-24).
TEST(BrickSeams, LookupsEitherSideOfAFaceAgreeAtEveryLevel) {
  for (const SeamCase& c : seam_cases()) {
    SCOPED_TRACE(c.name);
    const TextureSpec spec = marble_all_channels();
    const TextureEvaluator texture(spec);
    const BrickLayout layout(c.volume, 8);
    const Bricks bricks = evaluate_all(texture, layout, c.mip);
    const int channels = spec.channels.sample_count();
    BrickCache cache(std::size_t{64} << 20);
    const uint64_t id = 42;
    for (int level = 0; level < layout.level_count(); ++level) {
      const int n = layout.bricks_per_axis(level);
      for (int i = 0; i < n * n * n; ++i) {
        const glm::ivec3 brick(i % n, (i / n) % n, i / (n * n));
        ASSERT_TRUE(cache.insert(
            {id, level, brick}, 8, channels,
            quantize(bricks[static_cast<std::size_t>(level)][static_cast<std::size_t>(i)])));
      }
    }
    TextureSampler sampler(cache, id, layout, channels);
    std::mt19937_64 rng(41);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::size_t checked = 0;
    for (int level = 0; level < layout.coarsest_level(); ++level) {
      const glm::dvec3 h = layout.spacing(level);
      const int n = layout.bricks_per_axis(level);
      for (int axis = 0; axis < 3; ++axis) {
        for (int face = 1; face < n; ++face) {
          for (int k = 0; k < 20; ++k) {
            glm::dvec3 p = c.volume.min + unit(rng) * (c.volume.max - c.volume.min);
            const double face_coordinate =
                c.volume.min[axis] + static_cast<double>(face * layout.brick_size()) * h[axis];
            glm::dvec3 below = p, above = p;
            below[axis] = face_coordinate - 1e-4 * h[axis];
            above[axis] = face_coordinate + 1e-4 * h[axis];
            const BrickKey key_below = sampler.brick_key(below, level);
            const BrickKey key_above = sampler.brick_key(above, level);
            ASSERT_EQ(key_below.brick[axis] + 1, key_above.brick[axis]);
            const SampleResult a = sampler.sample(below, level, SampleFilter::trilinear);
            const SampleResult b = sampler.sample(above, level, SampleFilter::trilinear);
            ASSERT_EQ(a.level, level);
            ASSERT_EQ(b.level, level);
            for (int ch = 0; ch < channels; ++ch) {
              ASSERT_NEAR(a.values[static_cast<std::size_t>(ch)],
                          b.values[static_cast<std::size_t>(ch)], 2e-4 + 1e-6)
                  << "level " << level << " axis " << axis << " face " << face << " channel " << ch;
            }
            ++checked;
          }
        }
      }
    }
    EXPECT_GT(checked, 0u);
  }
}

}  // namespace
}  // namespace soltex
