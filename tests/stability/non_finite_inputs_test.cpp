// NaN and infinity in a scene transform or a texture parameter: refused with an error that
// names the field, or, where no validation stands between them and the rasterizer (a scene
// built in code), kept away from every pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "soltex/common/spec_error.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/common/value_noise.h"
#include "soltex/scene/builtin_meshes.h"
#include "soltex/scene/scene_error.h"
#include "soltex/scene/scene_loader.h"
#include "stability_scene.h"

namespace soltex {
namespace {

// Whether `text` contains `part`, with both in the failure message.
::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\"" << text << "\" does not contain \"" << part << "\"";
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- Scene files -----------------------------------------------------------------------------

// JSON has no NaN or infinity: the only way to write one is a number too large for a double.
std::string scene_with(const std::string& transform, const std::string& marble = "{}") {
  return R"({"objects": [{"name": "ball", "mesh": "sphere",
             "material": {"texture": {"marble": )" +
         marble + R"(}},
             "transform": )" +
         transform + "}]}";
}

SceneError parse_error(const std::string& text) {
  try {
    parse_scene(text, "far.json");
  } catch (const SceneError& error) {
    return error;
  }
  ADD_FAILURE() << "accepted: " << text;
  return SceneError("far.json", "", "accepted");
}

struct OverflowCase {
  std::string text;  // a scene file
  std::string path;  // the JSON path of the number that overflows
  std::string literal;
};

std::vector<OverflowCase> overflow_cases() {
  return {
      {scene_with(R"({"translate": [1e999, 0, 0]})"), "objects[0].transform.translate", "1e999"},
      {scene_with(R"({"translate": [0, -1e999, 0]})"), "objects[0].transform.translate", "-1e999"},
      {scene_with(R"({"rotate": [0, 0, 1e400]})"), "objects[0].transform.rotate", "1e400"},
      {scene_with(R"({"scale": 1e999})"), "objects[0].transform.scale", "1e999"},
      {scene_with("{}", R"({"frequency": 1e999})"), "objects[0].material.texture.marble.frequency",
       "1e999"},
  };
}

// Expected: SceneError naming the file and quoting the number.
TEST(NonFiniteInputs, SceneNumberOverflowIsRefused) {
  for (const OverflowCase& c : overflow_cases()) {
    const SceneError error = parse_error(c.text);
    EXPECT_EQ(error.file(), "far.json");
    EXPECT_TRUE(contains(error.what(), c.literal)) << c.path;
  }
}

// Expected: the error also names the field's JSON path, as every other refused number's does.
TEST(NonFiniteInputs, SceneNumberOverflowErrorNamesTheField) {
  for (const OverflowCase& c : overflow_cases()) {
    const SceneError error = parse_error(c.text);
    EXPECT_TRUE(contains(error.field(), c.path)) << error.what();
  }
}

// The largest finite numbers are refused by their bounds, with the field's path.
TEST(NonFiniteInputs, HugeFiniteTransformIsRefusedByItsBound) {
  const SceneError error = parse_error(scene_with(R"({"translate": [1.7e308, 0, 0]})"));
  EXPECT_TRUE(contains(error.field(), "objects[0].transform.translate"));
  EXPECT_TRUE(contains(error.what(), "out of range"));
}

// ---- Texture specs ---------------------------------------------------------------------------

struct SpecCase {
  std::string field;
  std::function<void(TextureSpec&, double)> set;
};

std::vector<SpecCase> spec_cases() {
  const auto with = [](auto params, auto field_setter) {
    return [params, field_setter](TextureSpec& spec, double v) {
      auto p = params;
      field_setter(p, v);
      spec.pattern = p;
    };
  };
  return {
      {"marble.frequency",
       with(MarbleParams{}, [](MarbleParams& p, double v) { p.frequency = v; })},
      {"marble.amplitude",
       with(MarbleParams{}, [](MarbleParams& p, double v) { p.amplitude = v; })},
      {"marble.turbulence.scale",
       with(MarbleParams{}, [](MarbleParams& p, double v) { p.turbulence.scale = v; })},
      {"turbulence.fractal.scale",
       with(TurbulenceParams{}, [](TurbulenceParams& p, double v) { p.fractal.scale = v; })},
      {"noise.scale", with(NoiseParams{}, [](NoiseParams& p, double v) { p.scale = v; })},
      {"stripes.width", with(StripesParams{}, [](StripesParams& p, double v) { p.width = v; })},
      {"stripes.offset", with(StripesParams{}, [](StripesParams& p, double v) { p.offset = v; })},
      {"checker.size.y", with(CheckerParams{}, [](CheckerParams& p, double v) { p.size.y = v; })},
      {"colour_cube.period",
       with(ColourCubeParams{}, [](ColourCubeParams& p, double v) { p.period = v; })},
      {"rings.thickness", with(RingsParams{}, [](RingsParams& p, double v) { p.thickness = v; })},
      {"wood.twist", with(WoodParams{}, [](WoodParams& p, double v) { p.twist = v; })},
      {"wood.jitter_scale",
       with(WoodParams{}, [](WoodParams& p, double v) { p.jitter_scale = v; })},
      {"ramp.keys[0].position",
       [](TextureSpec& s, double v) {
         s.ramp.keys = {{static_cast<float>(v), glm::vec3(0.5f)}};
       }},
      {"ramp.keys[0].colour.g",
       [](TextureSpec& s, double v) {
         s.ramp.keys = {{0.0f, glm::vec3(0.5f, static_cast<float>(v), 0.5f)}};
       }},
      {"opacity.low", [](TextureSpec& s, double v) { s.opacity.low = static_cast<float>(v); }},
      {"specular.high", [](TextureSpec& s, double v) { s.specular.high = static_cast<float>(v); }},
  };
}

// Expected: SpecError whose field() is the parameter's path and whose value() spells the
// non-finite value, from validated() and from the evaluator's constructor (which validates).
TEST(NonFiniteInputs, TextureParametersAreRefusedNamingTheField) {
  for (const SpecCase& c : spec_cases()) {
    for (double bad : {kNaN, kInf, -kInf}) {
      TextureSpec spec;
      c.set(spec, bad);
      try {
        validated(spec);
        ADD_FAILURE() << c.field << " = " << bad << " accepted";
      } catch (const SpecError& error) {
        EXPECT_EQ(error.field(), c.field);
        EXPECT_EQ(error.value(), std::isnan(bad) ? "nan" : bad > 0 ? "inf" : "-inf");
        EXPECT_TRUE(contains(error.what(), c.field));
      }
      EXPECT_THROW(TextureEvaluator{spec}, SpecError) << c.field;
    }
  }
}

TEST(NonFiniteInputs, VolumeCornersAreRefusedNamingTheField) {
  for (double bad : {kNaN, kInf, -kInf}) {
    Volume volume;
    volume.min.y = bad;
    try {
      validated(volume);
      ADD_FAILURE() << "volume.min.y = " << bad << " accepted";
    } catch (const SpecError& error) {
      EXPECT_EQ(error.field(), "volume.min.y");
    }
  }
}

// ---- Coordinates and scenes built in code ----------------------------------------------------

// A non-finite coordinate reaches noise as 0 (docs/TEXTURES.md): a defined value, the same
// as at 0, never an out-of-range table index.
TEST(NonFiniteInputs, NonFiniteCoordinatesAreNoiseAtZero) {
  for (double bad : {kNaN, kInf, -kInf}) {
    EXPECT_EQ(value_noise({bad, 0.25, -3.5}), value_noise({0.0, 0.25, -3.5}));
    EXPECT_EQ(value_noise({0.75, bad, bad}), value_noise({0.75, 0.0, 0.0}));
  }
  TextureSpec spec;
  spec.pattern = MarbleParams{};
  const TextureEvaluator marble(spec);
  const Texel texel = marble.sample({kNaN, kInf, -kInf});
  EXPECT_TRUE(std::isfinite(texel.field));
  EXPECT_GE(texel.field, 0.0f);
  EXPECT_LE(texel.field, 1.0f);
}

// A scene built in code skips the file's validation. Expected: the rasterizer refuses every
// triangle of the object whose transform is not finite (counted as invalid), draws the
// other object as usual, and nothing non-finite reaches a pixel.
TEST(NonFiniteInputs, NonFiniteTransformInACodeBuiltSceneDrawsNothingOfThatObject) {
  TextureSpec spec;
  spec.pattern = MarbleParams{};
  for (double bad : {kNaN, kInf}) {
    SceneObject broken = stability::make_object("broken", SphereShape{1.0, 16, 8}, spec);
    broken.transform.translate.x = bad;
    SceneObject fine = stability::make_object("fine", SphereShape{1.0, 16, 8}, spec);
    fine.transform.translate.x = 1.2;
    const Scene scene =
        stability::make_scene({broken, fine}, {0.0, 0.5, 5.0}, {0.0, 0.0, 0.0}, 64, 48);
    stability::LocalRender render;
    const PreparedScene prepared =
        prepare_scene(scene, TextureResolution{6, 16, {}}, render.source);
    const stability::ConvergedFrame result = stability::render_until_converged(
        render.renderer, prepared, scene.camera, 64, 48, render.source);
    ASSERT_TRUE(result.converged);
    EXPECT_EQ(result.frame.stats.raster.triangles_invalid, broken.mesh->triangle_count());
    EXPECT_GT(result.frame.stats.covered_pixels, 0u);  // the fine sphere
    EXPECT_EQ(result.frame.stats.empty_pixels, 0u);
  }
}

}  // namespace
}  // namespace soltex
