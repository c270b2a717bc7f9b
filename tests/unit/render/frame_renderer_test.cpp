// FrameRenderer draws the same frame whether it keeps the whole G-buffer (tests, tools) or
// shades each tile from a tile-sized one, and nearly the same from a fine mesh's simplified
// level as from the mesh itself; a frame drawn for its misses alone finds what a shaded one
// misses.
#include "soltex/render/frame_renderer.h"

#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <string>
#include <unordered_map>

#include "soltex/common/brick_cache.h"
#include "soltex/common/spec_error.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/default_scene.h"
#include "soltex/scene/scene_loader.h"

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

// A material's finest level below the bricks' own size is refused as the scene file names it.
TEST(PrepareScene, AVolumeTheBricksCannotMakeNamesItsObject) {
  Scene scene = default_scene();
  scene.name = "floors.json";
  scene.objects[2].material.volume.finest_level_log2 = 3;
  BrickCache cache(16u << 20);
  net::LocalBrickSource source(cache);
  try {
    (void)prepare_scene(scene, TextureResolution{8, 16, {}}, source);
    FAIL() << "a finest level of 2^3 with bricks of 16 was accepted";
  } catch (const SpecError& e) {
    EXPECT_STREQ(e.what(),
                 "floors.json: objects[2].material.volume.finest_level_log2 = 3: must be at least "
                 "log2(brick_size) = 4 so that the coarsest level is one whole brick");
  }
  // Bricks of 8 can make it.
  EXPECT_NO_THROW((void)prepare_scene(scene, TextureResolution{8, 8, {}}, source));
}

// A mesh its file wrote two-sided (each face once each way, kept once) is drawn from both
// sides even where its object asks for back faces to be culled.
TEST(PrepareScene, ATwoSidedMeshIsNotCulled) {
  Scene scene = default_scene();
  SceneObject& torus = scene.objects[1];
  ASSERT_FALSE(torus.double_sided);
  BrickCache cache(16u << 20);
  net::LocalBrickSource source(cache);
  EXPECT_TRUE(
      prepare_scene(scene, TextureResolution{8, 16, {}}, source).objects[1].raster.cull_back_faces);
  auto two_sided = std::make_shared<Mesh>(*torus.mesh);
  two_sided->two_sided = true;
  torus.mesh = two_sided;
  EXPECT_FALSE(
      prepare_scene(scene, TextureResolution{8, 16, {}}, source).objects[1].raster.cull_back_faces);
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

// A fine sphere drawn converged at 320 x 180: with its simplified levels, as loaded, or without
// (every triangle drawn).
struct SphereFrame {
  Image image;
  std::size_t triangles = 0;
};

SphereFrame draw_fine_sphere(bool levels) {
  Scene scene = parse_scene(R"({
    "camera": {"position": [0, 0.6, 3.2], "target": [0, 0, 0], "fov_y_degrees": 40},
    "lights": [{"directional": {"direction": [-0.5, -1.0, -0.7]}}],
    "objects": [{"name": "sphere", "double_sided": false,
      "mesh": {"sphere": {"radius": 1, "segments": 400, "rings": 200}},
      "material": {"texture": {"marble": {}}, "specular": 0.5, "shininess": 48}}]})",
                            "<fine sphere>");
  if (!levels) scene.objects.front().levels.reset();
  BrickCache cache(64u << 20);
  net::LocalBrickSource source(cache);
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{6, 16, {}}, source);
  FrameRenderer renderer(cache, RenderOptions{.threads = 2});
  Frame frame = renderer.render(prepared, scene.camera, 320, 180);
  for (int i = 0; i < 50 && !(frame.complete() && source.idle()); ++i) {
    source.want(std::move(frame.misses));
    source.wait_idle(std::chrono::seconds(5));
    frame = renderer.render(prepared, scene.camera, 320, 180);
  }
  EXPECT_TRUE(frame.complete());
  return {frame.image, frame.stats.raster.triangles_in};
}

// A cold frame hands each tile's new misses out while it is drawn (from the render threads),
// and its misses at the end are the same, key for key and pixel for pixel, as without.
// Depth is float: a near plane of 1e-6 (which the scene format allows) would leave surfaces
// a few units away too close in depth to draw in order. Where no object comes nearer, the
// frame moves its near plane out; the picture is the one a near plane of 0.1 gives.
TEST(FrameRenderer, ATinyNearPlaneDrawsWhatAnOrdinaryOneDraws) {
  Scene scene = default_scene();
  BrickCache cache(256u << 20);
  net::LocalBrickSource source(cache);
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{6, 16, {}}, source);
  FrameRenderer renderer(cache, RenderOptions{.threads = 2, .keep_gbuffer = true});
  const auto draw = [&](double near, double far) {
    scene.camera.near = near;
    scene.camera.far = far;
    return renderer.render(prepared, scene.camera, 320, 180);
  };
  const Frame ordinary = draw(0.1, 100.0);
  const GBufferPlane<uint32_t> ordinary_ids = renderer.last_gbuffer().object_id;
  const Frame tiny = draw(1e-6, 1e7);
  EXPECT_TRUE(tiny.image == ordinary.image);
  EXPECT_TRUE(renderer.last_gbuffer().object_id == ordinary_ids);
}

