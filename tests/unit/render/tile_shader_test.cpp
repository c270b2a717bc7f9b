// TileShader alone, on a hand-made G-buffer: an evaluated texture on a face that lies on a
// checker edge shows the inside, a cached texture reports the bricks its pixels missed, and
// uncovered pixels keep the background.
#include "tile_shader.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/scene_loader.h"

namespace soltex::render {
namespace {

constexpr int kSide = 8;

// A box with a 3D checker of 0.25 cells, unlit so that a pixel shows the texture's colour.
Scene checker_box() {
  return parse_scene(R"({"objects": [{"mesh": "box", "material": {"unlit": true,
      "texture": {"checker": {"three_d": true, "size": [0.25, 0.25, 0.25]}}}}]})",
                     "checker box");
}

// Every pixel sees the box's +x face (x = 0.5, on a checker edge) at texture point
// (0.5, y, z), with a footprint of 0.01 (`stretch` times as long along y, seen at a slant); the
// last column sees nothing.
GBuffer face_on_an_edge(float stretch = 1.0f) {
  GBuffer g;
  g.resize(kSide, kSide, false);
  for (int y = 0; y < kSide; ++y) {
    for (int x = 0; x < kSide; ++x) {
      const std::size_t i = g.index(x, y);
      const bool covered = x + 1 < kSide;
      g.flags[i] = covered ? GBuffer::kCovered : 0;
      g.object_id[i] = covered ? 0 : GBuffer::kNoObject;
      g.depth[i] = covered ? 0.5f : std::numeric_limits<float>::infinity();
      g.texture_position[i] =
          covered ? glm::dvec3(0.5, 0.03 * y - 0.2, 0.03 * x - 0.2) : glm::dvec3(0.0);
      g.normal[i] = covered ? glm::vec3(1, 0, 0) : glm::vec3(0.0f);
      g.footprint[i] = covered ? 0.01f * stretch : 0.0f;
      g.footprint_axis[i] = covered ? glm::vec3(0.0f, 0.01f * stretch, 0.0f) : glm::vec3(0.0f);
      g.footprint_minor[i] = covered ? 0.01f : 0.0f;
    }
  }
  return g;
}

// A lit marble box with a highlight, lit from +x: the fast path's material.
Scene lit_marble_box() {
  return parse_scene(R"({"lights": [{"directional": {"direction": [-1, -0.2, -0.1]}}],
      "objects": [{"mesh": "box", "material": {"texture": {"marble": {}}, "specular": 0.5,
      "shininess": 48}}]})",
                     "lit marble box");
}

struct Fixture {
  explicit Fixture(Scene s = checker_box()) : scene(std::move(s)) {
    const PreparedObject& o = prepared.objects[0];
    samplers.push_back(std::make_unique<TextureSampler>(cache, o.texture_id, o.layout, o.channels));
  }

  Scene scene;
  BrickCache cache{std::size_t{16} << 20};
  net::LocalBrickSource source{cache};
  PreparedScene prepared = prepare_scene(scene, TextureResolution{6, 16, {}}, source);
  TextureEvaluator evaluator{prepared.objects[0].texture};
  std::vector<std::unique_ptr<TextureSampler>> samplers;

  FrameShading shading(bool evaluated) const {
    const PreparedObject& o = prepared.objects[0];
    FrameShading frame{{},
                       prepare_lights(scene),
                       {glm::dmat4(1.0), glm::dvec3(0.0), kSide, kSide},
                       RenderOptions{}};
    ObjectShading object;
    object.material = material_inputs(o);
    object.surface = TextureSurface(o);
    object.evaluator = evaluated ? &evaluator : nullptr;
    object.level_table = NearestLevelTable(o.layout, 0.0);
    object.level0_spacing = o.layout.filter_width(0);
    object.cached_inset = kCachedInset;
    frame.objects.push_back(object);
    return frame;
  }
};

