// Only what a scene calls for, shown by counters: no clip-plane work without clip planes,
// colour-only bricks for colour-only materials, bricks only for the visible surface, only the
// octaves a level can show, no shading for unlit materials. Against a real soltexd where
// bytes or the server's counters are measured.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <unordered_set>
#include <vector>

#include "../stability/stability_scene.h"
#include "soltex/common/brick_codec.h"
#include "soltex/common/evaluation_counters.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/net/brick_fetcher.h"
#include "soltex/render/anisotropic_taps.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/scene/default_scene.h"
#include "soltex/spec_proto/spec_from_proto.h"
#include "soltex/v1/brick_service.grpc.pb.h"
#include "soltexd_process.h"

namespace soltex {
namespace {

using testing::http_get;
using testing::metric_value;
using testing::SoltexdProcess;

using KeySet = std::unordered_set<BrickKey, BrickKeyHash>;

constexpr int kWidth = 320;
constexpr int kHeight = 180;

Scene default_scene_without_clip_planes() {
  Scene scene = default_scene();
  for (SceneObject& object : scene.objects) object.clip_planes.clear();
  return scene;
}

Scene with_channels(Scene scene, const ChannelSet& channels) {
  for (SceneObject& object : scene.objects) {
    object.material.texture.channels = channels;
    object.material.texture = validated(object.material.texture);
  }
  return scene;
}

// The bricks the visible surface reads, of the objects whose textures come from bricks (the
// default access evaluates the analytic ones per pixel: they read none): at every covered
// pixel, the bricks that hold its taps (its texture position, or the default anisotropy's taps
// along a grazing footprint) at the level of their share of the footprint (trilinear: the
// nearest level).
KeySet surface_bricks(const PreparedScene& scene, const GBuffer& g, BrickCache& cache) {
  std::vector<std::unique_ptr<TextureSampler>> samplers;
  for (const PreparedObject& o : scene.objects) {
    samplers.push_back(std::make_unique<TextureSampler>(cache, o.texture_id, o.layout, o.channels));
  }
  KeySet keys;
  for (std::size_t i = 0; i < g.pixel_count(); ++i) {
    if (!g.covered(i)) continue;
    if (evaluated_per_pixel(scene.objects[g.object_id[i]].texture, TextureAccess::automatic)) {
      continue;
    }
    TextureSampler& sampler = *samplers[g.object_id[i]];
    const int n =
        render::tap_count(g.footprint[i], g.footprint_minor[i], RenderOptions{}.anisotropy);
    const double lod = std::min(sampler.level_of_detail(render::tap_share(g.footprint[i], n)),
                                static_cast<double>(sampler.layout().coarsest_level()));
    for (int k = 0; k < n; ++k) {
      const glm::dvec3 p =
          n == 1 ? g.texture_position[i]
                 : render::tap_position(g.texture_position[i], g.footprint_axis[i], k, n);
      keys.insert(sampler.brick_key(p, static_cast<int>(lod + 0.5)));
    }
  }
  return keys;
}

// What a dense cache cube holds at the levels the requests touched, per texture.
uint64_t dense_bricks(const PreparedScene& scene, const KeySet& requested) {
  std::set<std::pair<uint64_t, int>> levels;
  for (const BrickKey& key : requested) levels.insert({key.texture, key.level});
  uint64_t total = 0;
  for (const auto& [texture, level] : levels) {
    for (const PreparedObject& o : scene.objects) {
      if (o.texture_id == texture) {
        total += o.layout.brick_count(level);
        break;
      }
    }
  }
  return total;
}

const PreparedObject* object_of(const PreparedScene& scene, uint64_t texture) {
  for (const PreparedObject& o : scene.objects) {
    if (o.texture_id == texture) return &o;
  }
  return nullptr;
}

// Octave-samples the given bricks cost when evaluated band-limited: per brick, its samples
// times the octaves evaluated (or skipped) at its level's filter width.
struct OctaveWork {
  uint64_t bricks = 0;
  uint64_t samples = 0;
  uint64_t evaluated = 0;
  uint64_t skipped = 0;
};

// Keyed by (object name, level).
std::map<std::pair<std::string, int>, OctaveWork> octave_work(const PreparedScene& scene,
                                                              const KeySet& bricks) {
  std::map<std::pair<std::string, int>, OctaveWork> work;
  for (const BrickKey& key : bricks) {
    const PreparedObject* o = object_of(scene, key.texture);
    if (o == nullptr) continue;
    const TextureEvaluator evaluator(o->texture);
    const auto samples = static_cast<uint64_t>(o->layout.samples_per_brick());
    const int all = evaluator.evaluated_octaves(0.0);
    const int evaluated = evaluator.evaluated_octaves(o->layout.filter_width(key.level));
    OctaveWork& w = work[{o->object->name, key.level}];
    ++w.bricks;
    w.samples += samples;
    w.evaluated += samples * static_cast<uint64_t>(evaluated);
    w.skipped += samples * static_cast<uint64_t>(all - evaluated);
  }
  return work;
}

std::string metrics(const SoltexdProcess& server) {
  return http_get(server.metrics_port(), "/metrics");
}

// ---- Clip planes -----------------------------------------------------------------------------

// Expected: without clip planes the rasterizer classifies no triangle against a plane, tests no
// fragment and traces no cap ray (every clip-plane counter 0); the same scene with its plane
// does that work.
TEST(SceneNeeds, NoClipPlanesNoClippingOrCappingWork) {
  for (const bool with_plane : {false, true}) {
    const Scene scene = with_plane ? default_scene() : default_scene_without_clip_planes();
    stability::LocalRender render;
    const PreparedScene prepared =
        prepare_scene(scene, TextureResolution{7, 16, {}}, render.source);
    const Frame frame = render.renderer.render(prepared, scene.camera, kWidth, kHeight);
    const RasterStats& raster = frame.stats.raster;
    if (with_plane) {
      EXPECT_GT(raster.clip_plane_work(), 0u);
      EXPECT_GT(raster.cap_pixels, 0u);
    } else {
      EXPECT_EQ(raster.clip_plane_work(), 0u);
      EXPECT_GT(frame.stats.covered_pixels, 0u);
    }
  }
}

// ---- Channels --------------------------------------------------------------------------------

struct FetchedScene {
  net::SourceStats stats;
  KeySet requested;
  std::vector<int> channels_in_cache;  // per requested brick
  bool converged = false;
  int frames = 0;
  FrameStats last;  // the converged frame's
};

FetchedScene fetch_scene(const SoltexdProcess& server, const Scene& scene,
                         const TextureResolution& resolution, int width, int height) {
  BrickCache cache(std::size_t{512} << 20);
  net::BrickFetcher fetcher(server.grpc_address(), cache);
  const PreparedScene prepared = prepare_scene(scene, resolution, fetcher);
  FrameRenderer renderer(cache, RenderOptions{});
  const stability::ConvergedFrame result = stability::render_until_converged(
      renderer, prepared, scene.camera, width, height, fetcher, 2000);
  FetchedScene fetched{fetcher.stats(),  result.requested, {},
                       result.converged, result.frames,    result.frame.stats};
  for (const BrickKey& key : result.requested) {
    const auto brick = cache.find(key);
    fetched.channels_in_cache.push_back(brick ? brick->channels() : 0);
  }
  return fetched;
}

// Expected: the same scene with colour-only materials needs the same bricks and fewer bytes
// than with colour, opacity and specular, and every brick it holds has 3 channels (5 with
// all channels).
TEST(SceneNeeds, ColourOnlyMaterialsReceiveColourOnlyBricks) {
  SoltexdProcess server;
  const Scene colour = with_channels(default_scene(), {true, false, false});
  const Scene all = with_channels(default_scene(), {true, true, true});
  const TextureResolution resolution{7, 16, {}};
  const FetchedScene c = fetch_scene(server, colour, resolution, kWidth, kHeight);
  const FetchedScene a = fetch_scene(server, all, resolution, kWidth, kHeight);
  ASSERT_TRUE(c.converged);
  ASSERT_TRUE(a.converged);
  EXPECT_EQ(c.requested.size(), a.requested.size());
  EXPECT_EQ(c.stats.received, a.stats.received);
  EXPECT_LT(c.stats.bytes, a.stats.bytes);
  for (int channels : c.channels_in_cache) EXPECT_EQ(channels, 3);
  for (int channels : a.channels_in_cache) EXPECT_EQ(channels, 5);
  RecordProperty("colour_only_bytes", std::to_string(c.stats.bytes));
  RecordProperty("all_channels_bytes", std::to_string(a.stats.bytes));
  std::printf("bricks %llu: colour only %llu bytes, colour + opacity + specular %llu bytes\n",
              static_cast<unsigned long long>(c.stats.received),
              static_cast<unsigned long long>(c.stats.bytes),
              static_cast<unsigned long long>(a.stats.bytes));
}

// The same on the wire, without the client library: a brick streamed for a colour-only
// registration decodes to 3 channel planes, for all channels to 5.
TEST(SceneNeeds, StreamedBrickDecodesToTheRegisteredChannels) {
  SoltexdProcess server;
  auto stub = v1::BrickService::NewStub(
      grpc::CreateChannel(server.grpc_address(), grpc::InsecureChannelCredentials()));
  for (const auto& [channels, expected] :
       {std::pair{ChannelSet{true, false, false}, 3}, std::pair{ChannelSet{true, true, true}, 5}}) {
    TextureSpec spec;
    spec.pattern = MarbleParams{};
    spec.channels = channels;
    v1::RegisterTextureRequest registration;
    *registration.mutable_spec() = to_proto(validated(spec));
    *registration.mutable_volume() = to_proto(Volume{glm::dvec3(-1.0), glm::dvec3(1.0), 6});
    registration.set_brick_size(16);
    v1::TextureHandle handle;
    {
      grpc::ClientContext context;
      ASSERT_TRUE(stub->RegisterTexture(&context, registration, &handle).ok());
    }
    EXPECT_EQ(handle.channels_size(), expected == 3 ? 1 : 3);  // Channel values, not planes
    grpc::ClientContext context;
    auto stream = stub->StreamBricks(&context);
    v1::BrickRequest request;
    v1::BrickKey* key = request.add_want()->mutable_key();
    key->set_texture_id(handle.id());
    key->set_level(handle.levels() - 1);
    request.add_accept_codecs(v1::CODEC_ZSTD);
    ASSERT_TRUE(stream->Write(request));
    stream->WritesDone();
    v1::BrickBatch batch;
    std::vector<v1::Brick> bricks;
    while (stream->Read(&batch)) {
      for (const v1::Brick& brick : batch.bricks()) bricks.push_back(brick);
    }
    ASSERT_TRUE(stream->Finish().ok());
    ASSERT_EQ(bricks.size(), 1u);
    const std::string& payload = bricks[0].payload();
    const DecodedBrick decoded =
        decode_brick({reinterpret_cast<const uint8_t*>(payload.data()), payload.size()});
    EXPECT_EQ(decoded.channels, expected);
    EXPECT_EQ(decoded.samples.size(), brick_decoded_size(16, expected));
  }
}

// ---- Visible surface -------------------------------------------------------------------------

// Expected: the distinct bricks all frames of a converged render asked for are exactly the
// bricks the visible surface touches (each covered pixel's texture position at its level),
// plus at most one coarsest brick per texture (asked for while nothing was resident yet), and
// far fewer than a dense cube holds at those levels.
TEST(SceneNeeds, BricksAreRequestedOnlyForTheVisibleSurface) {
  const Scene scene = default_scene();
  stability::LocalRender render;
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{8, 16, {}}, render.source);
  const stability::ConvergedFrame result = stability::render_until_converged(
      render.renderer, prepared, scene.camera, kWidth, kHeight, render.source);
  ASSERT_TRUE(result.converged);
  const GBuffer g = stability::rasterize(prepared, scene.camera, kWidth, kHeight);
  const KeySet surface = surface_bricks(prepared, g, render.cache);
  for (const BrickKey& key : surface) {
    EXPECT_TRUE(result.requested.contains(key)) << "level " << key.level;
  }
  std::size_t outside_surface = 0;
  for (const BrickKey& key : result.requested) {
    if (surface.contains(key)) continue;
    ++outside_surface;
    const PreparedObject* o = object_of(prepared, key.texture);
    ASSERT_NE(o, nullptr);
    EXPECT_EQ(key.level, o->layout.coarsest_level()) << "a brick off the surface";
  }
  EXPECT_LE(outside_surface, prepared.objects.size());
  const uint64_t dense = dense_bricks(prepared, result.requested);
  EXPECT_LT(result.requested.size() * 10, dense);
  std::printf("requested %zu, surface %zu, dense cube at those levels %llu\n",
              result.requested.size(), surface.size(), static_cast<unsigned long long>(dense));
}

// ---- Octaves ---------------------------------------------------------------------------------

TextureSpec six_octave_marble() {
  TextureSpec spec;
  MarbleParams m;
  m.turbulence.scale = 2.0;
  m.turbulence.octave_max = 6;
  spec.pattern = m;
  return validated(spec);
}

// A 2^8 cube over [-1, 1]: h_0 = 1/128, so octave k (2^(k+1) cells per unit) has
// 2^(k+1) / 128 cells per sample. Below 0.25 it is evaluated, from 0.5 on it is replaced by
// its mean: level 0 evaluates octaves 0..4 and skips 5 and 6; level 4 (h = 1/8) evaluates
// octave 0 only.
const Volume kOctaveVolume{glm::dvec3(-1.0), glm::dvec3(1.0), 8};

// Expected: evaluate_brick counts, per sample, the octaves the level's plan evaluates and
// those it skips; a coarse level evaluates fewer octave-samples per sample than level 0.
TEST(SceneNeeds, CoarseLevelsEvaluateOnlyTheOctavesTheyCanShow) {
  const TextureEvaluator evaluator(six_octave_marble());
  const BrickLayout layout(kOctaveVolume, 16);
  std::vector<float> out(static_cast<std::size_t>(layout.samples_per_brick()) * 3);
  const auto samples = static_cast<uint64_t>(layout.samples_per_brick());
  std::map<int, OctaveCounts> per_level;
  for (int level : {0, 2, layout.coarsest_level()}) {
    const OctaveCounts before = octave_counters().snapshot();
    evaluate_brick(evaluator, layout, level, glm::ivec3(0), MipSettings{}, out);
    const OctaveCounts after = octave_counters().snapshot();
    per_level[level] = {after.samples - before.samples,
                        after.evaluated_octave_samples - before.evaluated_octave_samples,
                        after.skipped_octave_samples - before.skipped_octave_samples};
    EXPECT_EQ(per_level[level].samples, samples);
    EXPECT_EQ(per_level[level].evaluated_octave_samples + per_level[level].skipped_octave_samples,
              7 * samples);
  }
  EXPECT_EQ(per_level[0].evaluated_octave_samples, 5 * samples);
  EXPECT_EQ(per_level[layout.coarsest_level()].evaluated_octave_samples, 1 * samples);
  EXPECT_LT(per_level[2].evaluated_octave_samples, per_level[0].evaluated_octave_samples);
  EXPECT_LT(per_level[layout.coarsest_level()].evaluated_octave_samples,
            per_level[2].evaluated_octave_samples);

  // Point sampling evaluates every octave at every level; supersampling at the sub-sample
  // spacing, k^3 samples per sample.
  const OctaveCounts before = octave_counters().snapshot();
  evaluate_brick(evaluator, layout, layout.coarsest_level(), glm::ivec3(0),
                 MipSettings{MipMode::point, 2}, out);
  const OctaveCounts after = octave_counters().snapshot();
  EXPECT_EQ(after.evaluated_octave_samples - before.evaluated_octave_samples, 7 * samples);
  evaluate_brick(evaluator, layout, layout.coarsest_level(), glm::ivec3(0),
                 MipSettings{MipMode::supersampled, 2}, out);
  const OctaveCounts super = octave_counters().snapshot();
  EXPECT_EQ(super.samples - after.samples, 8 * samples);
  EXPECT_EQ(super.evaluated_octave_samples - after.evaluated_octave_samples,
            8 * samples *
                static_cast<uint64_t>(
                    evaluator.evaluated_octaves(layout.filter_width(layout.coarsest_level()) / 2)));
}

// Expected: soltexd's /metrics exposes the counters, and after serving one level-0 brick and
// one coarsest brick of a fresh server they hold exactly what those two levels' plans give.
TEST(SceneNeeds, ServerMetricsExposeOctaveWork) {
  SoltexdProcess server;
  const std::string before = metrics(server);
  ASSERT_EQ(metric_value(before, "soltex_octave_samples_evaluated_total"), 0.0) << before;
  ASSERT_EQ(metric_value(before, "soltex_octave_samples_skipped_total"), 0.0);
  BrickCache cache(std::size_t{64} << 20);
  net::BrickFetcher fetcher(server.grpc_address(), cache);
  const uint64_t id = fetcher.register_texture(six_octave_marble(), kOctaveVolume, 16, {});
  const BrickLayout layout(kOctaveVolume, 16);
  fetcher.want({{{id, layout.coarsest_level(), glm::ivec3(0)}, 1}, {{id, 0, glm::ivec3(0)}, 1}});
  ASSERT_TRUE(fetcher.wait_idle(std::chrono::seconds(60)));
  ASSERT_EQ(fetcher.stats().received, 2u);
  const std::string after = metrics(server);
  const double samples = layout.samples_per_brick();
  EXPECT_EQ(metric_value(after, "soltex_octave_samples_evaluated_total"), (5 + 1) * samples);
  EXPECT_EQ(metric_value(after, "soltex_octave_samples_skipped_total"), (2 + 6) * samples);
}

// ---- Shading ---------------------------------------------------------------------------------

// Expected: a scene whose materials are all unlit shades no pixel; lit, every covered pixel;
// with only the floor unlit, some but not all.
TEST(SceneNeeds, UnlitMaterialsSkipShading) {
  for (const int unlit_objects : {0, 1, 4}) {
    Scene scene = default_scene();
    ASSERT_EQ(scene.objects.size(), 4u);
    // The floor is the last object; unlit_objects counts from the end.
    for (int i = 0; i < unlit_objects; ++i)
      scene.objects[3 - static_cast<std::size_t>(i)].material.unlit = true;
    stability::LocalRender render;
    const PreparedScene prepared =
        prepare_scene(scene, TextureResolution{7, 16, {}}, render.source);
    const Frame frame = render.renderer.render(prepared, scene.camera, kWidth, kHeight);
    ASSERT_GT(frame.stats.covered_pixels, 0u);
    if (unlit_objects == 0) {
      EXPECT_EQ(frame.stats.shaded_pixels, frame.stats.covered_pixels);
    } else if (unlit_objects == 1) {
      EXPECT_GT(frame.stats.shaded_pixels, 0u);
      EXPECT_LT(frame.stats.shaded_pixels, frame.stats.covered_pixels);
    } else {
      EXPECT_EQ(frame.stats.shaded_pixels, 0u);
    }
  }
}

// ---- The default scene, counted --------------------------------------------------------------

// What the default scene computes at its own size (1280 x 720) and a finest level of 2^9 cells,
// rendered until converged against a fresh soltexd: printed (docs/PERFORMANCE.md quotes it)
// and checked against the counters' definitions.
TEST(SceneNeeds, DefaultSceneReport) {
  const Scene scene = default_scene();
  const int width = scene.image.width, height = scene.image.height;
  const TextureResolution resolution{9, 16, {}};
  SoltexdProcess server;
  const FetchedScene fetched = fetch_scene(server, scene, resolution, width, height);
  ASSERT_TRUE(fetched.converged);
  for (int channels : fetched.channels_in_cache) EXPECT_EQ(channels, 3);
  const std::string m = metrics(server);
  const double server_evaluated = metric_value(m, "soltex_octave_samples_evaluated_total");
  const double server_skipped = metric_value(m, "soltex_octave_samples_skipped_total");
  const FetchedScene all_channels =
      fetch_scene(server, with_channels(scene, {true, true, true}), resolution, width, height);
  ASSERT_TRUE(all_channels.converged);

  // The same textures (ids are content-addressed), in process, for what the counts mean.
  stability::LocalRender local;
  const PreparedScene prepared = prepare_scene(scene, resolution, local.source);
  const GBuffer g = stability::rasterize(prepared, scene.camera, width, height);
  const KeySet surface = surface_bricks(prepared, g, local.cache);
  const auto work = octave_work(prepared, fetched.requested);
  OctaveWork total;
  for (const auto& [where, w] : work) {
    total.evaluated += w.evaluated;
    total.skipped += w.skipped;
  }
  EXPECT_EQ(server_evaluated, static_cast<double>(total.evaluated));
  EXPECT_EQ(server_skipped, static_cast<double>(total.skipped));

  // Without its clip plane, and with every material unlit: one frame each.
  const Scene no_plane = default_scene_without_clip_planes();
  Scene unlit = default_scene();
  for (SceneObject& object : unlit.objects) object.material.unlit = true;
  const Frame no_plane_frame = local.renderer.render(
      prepare_scene(no_plane, resolution, local.source), no_plane.camera, width, height);
  const Frame unlit_frame = local.renderer.render(prepare_scene(unlit, resolution, local.source),
                                                  unlit.camera, width, height);
  EXPECT_EQ(no_plane_frame.stats.raster.clip_plane_work(), 0u);
  EXPECT_EQ(unlit_frame.stats.shaded_pixels, 0u);

  const auto u = [](auto v) { return static_cast<unsigned long long>(v); };
  const FrameStats& stats = fetched.last;
  const RasterStats& r = stats.raster;
  std::printf(
      "default scene, %dx%d, finest level 2^%d, bricks of 16^3, band-limited MIP, "
      "converged in %d frames\n",
      width, height, resolution.finest_level_log2, fetched.frames);
  std::printf(
      "clip-plane work with the scene's plane: triangles tested %llu (rejected %llu, "
      "straddling %llu), fragments tested %llu (discarded %llu), cap rays %llu, cap "
      "pixels %llu; clip_plane_work() %llu; without the plane: %llu\n",
      u(r.triangles_clip_tested), u(r.triangles_clip_rejected), u(r.triangles_clip_straddling),
      u(r.fragments_clip_tested), u(r.fragments_clip_discarded), u(r.cap_rays), u(r.cap_pixels),
      u(r.clip_plane_work()), u(no_plane_frame.stats.raster.clip_plane_work()));
  std::printf("bricks: object | requested | on the surface | dense cube at those levels\n");
  uint64_t dense_total = 0;
  for (const PreparedObject& o : prepared.objects) {
    KeySet requested, on_surface;
    for (const BrickKey& key : fetched.requested) {
      if (key.texture == o.texture_id) requested.insert(key);
    }
    for (const BrickKey& key : surface) {
      if (key.texture == o.texture_id) on_surface.insert(key);
    }
    // A texture evaluated per pixel is never fetched.
    if (evaluated_per_pixel(o.texture, TextureAccess::automatic)) {
      EXPECT_TRUE(requested.empty()) << o.object->name;
    }
    const uint64_t dense = dense_bricks(prepared, requested);
    dense_total += dense;
    std::printf("  %s | %zu | %zu | %llu\n", o.object->name.c_str(), requested.size(),
                on_surface.size(), u(dense));
  }
  std::printf(
      "  all | %zu | %zu | %llu (requested / dense: %.2f %%)\n", fetched.requested.size(),
      surface.size(), u(dense_total),
      100.0 * static_cast<double>(fetched.requested.size()) / static_cast<double>(dense_total));
  EXPECT_EQ(stats.evaluated_objects + stats.cached_objects, prepared.objects.size());
  std::printf(
      "texture access (auto, docs/TEXTURES.md \"Cache or evaluate\"): objects evaluated per "
      "pixel %zu, cached %zu; covered pixels evaluated %zu of %zu (%.1f %%)\n",
      stats.evaluated_objects, stats.cached_objects, stats.evaluated_pixels, stats.covered_pixels,
      100.0 * static_cast<double>(stats.evaluated_pixels) /
          static_cast<double>(std::max<std::size_t>(1, stats.covered_pixels)));
  for (const PreparedObject& o : prepared.objects) {
    std::printf("  %s | %s | %s\n", o.object->name.c_str(), pattern_name(o.texture.pattern),
                evaluated_per_pixel(o.texture, TextureAccess::automatic)
                    ? "evaluated per pixel, no bricks"
                    : "cached lookup");
  }
  std::printf(
      "bytes: colour only %llu (%.0f per brick, 3 channels); colour + opacity + specular "
      "%llu (%.0f per brick, 5 channels)\n",
      u(fetched.stats.bytes),
      static_cast<double>(fetched.stats.bytes) / static_cast<double>(fetched.stats.received),
      u(all_channels.stats.bytes),
      static_cast<double>(all_channels.stats.bytes) /
          static_cast<double>(all_channels.stats.received));
  std::printf("octave-samples: evaluated %llu, skipped %llu (soltexd /metrics: %.0f, %.0f)\n",
              u(total.evaluated), u(total.skipped), server_evaluated, server_skipped);
  for (const auto& [where, w] : work) {
    if (w.evaluated + w.skipped == 0) continue;  // no noise octaves (wood, checker)
    std::printf("  %s, level %d: %llu bricks, %.0f octaves evaluated and %.0f skipped per sample\n",
                where.first.c_str(), where.second, u(w.bricks),
                static_cast<double>(w.evaluated) / static_cast<double>(w.samples),
                static_cast<double>(w.skipped) / static_cast<double>(w.samples));
  }
  std::printf("shading: %zu of %zu covered pixels shaded; with every material unlit %zu of %zu\n",
              stats.shaded_pixels, stats.covered_pixels, unlit_frame.stats.shaded_pixels,
              unlit_frame.stats.covered_pixels);
}

}  // namespace
}  // namespace soltex
