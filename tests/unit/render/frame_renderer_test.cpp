// FrameRenderer draws the same frame whether it keeps the whole G-buffer (tests, tools) or
// shades each tile from a tile-sized one.
#include "soltex/render/frame_renderer.h"

#include <gtest/gtest.h>

#include <chrono>

#include "soltex/common/brick_cache.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/default_scene.h"

namespace soltex {
namespace {

struct Drawn {
  Image cold;  // the first frame, nothing resident
  std::vector<net::BrickWant> cold_misses;
  Image converged;
  std::size_t gbuffer_pixels = 0;
};

Drawn draw_default_scene(bool keep_gbuffer) {
  const Scene scene = default_scene();
  BrickCache cache(256u << 20);
  net::LocalBrickSource source(cache);
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{6, 16, {}}, source);
  FrameRenderer renderer(cache, RenderOptions{.threads = 2, .keep_gbuffer = keep_gbuffer});
  constexpr int kWidth = 320, kHeight = 180;
  Drawn drawn;
  Frame frame = renderer.render(prepared, scene.camera, kWidth, kHeight);
  drawn.cold = frame.image;
  drawn.cold_misses = frame.misses;
  for (int i = 0; i < 50 && !(frame.complete() && source.idle()); ++i) {
    source.want(std::move(frame.misses));
    source.wait_idle(std::chrono::seconds(5));
    frame = renderer.render(prepared, scene.camera, kWidth, kHeight);
  }
  EXPECT_TRUE(frame.complete());
  drawn.converged = frame.image;
  drawn.gbuffer_pixels = renderer.last_gbuffer().pixel_count();
  return drawn;
}

TEST(FrameRenderer, TileGBuffersDrawWhatTheFrameGBufferDraws) {
  const Drawn kept = draw_default_scene(true);
  const Drawn tiled = draw_default_scene(false);
  EXPECT_EQ(kept.gbuffer_pixels, 320u * 180u);
  EXPECT_EQ(tiled.gbuffer_pixels, 0u) << "no frame-sized G-buffer unless asked for";
  EXPECT_TRUE(kept.cold == tiled.cold);
  ASSERT_EQ(kept.cold_misses.size(), tiled.cold_misses.size());
  for (std::size_t i = 0; i < kept.cold_misses.size(); ++i) {
    EXPECT_EQ(kept.cold_misses[i].key, tiled.cold_misses[i].key);
    EXPECT_EQ(kept.cold_misses[i].screen_pixels, tiled.cold_misses[i].screen_pixels);
  }
  EXPECT_TRUE(kept.converged == tiled.converged);
}

}  // namespace
}  // namespace soltex
