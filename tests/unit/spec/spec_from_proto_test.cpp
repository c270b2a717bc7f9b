#include "soltex/spec_proto/spec_from_proto.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "soltex/common/spec_error.h"

namespace soltex {
namespace {

using ::testing::HasSubstr;

std::string error_field(const v1::TextureSpec& m) {
  try {
    (void)from_proto(m);
  } catch (const SpecError& e) {
    return e.field();
  }
  return "(no error)";
}

TEST(SpecFromProto, AbsentFieldsTakeTheDocumentedDefaults) {
  v1::TextureSpec m;
  m.mutable_marble();
  const TextureSpec spec = from_proto(m);
  const auto& marble = std::get<MarbleParams>(spec.pattern);
  const MarbleParams defaults;
  EXPECT_EQ(marble.frequency, defaults.frequency);
  EXPECT_EQ(marble.amplitude, defaults.amplitude);
  EXPECT_EQ(marble.turbulence.octave_max, defaults.turbulence.octave_max);
  EXPECT_EQ(marble.turbulence.scale, defaults.turbulence.scale);
  EXPECT_TRUE(spec.channels.colour);
  EXPECT_FALSE(spec.channels.opacity);
  EXPECT_FALSE(spec.ramp.keys.empty());
}

TEST(SpecFromProto, RoundTripsEveryPattern) {
  std::vector<v1::TextureSpec> messages(8);
  messages[0].mutable_stripes()->set_width(0.5);
  messages[1].mutable_checker()->set_three_d(true);
  messages[2].mutable_colour_cube()->set_period(2.0);
  messages[3].mutable_rings()->set_base(0.25);
  messages[4].mutable_wood()->set_twist(1.5);
  messages[5].mutable_noise()->set_basis(v1::NOISE_BASIS_GRADIENT);
  messages[6].mutable_turbulence()->mutable_fractal()->set_octave_max(7);
  messages[7].mutable_marble()->set_ripple(v1::RIPPLE_PRODUCT);
  messages[7].add_channels(v1::CHANNEL_COLOUR);
  messages[7].add_channels(v1::CHANNEL_SPECULAR);
  for (const auto& m : messages) {
    const TextureSpec spec = from_proto(m);
    const v1::TextureSpec canonical = to_proto(spec);
    const TextureSpec again = from_proto(canonical);
    EXPECT_EQ(to_proto(again).SerializeAsString(), canonical.SerializeAsString())
        << pattern_name(spec.pattern);
    EXPECT_EQ(again.pattern.index(), spec.pattern.index());
    EXPECT_EQ(again.channels, spec.channels);
  }
}

TEST(SpecFromProto, UnsetPatternIsAnError) {
  v1::TextureSpec m;
  try {
    (void)from_proto(m);
    FAIL() << "expected a SpecError";
  } catch (const SpecError& e) {
    EXPECT_EQ(e.field(), "pattern");
    EXPECT_THAT(e.what(), HasSubstr("exactly one of"));
  }
}

TEST(SpecFromProto, UnknownEnumValuesAreNamed) {
  v1::TextureSpec m;
  m.mutable_stripes()->set_axis(static_cast<v1::Axis>(7));
  EXPECT_EQ(error_field(m), "stripes.axis");
  v1::TextureSpec n;
  n.mutable_marble()->mutable_turbulence()->set_basis(static_cast<v1::NoiseBasis>(9));
  EXPECT_EQ(error_field(n), "marble.turbulence.basis");
  v1::TextureSpec c;
  c.mutable_noise();
  c.add_channels(static_cast<v1::Channel>(42));
  EXPECT_EQ(error_field(c), "channels[0]");
}

TEST(SpecFromProto, HugeUnsignedOctavesAreReportedAsSent) {
  v1::TextureSpec m;
  m.mutable_turbulence()->mutable_fractal()->set_octave_max(4000000000u);
  try {
    (void)from_proto(m);
    FAIL() << "expected a SpecError";
  } catch (const SpecError& e) {
    EXPECT_EQ(e.field(), "turbulence.fractal.octave_max");
    EXPECT_EQ(e.value(), "4000000000");
  }
}

TEST(SpecFromProto, InvalidValuesFailValidation) {
  v1::TextureSpec m;
  m.mutable_rings()->set_thickness(0.0);
  EXPECT_EQ(error_field(m), "rings.thickness");
}

TEST(VolumeFromProto, ConvertsAndValidates) {
  v1::Volume m;
  m.mutable_min()->set_x(-1);
  m.mutable_min()->set_y(-1);
  m.mutable_min()->set_z(-1);
  m.mutable_max()->set_x(1);
  m.mutable_max()->set_y(1);
  m.mutable_max()->set_z(1);
  m.set_finest_level_log2(9);
  const Volume v = from_proto(m);
  EXPECT_EQ(v.finest_level_log2, 9);
  EXPECT_EQ(v.min.x, -1.0);
  EXPECT_EQ(to_proto(v).SerializeAsString(), m.SerializeAsString());
  m.set_finest_level_log2(99);
  EXPECT_THROW((void)from_proto(m), SpecError);
  m.set_finest_level_log2(4);
  m.mutable_max()->set_z(-2);
  EXPECT_THROW((void)from_proto(m), SpecError);
}

}  // namespace
}  // namespace soltex
