#include "soltex/common/texture_id.h"

#include <gtest/gtest.h>

namespace soltex {
namespace {

TextureSpec marble_spec() {
  TextureSpec spec;
  spec.pattern = MarbleParams{};
  return validated(spec);
}

Volume unit_volume() {
  Volume v;
  v.min = glm::dvec3(-1.0);
  v.max = glm::dvec3(1.0);
  v.finest_level_log2 = 8;
  return v;
}

TEST(TextureId, GoldenValueIsStableAcrossProcessesAndBuilds) {
  // The id is part of the protocol: clients and servers of different builds must agree.
  // A change here changes every cached brick's name; bump the format tag if it is intended.
  EXPECT_EQ(texture_id_hex(texture_id(marble_spec(), unit_volume(), 16)), "e443b7e968f01c59");
  TextureSpec stripes;
  stripes.pattern = StripesParams{};
  EXPECT_EQ(texture_id_hex(texture_id(stripes, unit_volume(), 8)), "6b67317809217548");
}

TEST(TextureId, EveryInputChangesTheId) {
  const uint64_t base = texture_id(marble_spec(), unit_volume(), 16);
  EXPECT_NE(texture_id(marble_spec(), unit_volume(), 8), base);
  Volume v = unit_volume();
  v.finest_level_log2 = 9;
  EXPECT_NE(texture_id(marble_spec(), v, 16), base);
  v = unit_volume();
  v.max.z = 1.5;
  EXPECT_NE(texture_id(marble_spec(), v, 16), base);
  TextureSpec spec = marble_spec();
  std::get<MarbleParams>(spec.pattern).turbulence.octave_max = 4;
  EXPECT_NE(texture_id(spec, unit_volume(), 16), base);
  spec = marble_spec();
  spec.channels.specular = true;
  EXPECT_NE(texture_id(spec, unit_volume(), 16), base);
  EXPECT_NE(texture_id(marble_spec(), unit_volume(), 16, {MipMode::point, 2}), base);
  EXPECT_NE(texture_id(marble_spec(), unit_volume(), 16, {MipMode::supersampled, 2}),
            texture_id(marble_spec(), unit_volume(), 16, {MipMode::supersampled, 3}));
  // The supersample count only matters when supersampling.
  EXPECT_EQ(texture_id(marble_spec(), unit_volume(), 16, {MipMode::band_limited, 3}), base);
  spec = marble_spec();
  spec.ramp.keys[1].colour.r = 0.5f;
  EXPECT_NE(texture_id(spec, unit_volume(), 16), base);
}

TEST(TextureId, DefaultRampAndExplicitDefaultRampAreTheSameTexture) {
  TextureSpec implicit;
  implicit.pattern = MarbleParams{};
  EXPECT_EQ(texture_id(implicit, unit_volume(), 16), texture_id(marble_spec(), unit_volume(), 16));
}

TEST(TextureId, NegativeZeroIsZero) {
  TextureSpec a, b;
  a.pattern = StripesParams{1.0, 0.0, Axis::x};
  b.pattern = StripesParams{1.0, -0.0, Axis::x};
  EXPECT_EQ(texture_id(a, unit_volume(), 16), texture_id(b, unit_volume(), 16));
}

}  // namespace
}  // namespace soltex
