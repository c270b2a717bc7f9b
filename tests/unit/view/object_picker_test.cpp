// The object under a pixel is the one the frame draws there: seen through the same
// eye-relative view, near plane and mesh levels, so depth order and clip planes agree.
#include "object_picker.h"

#include <gtest/gtest.h>

#include "soltex/common/brick_cache.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/scene/scene_loader.h"

namespace soltex::view {
namespace {

// A small sphere just in front of a large one, both far from the origin, seen with a near
// plane far smaller than their distance (float depth there would put them in the wrong
// order), and a plane cutting the front sphere's left half away.
const char* kScene = R"({
  "camera": {"position": [1e9, 0, 6], "target": [1e9, 0, 0], "near": 1e-6, "far": 100},
  "objects": [
    {"name": "back", "mesh": {"sphere": {"radius": 2}}, "transform": {"translate": [1e9, 0, 0]},
     "material": {"texture": {"checker": {}}}},
    {"name": "front", "mesh": {"sphere": {"radius": 0.5}}, "transform": {"translate": [1e9, 0, 2.3]},
     "material": {"texture": {"checker": {}}}}],
  "clip_planes": [{"normal": [-1, 0, 0], "point": [1e9, 0, 0], "objects": ["front"]}]})";

TEST(ObjectPicker, PicksWhatTheFrameDrawsAtThePixel) {
  const Scene scene = parse_scene(kScene, "pick.json");
  BrickCache cache(16u << 20);
  net::LocalBrickSource source(cache);
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{6, 16, {}}, source);
  constexpr int kWidth = 200, kHeight = 100;
  FrameRenderer renderer(cache, RenderOptions{.threads = 1, .keep_gbuffer = true});
  (void)renderer.render(prepared, scene.camera, kWidth, kHeight);
  const GBuffer& frame = renderer.last_gbuffer();
  ObjectPicker picker;
  int checked = 0;
  for (int y = 0; y < kHeight; y += 7) {
    for (int x = 0; x < kWidth; x += 7) {
      const uint32_t drawn = frame.object_id[frame.index(x, y)];
      const std::optional<std::size_t> picked =
          picker.pick(prepared, scene.camera, kWidth, kHeight, x, y);
      if (drawn == GBuffer::kNoObject) {
        EXPECT_FALSE(picked.has_value()) << x << "," << y;
      } else {
        ASSERT_TRUE(picked.has_value()) << x << "," << y;
        EXPECT_EQ(prepared.objects[*picked].raster.object_id, drawn) << x << "," << y;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 100);
  // The front sphere's kept half, right of the centre, is in front of the back sphere.
  EXPECT_EQ(picker.pick(prepared, scene.camera, kWidth, kHeight, kWidth / 2 + 6, kHeight / 2), 1u);
  // Its cut-away half shows the back sphere.
  EXPECT_EQ(picker.pick(prepared, scene.camera, kWidth, kHeight, kWidth / 2 - 6, kHeight / 2), 0u);
  EXPECT_EQ(picker.pick(prepared, scene.camera, kWidth, kHeight, 0, 0), std::nullopt);
}

}  // namespace
}  // namespace soltex::view
