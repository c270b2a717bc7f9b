// Quantization at exactly 0 and 1, and just past them: 1.0000001, -0, NaN, infinities.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/texture_sampler.h"
#include "soltex/render/image.h"

namespace soltex {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// The definition, written as a count: q is the number of thresholds (2k - 1) / 510,
// k = 1..255, that v reaches, so v exactly halfway between two codes takes the upper one
// (round half up). 510 v is exact in double for every float v.
int reference_quantize(float v) {
  if (std::isnan(v)) return 0;
  int q = 0;
  while (q < 255 && 510.0 * static_cast<double>(v) >= 2.0 * q + 1.0) ++q;
  return q;
}

// Expected: 0 and -0 give 0; 1, 1.0000001 and +inf give 255; NaN (either sign) and -inf give
// 0; the largest float below 1 still rounds to 255 and the smallest positive float to 0.
TEST(QuantizationEdges, StatedValues) {
  EXPECT_EQ(quantize(0.0f), 0);
  EXPECT_EQ(quantize(-0.0f), 0);
  EXPECT_EQ(quantize(1.0f), 255);
  EXPECT_EQ(quantize(1.0000001f), 255);
  EXPECT_EQ(quantize(kInf), 255);
  EXPECT_EQ(quantize(-kInf), 0);
  EXPECT_EQ(quantize(kNaN), 0);
  EXPECT_EQ(quantize(-kNaN), 0);
  EXPECT_EQ(quantize(std::nextafter(1.0f, 0.0f)), 255);
  EXPECT_EQ(quantize(std::numeric_limits<float>::denorm_min()), 0);
  EXPECT_EQ(quantize(-std::numeric_limits<float>::denorm_min()), 0);
}

// Every code's rounding boundary (k + 0.5) / 255 as a float, and its float neighbours on both
// sides, against the reference: exactly.
TEST(QuantizationEdges, EveryRoundingBoundaryMatchesTheReference) {
  for (int k = 0; k < 255; ++k) {
    const float boundary = static_cast<float>((k + 0.5) / 255.0);
    for (float v : {std::nextafter(boundary, 0.0f), boundary, std::nextafter(boundary, 2.0f)}) {
      EXPECT_EQ(quantize(v), reference_quantize(v)) << "k " << k << " v " << v;
    }
  }
}

// A sweep across [-0.01, 1.01] through the float bit patterns, every 257th (about 8 million
// values, all exponents from the subnormals up), against the reference: exactly.
TEST(QuantizationEdges, SweepMatchesTheReference) {
  // Non-negative floats: bits from +0 upwards. Negative ones: from -0.01 down to -0.
  for (uint32_t bits = 0; std::bit_cast<float>(bits) <= 1.01f; bits += 257u) {
    const float v = std::bit_cast<float>(bits);
    ASSERT_EQ(quantize(v), reference_quantize(v)) << v;
  }
  for (uint32_t bits = std::bit_cast<uint32_t>(-0.01f); bits >= 0x8000'0000u; bits -= 257u) {
    const float v = std::bit_cast<float>(bits);
    ASSERT_EQ(quantize(v), reference_quantize(v)) << v;
  }
}

TEST(QuantizationEdges, EveryCodeRoundTrips) {
  for (int q = 0; q < 256; ++q) {
    EXPECT_EQ(quantize(dequantize(static_cast<uint8_t>(q))), q);
  }
  EXPECT_EQ(dequantize(0), 0.0f);
  EXPECT_EQ(dequantize(255), 1.0f);
}

// Through the codec: a brick whose samples are the edge values decodes to their codes.
TEST(QuantizationEdges, EdgeValuesSurviveTheCodec) {
  const std::vector<float> edges = {0.0f, -0.0f, 1.0f, 1.0000001f, kNaN, kInf, -kInf, 0.5f};
  const std::vector<uint8_t> expected = {0, 0, 255, 255, 0, 255, 0, 128};
  const std::size_t size = brick_decoded_size(8, 1);
  std::vector<float> samples(size);
  for (std::size_t i = 0; i < size; ++i) samples[i] = edges[i % edges.size()];
  for (Codec codec : {Codec::raw, Codec::lz4, Codec::zstd}) {
    const DecodedBrick decoded =
        decode_brick(encode_brick(quantize(samples), 8, 1, CodecOptions{codec, 3, true}));
    for (std::size_t i = 0; i < size; ++i) {
      ASSERT_EQ(decoded.samples[i], expected[i % expected.size()]) << codec_name(codec) << " " << i;
    }
  }
}

// Through the cache: a brick of all 0 and one of all 255, sampled anywhere (corners, faces,
// the middle of cells), give exactly 0 and exactly 1 (equal corners interpolate to
// themselves; 255 * (1 / 255.f) rounds to 1).
TEST(QuantizationEdges, ConstantBricksSampleToExactlyZeroAndOne) {
  const BrickLayout layout(Volume{glm::dvec3(0.0), glm::dvec3(1.0), 3}, 8);
  for (int channels : {1, 3, 4, 5}) {
    for (uint8_t code : {uint8_t{0}, uint8_t{255}}) {
      BrickCache cache(std::size_t{1} << 20);
      const std::vector<uint8_t> planar(brick_decoded_size(8, channels), code);
      ASSERT_TRUE(cache.insert({7, 0, glm::ivec3(0)}, 8, channels, planar));
      TextureSampler sampler(cache, 7, layout, channels);
      for (const glm::dvec3& p : {glm::dvec3(0.0), glm::dvec3(1.0), glm::dvec3(0.5, 0.0625, 1.0),
                                  glm::dvec3(0.3, 0.71, 0.999)}) {
        for (SampleFilter filter : {SampleFilter::nearest, SampleFilter::trilinear}) {
          const SampleResult r = sampler.sample(p, 0.0, filter);
          ASSERT_EQ(r.level, 0);
          for (int c = 0; c < channels; ++c) {
            EXPECT_EQ(r.values[static_cast<std::size_t>(c)], code == 0 ? 0.0f : 1.0f)
                << "channels " << channels << " at " << p.x << " " << p.y << " " << p.z;
          }
        }
      }
    }
  }
}

// End to end: a two-colour pattern with a black-to-white ramp evaluates to exactly 0 and 1,
// which quantize to 0 and 255 and sample back to exactly 0 and 1 at the lattice points.
TEST(QuantizationEdges, ExactZeroAndOneTexturesStayExact) {
  TextureSpec spec;
  spec.pattern = CheckerParams{glm::dvec3(0.25), 0.0, true};
  spec.ramp.keys = {{0.0f, glm::vec3(0.0f)}, {1.0f, glm::vec3(1.0f)}};
  const TextureEvaluator texture(spec);
  const BrickLayout layout(Volume{glm::dvec3(0.0), glm::dvec3(1.0), 3}, 8);
  std::vector<float> samples(static_cast<std::size_t>(layout.samples_per_brick()) * 3);
  // Point-sampled: a band-limited level averages the checker's edges, which its vertices sit on.
  evaluate_brick(texture, layout, 0, glm::ivec3(0), MipSettings{MipMode::point, 2}, samples);
  for (float v : samples) ASSERT_TRUE(v == 0.0f || v == 1.0f) << v;
  const std::vector<uint8_t> codes = quantize(samples);
  for (uint8_t q : codes) ASSERT_TRUE(q == 0 || q == 255);
  BrickCache cache(std::size_t{1} << 20);
  ASSERT_TRUE(cache.insert({9, 0, glm::ivec3(0)}, 8, 3, codes));
  TextureSampler sampler(cache, 9, layout, 3);
  for (int i = 0; i <= 8; ++i) {
    const glm::dvec3 p(i / 8.0, (8 - i) / 8.0, 0.125 * (i % 3));
    const float expected = texture.sample(p).colour.r;
    EXPECT_EQ(sampler.sample(p, 0.0, SampleFilter::trilinear).values[0], expected) << i;
  }
}

// The image's own 8-bit conversion: 0 -> 0, 1 and above -> 255, -0 and NaN -> 0.
TEST(QuantizationEdges, ImagePixelsAtTheEdges) {
  Image image(2, 1);
  image.set(0, 0, 1.0000001f, -0.0f, kNaN);
  image.set(1, 0, 1.0f, 0.0f, kInf);
  EXPECT_EQ(image.rgb, (std::vector<uint8_t>{255, 0, 0, 255, 0, 255}));
}

}  // namespace
}  // namespace soltex