// Inside a room, where the near plane stays as given, a point light shades its walls from each
// pixel's world position. That position comes from the G-buffer's double texture position, so
// a near plane of 1e-6, with which the float depth resolves only about a quarter of a unit at
// the walls, lights them as one of 1e-3 does (from the depth they broke into blocks).
TEST(FrameRenderer, APointLightShadesTheSameWhateverTheNearPlane) {
  // Away from the origin, where a position from the depth would also lose bits to the eye's.
  Scene scene = parse_scene(R"({
    "camera": {"position": [3.999, -6.001, 11.999], "target": [3, -7, 11]},
    "lights": [{"point": {"position": [3, -7, 11.5], "intensity": 1}}],
    "objects": [{"name": "room", "mesh": {"box": {"size": 2}},
                 "transform": {"translate": [3, -7, 11]},
                 "material": {"texture": {"colour_cube": {}}, "space": "world", "specular": 0}}]
  })",
                            "room.json");
  BrickCache cache(64u << 20);
  net::LocalBrickSource source(cache);
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{6, 16, {}}, source);
  RenderOptions options{.threads = 2};
  options.access = TextureAccess::evaluated;
  FrameRenderer renderer(cache, options);
  const auto draw = [&](double near) {
    scene.camera.near = near;
    return renderer.render(prepared, scene.camera, 160, 120).image;
  };
  const Image ordinary = draw(1e-3);
  const Image tiny = draw(1e-6);
  EXPECT_TRUE(tiny == ordinary);
}

TEST(FrameRenderer, TileMissesAddUpToTheFramesMisses) {
  const Scene scene = default_scene();
  BrickCache cache(256u << 20);
  net::LocalBrickSource source(cache);
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{6, 16, {}}, source);
  FrameRenderer renderer(cache, RenderOptions{.threads = 2});
  const Frame plain = renderer.render(prepared, scene.camera, 320, 180);
  ASSERT_FALSE(plain.misses.empty());

  std::mutex mutex;
  std::unordered_map<BrickKey, uint32_t, BrickKeyHash> reported;
  std::size_t calls = 0;
  renderer.set_on_tile_misses([&](std::vector<net::BrickWant> wants) {
    std::lock_guard lock(mutex);
    ++calls;
    for (const net::BrickWant& w : wants) {
      EXPECT_GT(w.screen_pixels, 0u);
      reported[w.key] += 1;
    }
  });
  const Frame told = renderer.render(prepared, scene.camera, 320, 180);
  renderer.set_on_tile_misses(nullptr);
  EXPECT_GT(calls, 1u) << "one call per tile with new misses, not one per frame";
  ASSERT_EQ(told.misses.size(), plain.misses.size());
  for (std::size_t i = 0; i < told.misses.size(); ++i) {
    EXPECT_EQ(told.misses[i].key, plain.misses[i].key);
    EXPECT_EQ(told.misses[i].screen_pixels, plain.misses[i].screen_pixels);
    // Every miss was told, at most once per render thread.
    const auto it = reported.find(plain.misses[i].key);
    ASSERT_NE(it, reported.end());
    EXPECT_LE(it->second, 2u);
  }
  EXPECT_EQ(reported.size(), plain.misses.size());
  EXPECT_TRUE(told.image == plain.image);
}