TEST(TileShader, EvaluatedFaceLyingOnAnEdgeShowsTheInside) {
  Fixture f;
  const FrameShading frame = f.shading(true);
  TileShader shader(frame, f.samplers);
  const GBuffer g = face_on_an_edge();
  Image image(kSide, kSide);
  shader.shade(g, 0, 0, 0, 0, kSide, kSide, image);
  EXPECT_EQ(shader.counts().covered, static_cast<std::size_t>((kSide - 1) * kSide));
  EXPECT_EQ(shader.counts().evaluated, shader.counts().covered);
  for (int y = 0; y < kSide; ++y) {
    for (int x = 0; x + 1 < kSide; ++x) {
      // Just inside the face; along y and z the box is the footprint, as on the face itself.
      const glm::dvec3 p = g.texture_position[g.index(x, y)];
      const Texel inside =
          f.evaluator.sample({0.5 - 1e-9, p.y, p.z}, SampleFootprint{0.01, {0.0, 0.01, 0.01}});
      Image expected(1, 1);
      expected.set(0, 0, inside.colour.r, inside.colour.g, inside.colour.b);
      const uint8_t* got = image.pixel(x, y);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected.rgb[c], 1) << x << "," << y;
    }
  }
  Image background(1, 1);
  background.set(0, 0, kBackground.r, kBackground.g, kBackground.b);
  for (int y = 0; y < kSide; ++y) {
    EXPECT_EQ(image.pixel(kSide - 1, y)[0], background.rgb[0]);
    EXPECT_EQ(image.pixel(kSide - 1, y)[2], background.rgb[2]);
  }
}

TEST(TileShader, CachedPixelsReportTheBricksTheyMissed) {
  Fixture f;
  const FrameShading frame = f.shading(false);
  TileShader shader(frame, f.samplers);
  const GBuffer g = face_on_an_edge();
  Image image(kSide, kSide);
  shader.shade(g, 0, 0, 0, 0, kSide, kSide, image);
  EXPECT_EQ(shader.counts().evaluated, 0u);
  EXPECT_EQ(shader.counts().empty, shader.counts().covered) << "nothing is resident yet";
  std::size_t keys = 0, pixels = 0;
  shader.misses().drain([&](const BrickKey& key, uint32_t count) {
    EXPECT_EQ(key.texture, f.prepared.objects[0].texture_id);
    ++keys;
    pixels += count;
  });
  EXPECT_GT(keys, 0u);
  EXPECT_GE(pixels, shader.counts().covered);
}

// The fast path (three colour channels, a tabled level) shades a tile as it shades the same
// pixels one at a time through the lit batch (shade_pixels()), bit for bit, once its bricks
// are resident: in a tile each pixel gets what it shares with its object (specular,
// shininess, opacity) when it is added and its albedo when it is looked up. Without the inset
// the tile takes the pixels run by run, with it one by one.
// Also with a slanted footprint, whose pixels take 4 taps each (anisotropic lookups): the fast
// path sums them in its tile, the pixel list looks them up one by one.
class FastPath : public ::testing::TestWithParam<float> {};

TEST_P(FastPath, TileEqualsThePixelListBitForBit) {
  const float stretch = GetParam();
  Fixture f(lit_marble_box());
  const GBuffer g = face_on_an_edge(stretch);
  std::vector<glm::ivec2> covered;
  for (int y = 0; y < kSide; ++y) {
    for (int x = 0; x + 1 < kSide; ++x) covered.emplace_back(x, y);
  }
  for (const double inset : {0.0, kCachedInset}) {
    FrameShading frame = f.shading(false);
    frame.objects[0].rgb_fast_path = true;
    frame.objects[0].cached_inset = inset;
    Image tile(kSide, kSide);
    for (int pass = 0; pass < 10; ++pass) {
      TileShader shader(frame, f.samplers);
      shader.shade(g, 0, 0, 0, 0, kSide, kSide, tile);
      std::vector<net::BrickWant> wants;
      shader.misses().drain([&](const BrickKey& key, uint32_t count) {
        wants.push_back({key, count});
      });
      if (wants.empty()) break;
      f.source.want(std::move(wants));
      ASSERT_TRUE(f.source.wait_idle(std::chrono::seconds(10)));
    }
    TileShader by_tile(frame, f.samplers);
    by_tile.shade(g, 0, 0, 0, 0, kSide, kSide, tile);
    ASSERT_EQ(by_tile.counts().fallback, 0u) << "inset " << inset;
    ASSERT_EQ(by_tile.counts().shaded, covered.size());
    ASSERT_EQ(by_tile.counts().tapped, stretch > 1.0f ? covered.size() : 0u);
    TileShader by_list(frame, f.samplers);
    Image list(kSide, kSide);
    by_list.shade_pixels(g, 0, 0, covered, list);
    for (const glm::ivec2& at : covered) {
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(tile.pixel(at.x, at.y)[c], list.pixel(at.x, at.y)[c])
            << "inset " << inset << " pixel " << at.x << "," << at.y << " channel " << c;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(TileShader, FastPath, ::testing::Values(1.0f, 4.0f), [](const auto& info) {
  return info.param > 1.0f ? std::string("FourTaps") : std::string("OneTap");
});

}  // namespace
}  // namespace soltex::render