// A frame drawn for its misses alone (RenderOptions::misses_only) asks for what the shaded
// frame asks for, key for key and pixel for pixel, and counts the same pixels, with nothing
// resident, with part of the bricks resident and converged; for every filter, with edge
// anti-aliasing and without, with planar edges looked up in bricks (their inward step) and
// evaluated.
TEST(FrameRenderer, AMissesOnlyFrameMissesWhatTheShadedFrameMisses) {
  const Scene scene = default_scene();
  struct Setting {
    SampleFilter filter;
    TextureAccess access;
    int edge_antialias;
  };
  const Setting settings[] = {{SampleFilter::trilinear, TextureAccess::automatic, 0},
                              {SampleFilter::nearest, TextureAccess::cached, 0},
                              {SampleFilter::quadrilinear, TextureAccess::cached, 0},
                              {SampleFilter::trilinear, TextureAccess::cached, 3}};
  for (const Setting& setting : settings) {
    SCOPED_TRACE(std::string(sample_filter_name(setting.filter)) + ", " +
                 texture_access_name(setting.access) + ", edge anti-aliasing " +
                 std::to_string(setting.edge_antialias));
    BrickCache cache(256u << 20);
    net::LocalBrickSource source(cache);
    const PreparedScene prepared = prepare_scene(scene, TextureResolution{7, 16, {}}, source);
    FrameRenderer renderer(cache, RenderOptions{.access = setting.access,
                                                .filter = setting.filter,
                                                .threads = 2,
                                                .edge_antialias = setting.edge_antialias});
    bool partly_resident = false;  // a round drew some pixels from a coarser resident level
    for (int round = 0; round < 8; ++round) {
      SCOPED_TRACE("round " + std::to_string(round));
      const Frame shaded = renderer.render(prepared, scene.camera, 320, 180);
      renderer.set_misses_only(true);
      const Frame found = renderer.render(prepared, scene.camera, 320, 180);
      renderer.set_misses_only(false);
      ASSERT_EQ(found.misses.size(), shaded.misses.size());
      for (std::size_t i = 0; i < found.misses.size(); ++i) {
        EXPECT_EQ(found.misses[i].key, shaded.misses[i].key);
        EXPECT_EQ(found.misses[i].screen_pixels, shaded.misses[i].screen_pixels);
      }
      EXPECT_EQ(found.stats.covered_pixels, shaded.stats.covered_pixels);
      EXPECT_EQ(found.stats.fallback_pixels, shaded.stats.fallback_pixels);
      EXPECT_EQ(found.stats.empty_pixels, shaded.stats.empty_pixels);
      EXPECT_EQ(found.stats.evaluated_pixels, shaded.stats.evaluated_pixels);
      EXPECT_EQ(found.stats.tapped_pixels, shaded.stats.tapped_pixels);
      EXPECT_EQ(found.stats.taps, shaded.stats.taps);
      EXPECT_EQ(found.stats.shaded_pixels, 0u) << "nothing lit";
      partly_resident |= shaded.stats.fallback_pixels > shaded.stats.empty_pixels;
      if (shaded.complete()) break;
      // Every other brick: the next round draws from coarser levels where the rest is missing.
      std::vector<net::BrickWant> half;
      for (std::size_t i = 0; i < shaded.misses.size(); i += 2) half.push_back(shaded.misses[i]);
      if (round >= 3) half = shaded.misses;
      source.want(std::move(half));
      source.wait_idle(std::chrono::seconds(5));
      EXPECT_TRUE(source.idle());
    }
    EXPECT_TRUE(partly_resident);
    EXPECT_TRUE(renderer.render(prepared, scene.camera, 320, 180).complete()) << "converged";
  }
}

// A floor seen at a grazing angle, against its 4 x 4 supersampled reference: one lookup (or one
// evaluation) per pixel over the footprint's long side blurs marble's veins and the checker's
// squares to grey towards the horizon; taps along the long side keep them. Marble comes from
// bricks, the checker is evaluated per pixel (measured here: marble 21.9 and 32.5 dB, the
// checker 29.6 and 38.3 dB).
class GrazingFloorTaps : public ::testing::TestWithParam<const char*> {};

TEST_P(GrazingFloorTaps, KeepTheReferencesDetail) {
  const std::string texture = GetParam();
  const Scene scene = parse_scene(R"({
    "camera": {"position": [0, 1.2, 6], "target": [0, 0, -4], "fov_y_degrees": 50,
               "near": 0.05, "far": 100},
    "lights": [{"directional": {"direction": [-0.3, -1, -0.4]}}],
    "objects": [{"name": "floor", "mesh": {"plane": {"size": [20, 20], "subdivisions": 4}},
      "material": {"texture": )" + texture +
                                      R"(, "space": "world", "specular": 0}}]})",
                                  "<grazing floor>");
  constexpr int kWidth = 240, kHeight = 135;
  double psnr_by_anisotropy[2] = {0.0, 0.0};
  std::size_t tapped[2] = {0, 0};
  Image reference;
  for (const int anisotropy : {1, 8}) {
    BrickCache cache(256u << 20);
    net::LocalBrickSource source(cache);
    const PreparedScene prepared = prepare_scene(scene, TextureResolution{12, 16, {}}, source);
    FrameRenderer renderer(cache, RenderOptions{.threads = 2, .anisotropy = anisotropy});
    Frame frame = renderer.render(prepared, scene.camera, kWidth, kHeight);
    for (int i = 0; i < 50 && !(frame.complete() && source.idle()); ++i) {
      source.want(std::move(frame.misses));
      source.wait_idle(std::chrono::seconds(10));
      frame = renderer.render(prepared, scene.camera, kWidth, kHeight);
    }
    ASSERT_TRUE(frame.complete()) << anisotropy;
    // The same reference whatever the frame's anisotropy: the ground truth does not move.
    const Image truth = renderer.render_reference(prepared, scene.camera, kWidth, kHeight, 4);
    if (reference.rgb.empty()) reference = truth;
    EXPECT_TRUE(truth == reference);
    const int k = anisotropy == 1 ? 0 : 1;
    psnr_by_anisotropy[k] = psnr(frame.image, reference);
    tapped[k] = frame.stats.tapped_pixels;
    EXPECT_GE(frame.stats.taps, 2 * frame.stats.tapped_pixels);
    EXPECT_LE(frame.stats.taps, 8 * frame.stats.tapped_pixels);
  }
  EXPECT_EQ(tapped[0], 0u);
  EXPECT_GT(tapped[1], 0u);
  EXPECT_GT(psnr_by_anisotropy[1], psnr_by_anisotropy[0] + 6.0)
      << psnr_by_anisotropy[0] << " dB without taps, " << psnr_by_anisotropy[1] << " with";
  EXPECT_GT(psnr_by_anisotropy[1], 30.0);
  RecordProperty("psnr_one_lookup", std::to_string(psnr_by_anisotropy[0]));
  RecordProperty("psnr_taps", std::to_string(psnr_by_anisotropy[1]));
}

INSTANTIATE_TEST_SUITE_P(FrameRenderer, GrazingFloorTaps,
                         ::testing::Values(
                             R"({"marble": {"frequency": 1.5, "amplitude": 4,
                       "turbulence": {"scale": 2, "octave_max": 6}}})",
                             R"({"checker": {"size": [0.25, 0.25, 0.25], "three_d": true}})"),
                         [](const auto& info) {
                           return std::string(info.index == 0 ? "MarbleFromBricks"
                                                              : "CheckerEvaluatedPerPixel");
                         });

TEST(FrameRenderer, SimplifiedLevelsDrawNearlyTheSamePicture) {
  const SphereFrame simplified = draw_fine_sphere(true);
  const SphereFrame whole = draw_fine_sphere(false);
  EXPECT_EQ(whole.triangles, 159200u);
  // At 180 rows a pixel spans about 0.009 units 2.2 away: a coarse level serves.
  EXPECT_LT(simplified.triangles, whole.triangles / 2);
  // Under half a pixel of error: a few silhouette pixels flip, nothing else moves much (the
  // image suite's floors are 35 to 42 dB against supersampled references).
  EXPECT_GT(psnr(simplified.image, whole.image), 40.0);
}

// A sheet cut by a clip plane and seen from below, through the plane, shows its underside, not
// a cap: it has no inside. Told it is a solid it still does: every cap point the view finds lies
// off the sheet, outside the mesh's bounds, so none is a cap.
TEST(FrameRenderer, ACutSheetShowsItsUndersideAndNoCap) {
  RasterStats drawn[2];
  for (const bool told_solid : {false, true}) {
    const std::string solid = told_solid ? R"("solid": true,)" : "";
    const Scene scene = parse_scene(R"({
      "camera": {"position": [3, -2, 0.2], "target": [-0.3, 0, 0], "up": [0, 0, 1]},
      "objects": [{"name": "sheet", "mesh": {"plane": {"size": 2, "subdivisions": 4}},)" +
                                        solid + R"(
                   "material": {"texture": {"checker": {"size": [0.25, 0.25, 0.25]}}}}],
      "clip_planes": [{"normal": [1, 0, 0], "offset": 0.5}]
    })",
                                    "sheet.json");
    BrickCache cache(64u << 20);
    net::LocalBrickSource source(cache);
    const PreparedScene prepared = prepare_scene(scene, TextureResolution{7, 16, {}}, source);
    FrameRenderer renderer(cache, RenderOptions{.threads = 1});
    drawn[told_solid] = renderer.render(prepared, scene.camera, 160, 120).stats.raster;
  }
  for (const bool told_solid : {false, true}) {
    EXPECT_GT(drawn[told_solid].back_face_pixels, 2000u) << "the underside fills the view";
    EXPECT_EQ(drawn[told_solid].cap_pixels, 0u);
  }
  EXPECT_GT(drawn[true].cap_rays, 0u) << "told it is a solid, caps were looked for";
}

}  // namespace
}  // namespace soltex
