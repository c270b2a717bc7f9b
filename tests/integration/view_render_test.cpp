// The client's rendering path against a real soltexd on loopback.
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>

#include "headless_session.h"
#include "soltex/capability/capability.h"
#include "soltex/net/brick_fetcher.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/scene/default_scene.h"
#include "soltex/scene/scene_loader.h"
#include "soltexd_process.h"

namespace soltex {
namespace {

using testing::SoltexdProcess;

constexpr int kWidth = 320;
constexpr int kHeight = 180;

struct Rendered {
  Image image;
  net::SourceStats stats;
  bool converged;
  std::size_t evaluated_here = 0;  // objects whose texture the source refused
};

Rendered render_with(net::BrickSource& source, BrickCache& cache, const Scene& scene,
                     int finest_level, RenderOptions options = {}) {
  PreparedScene prepared = prepare_scene(scene, TextureResolution{finest_level, 16, {}}, source);
  FrameRenderer renderer(cache, options);
  view::HeadlessOptions headless;
  headless.max_time = std::chrono::seconds(60);
  const view::HeadlessResult result = view::render_until_converged(
      renderer, prepared, scene.camera, kWidth, kHeight, source, headless);
  const auto refused = std::count_if(prepared.objects.begin(), prepared.objects.end(),
                                     [](const PreparedObject& o) { return o.evaluated_here; });
  return {result.image, source.stats(), result.converged_ms >= 0.0,
          static_cast<std::size_t>(refused)};
}

TEST(ViewRender, ConvergedImageEqualsTheInProcessSourceBitForBit) {
  const Scene scene = default_scene();
  SoltexdProcess server;
  BrickCache remote_cache(256u << 20);
  net::BrickFetcher fetcher(server.grpc_address(), remote_cache);
  const Rendered remote = render_with(fetcher, remote_cache, scene, 7);

  BrickCache local_cache(256u << 20);
  net::LocalBrickSource local(local_cache);
  const Rendered in_process = render_with(local, local_cache, scene, 7);

  ASSERT_TRUE(remote.converged);
  ASSERT_TRUE(in_process.converged);
  EXPECT_GT(remote.stats.received, 0u);
  EXPECT_GT(remote.stats.bytes, 0u);
  EXPECT_TRUE(remote.image == in_process.image);
}

// As many objects as a scene may hold, each with a texture of its own (marble, which the
// client draws from bricks): a soltexd with its default limits serves them all to one client.
TEST(ViewRender, ASceneOfTheMostObjectsConvergesAgainstADefaultServer) {
  std::string objects;
  constexpr int kSide = 32;
  static_assert(kSide * kSide == SceneLimits::kMaxObjects);
  for (int i = 0; i < SceneLimits::kMaxObjects; ++i) {
    if (i > 0) objects += ",";
    objects += R"({"mesh": {"box": {"size": 0.2}}, "transform": {"translate": [)" +
               std::to_string((i % kSide - kSide / 2) * 0.3) + ", 0, " +
               std::to_string(-(i / kSide) * 0.3) + R"(]}, "material": {"texture": {"marble": )" +
               R"({"frequency": )" + std::to_string(1.0 + i * 0.001) + "}}}}";
  }
  const Scene scene = parse_scene(
      R"({"camera": {"position": [0, 6, 4], "target": [0, 0, -4], "far": 100}, "objects": [)" +
          objects + "]}",
      "<most objects>");
  SoltexdProcess server;
  BrickCache cache(256u << 20);
  net::BrickFetcher fetcher(server.grpc_address(), cache);
  const Rendered rendered = render_with(fetcher, cache, scene, 5);
  EXPECT_TRUE(rendered.converged);
  EXPECT_EQ(rendered.stats.errors, 0u);
  EXPECT_GE(rendered.stats.received, static_cast<uint64_t>(SceneLimits::kMaxObjects));
}

// A graph of 200 nodes, whose registration is over 6,000 bytes.
std::string large_graph_texture() {
  std::string nodes = R"({"name": "p", "category": "position"})";
  for (int i = 0; i < 200; ++i) {
    nodes += R"(, {"name": "n)" + std::to_string(i) +
             R"(", "category": "extract", "inputs": {"in": {"node": "p"}, "index": )" +
             std::to_string(i % 3) + "}}";
  }
  nodes += R"(, {"name": "c", "category": "combine3", "type": "color3",
                 "inputs": {"in1": {"node": "n0"}, "in2": {"node": "n1"}, "in3": {"node": "n2"}}})";
  return R"({"graph": {"nodes": [)" + nodes + R"(], "outputs": {"colour": "c"}}})";
}

// A server that refuses one texture (here, its registration over the server's message bound)
// still serves the rest of the scene: the refused object's texture is evaluated per pixel by
// the client, and the picture converges to what a server taking both would give.
TEST(ViewRender, ATextureTheServerRefusesIsEvaluatedHere) {
  const Scene scene = parse_scene(R"({
    "camera": {"position": [0, 1, 4], "target": [0, 0, 0]},
    "objects": [
      {"name": "served", "mesh": {"sphere": {}}, "transform": {"translate": [-1.2, 0, 0]},
       "material": {"texture": {"marble": {}}}},
      {"name": "refused", "mesh": {"sphere": {}}, "transform": {"translate": [1.2, 0, 0]},
       "material": {"texture": )" + large_graph_texture() +
                                      R"(}}]})",
                                  "<two textures>");
  SoltexdProcess server({"--max-message-bytes", "6000"});
  BrickCache cache(64u << 20);
  net::BrickFetcher fetcher(server.grpc_address(), cache);
  PreparedScene prepared = prepare_scene(scene, TextureResolution{7, 16, {}}, fetcher);
  ASSERT_EQ(prepared.objects.size(), 2u);
  EXPECT_FALSE(prepared.objects[0].evaluated_here);
  EXPECT_TRUE(prepared.objects[1].evaluated_here);
  const Rendered rendered = render_with(fetcher, cache, scene, 7);
  EXPECT_TRUE(rendered.converged);
  EXPECT_GT(rendered.stats.received, 0u) << "the served object's bricks came from the server";

  SoltexdProcess roomy;
  BrickCache roomy_cache(64u << 20);
  net::BrickFetcher both(roomy.grpc_address(), roomy_cache);
  const Rendered served = render_with(both, roomy_cache, scene, 7);
  ASSERT_TRUE(served.converged);
  // The served sphere the same; the other differs only as evaluating a texture differs from
  // looking it up.
  EXPECT_GT(psnr(rendered.image, served.image), 35.0);
}

// A server whose registry holds fewer textures than the scene has takes every RegisterTexture
// (nothing pins a texture yet) and refuses the last texture when the stream sends them all. The
// frame goes on with that object evaluated per pixel and converges.
TEST(ViewRender, ATextureRefusedOnTheStreamIsEvaluatedHere) {
  const Scene scene = default_scene();
  SoltexdProcess server({"--max-textures", "3"});
  BrickCache cache(256u << 20);
  net::BrickFetcher fetcher(server.grpc_address(), cache);
  const Rendered rendered = render_with(fetcher, cache, scene, 7);
  ASSERT_TRUE(rendered.converged);
  EXPECT_EQ(rendered.evaluated_here, 1u);
  EXPECT_EQ(rendered.stats.errors, 0u);

  BrickCache local_cache(256u << 20);
  net::LocalBrickSource local(local_cache);
  const Rendered in_process = render_with(local, local_cache, scene, 7);
  ASSERT_TRUE(in_process.converged);
  EXPECT_GT(psnr(rendered.image, in_process.image), 35.0);
}

// Smooth textures (marble, turbulence): their cached, trilinearly filtered image approaches
// the per-pixel evaluation. Two-colour patterns (checker, wood) differ along every colour edge,
// where interpolation ramps what point evaluation keeps sharp; docs/PERFORMANCE.md measures it.
TEST(ViewRender, CachedImageIsWithin40DbOfThePerPixelReference) {
  Scene scene = default_scene();
  std::erase_if(scene.objects, [](const SceneObject& o) {
    return std::holds_alternative<CheckerParams>(o.material.texture.pattern) ||
           std::holds_alternative<WoodParams>(o.material.texture.pattern);
  });
  ASSERT_EQ(scene.objects.size(), 2u);
  BrickCache cache(512u << 20);
  net::LocalBrickSource source(cache);
  PreparedScene prepared = prepare_scene(scene, TextureResolution{9, 16, {}}, source);
  FrameRenderer renderer(cache, RenderOptions{});
  view::HeadlessOptions headless;
  const view::HeadlessResult cached = view::render_until_converged(
      renderer, prepared, scene.camera, kWidth, kHeight, source, headless);
  ASSERT_GE(cached.converged_ms, 0.0);
  const Image reference = renderer.render_reference(prepared, scene.camera, kWidth, kHeight, 1);
  const double db = psnr(cached.image, reference);
  RecordProperty("psnr_db", std::to_string(db));
  EXPECT_GE(db, 40.0);
}

// A machine that draws 50,000 pixels a second shrinks its window's frame to what it draws in
// 100 ms, and a texel per pixel of that frame is a coarser level.
TEST(ViewRender, AWeakClientChoosesCoarserLevelsAndFetchesFewerBytes) {
  const Scene scene = default_scene();
  capability::Capability strong;
  strong.pixels_per_second = 50e6;
  strong.available_memory_mb = 16000;
  strong.bandwidth_mb_per_s = 500.0;
  const capability::Capability weak =
      capability::apply(strong, capability::parse_override("cpu=0.001,mem=256,bandwidth=0.5"));
  const capability::Choice strong_choice = capability::choose(strong, scene, kWidth, kHeight);
  const capability::Choice weak_choice = capability::choose(weak, scene, kWidth, kHeight);
  EXPECT_LT(weak_choice.finest_level_log2, strong_choice.finest_level_log2) << weak_choice.reason;
  EXPECT_LT(weak_choice.cache_budget_bytes, strong_choice.cache_budget_bytes);
  EXPECT_LE(weak_choice.width, strong_choice.width);

  SoltexdProcess server;
  BrickCache strong_cache(strong_choice.cache_budget_bytes);
  net::BrickFetcher strong_fetcher(server.grpc_address(), strong_cache);
  const Rendered strong_render =
      render_with(strong_fetcher, strong_cache, scene, strong_choice.finest_level_log2);
  BrickCache weak_cache(weak_choice.cache_budget_bytes);
  net::BrickFetcher weak_fetcher(server.grpc_address(), weak_cache);
  const Rendered weak_render =
      render_with(weak_fetcher, weak_cache, scene, weak_choice.finest_level_log2);
  EXPECT_TRUE(strong_render.converged);
  EXPECT_TRUE(weak_render.converged);
  EXPECT_LT(weak_render.stats.bytes, strong_render.stats.bytes);
}

TEST(ViewRender, KeepsDrawingThroughAServerRestart) {
  const Scene scene = default_scene();
  const int port = testing::free_port();
  std::optional<SoltexdProcess> server(std::in_place, std::vector<std::string>{}, port);
  BrickCache cache(256u << 20);
  net::FetcherOptions options;
  options.initial_backoff = std::chrono::milliseconds(50);
  options.max_backoff = std::chrono::milliseconds(400);
  net::BrickFetcher fetcher("127.0.0.1:" + std::to_string(port), cache, options);
  PreparedScene prepared = prepare_scene(scene, TextureResolution{8, 16, {}}, fetcher);
  FrameRenderer renderer(cache, RenderOptions{});

  // A few frames: some bricks arrive, then the server goes away mid-render.
  for (int i = 0; i < 2; ++i) {
    Frame frame = renderer.render(prepared, scene.camera, kWidth, kHeight);
    fetcher.want(std::move(frame.misses));
    fetcher.wait_idle(std::chrono::milliseconds(30));
  }
  ASSERT_EQ(server->terminate(), 0);
  server.reset();
  // Frames still draw from what the cache holds.
  const Frame offline = renderer.render(prepared, scene.camera, kWidth, kHeight);
  EXPECT_GT(offline.stats.covered_pixels, 0u);
  fetcher.want(offline.misses);

  server.emplace(std::vector<std::string>{}, port);
  // Ask for finer bricks than before, so the frames after the restart need the new server.
  renderer.set_level_bias(-1.0);
  const uint64_t received_before = fetcher.stats().received;
  view::HeadlessOptions headless;
  headless.max_time = std::chrono::seconds(60);
  const view::HeadlessResult result = view::render_until_converged(
      renderer, prepared, scene.camera, kWidth, kHeight, fetcher, headless);
  EXPECT_GE(result.converged_ms, 0.0);
  EXPECT_GE(fetcher.stats().reconnects, 1u);
  EXPECT_GT(fetcher.stats().received, received_before);
}

// A slow server (every brick 20 ms late) never holds a frame up: frames are drawn at once from
// what the cache holds while the bricks trickle in, and the picture still converges to the
// in-process one.
TEST(ViewRender, ASlowServerLeavesTheClientDrawing) {
  const Scene scene = default_scene();
  SoltexdProcess server({"--fault-delay-ms", "20", "--threads", "2"});
  BrickCache cache(256u << 20);
  net::BrickFetcher fetcher(server.grpc_address(), cache);
  PreparedScene prepared = prepare_scene(scene, TextureResolution{6, 16, {}}, fetcher);
  FrameRenderer renderer(cache, RenderOptions{});

  Frame first = renderer.render(prepared, scene.camera, kWidth, kHeight);
  EXPECT_GT(first.stats.covered_pixels, 0u);
  fetcher.want(std::move(first.misses));
  int frames_while_waiting = 0;
  std::vector<double> frame_ms;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fetcher.idle() && std::chrono::steady_clock::now() < deadline) {
    const auto start = std::chrono::steady_clock::now();
    Frame frame = renderer.render(prepared, scene.camera, kWidth, kHeight);
    frame_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
    fetcher.want(std::move(frame.misses));
    ++frames_while_waiting;
    fetcher.wait_idle(std::chrono::milliseconds(10));  // the pace of an interactive loop
  }
  std::sort(frame_ms.begin(), frame_ms.end());
  RecordProperty("frames_while_waiting", frames_while_waiting);
  if (!frame_ms.empty())
    RecordProperty("median_frame_ms", std::to_string(frame_ms[frame_ms.size() / 2]));
  // Frames went on while bricks were owed: the loop was never blocked by the network.
  EXPECT_GE(frames_while_waiting, 3);

  view::HeadlessOptions headless;
  headless.max_time = std::chrono::seconds(60);
  const view::HeadlessResult converged = view::render_until_converged(
      renderer, prepared, scene.camera, kWidth, kHeight, fetcher, headless);
  ASSERT_GE(converged.converged_ms, 0.0);
  BrickCache local_cache(256u << 20);
  net::LocalBrickSource local(local_cache);
  EXPECT_TRUE(converged.image == render_with(local, local_cache, scene, 6).image);
}

// The capability's start is a cap, not the end: converged at 2^5 first, the run refines to the
// prepared levels and ends with the picture a run without a start draws, bit for bit; a cache
// too small for the finest level stops it where the budget holds, converged.
TEST(ViewRender, StartingCoarseRefinesToTheSamePicture) {
  const Scene scene = default_scene();
  const auto run = [&](std::size_t budget, int start_level) {
    BrickCache cache(budget);
    net::LocalBrickSource source(cache);
    PreparedScene prepared = prepare_scene(scene, TextureResolution{8, 16, {}}, source);
    FrameRenderer renderer(cache, RenderOptions{});
    view::HeadlessOptions headless;
    headless.max_time = std::chrono::seconds(60);
    headless.start_level_log2 = start_level;
    headless.cache = &cache;
    return view::render_until_converged(renderer, prepared, scene.camera, kWidth, kHeight, source,
                                        headless);
  };
  const view::HeadlessResult direct = run(256u << 20, 0);
  const view::HeadlessResult refined = run(256u << 20, 5);
  ASSERT_GE(direct.converged_ms, 0.0);
  ASSERT_GE(refined.converged_ms, 0.0);
  EXPECT_EQ(refined.start_level_log2, 5);
  EXPECT_GE(refined.start_converged_ms, 0.0);
  EXPECT_LE(refined.start_converged_ms, refined.converged_ms);
  EXPECT_EQ(refined.refined_level_log2, 8);
  EXPECT_TRUE(refined.image == direct.image);

  const view::HeadlessResult tight = run(2u << 20, 5);
  ASSERT_GE(tight.converged_ms, 0.0);
  EXPECT_GE(tight.refined_level_log2, 5);
  EXPECT_LT(tight.refined_level_log2, 8);
}

// The first frame, drawn in false colour only for its misses, asks for what a shaded one
// does: the run converges in as many frames to the same picture. With every brick resident
// already it misses nothing, and the shaded frame after it is the output.
TEST(ViewRender, AFirstFrameDrawnForItsMissesConvergesToTheSamePicture) {
  const Scene scene = default_scene();
  const auto run = [&](BrickCache& cache, bool for_misses) {
    net::LocalBrickSource source(cache);
    PreparedScene prepared = prepare_scene(scene, TextureResolution{7, 16, {}}, source);
    FrameRenderer renderer(cache, RenderOptions{});
    view::HeadlessOptions headless;
    headless.max_time = std::chrono::seconds(60);
    headless.first_frame_for_misses = for_misses;
    return view::render_until_converged(renderer, prepared, scene.camera, kWidth, kHeight, source,
                                        headless);
  };
  BrickCache shaded_cache(256u << 20);
  const view::HeadlessResult shaded = run(shaded_cache, false);
  BrickCache cache(256u << 20);
  const view::HeadlessResult for_misses = run(cache, true);
  ASSERT_GE(shaded.converged_ms, 0.0);
  ASSERT_GE(for_misses.converged_ms, 0.0);
  EXPECT_EQ(for_misses.frames, shaded.frames);
  EXPECT_TRUE(for_misses.image == shaded.image);

  const view::HeadlessResult warm = run(cache, true);
  ASSERT_GE(warm.converged_ms, 0.0);
  EXPECT_EQ(warm.frames, 2);
  EXPECT_TRUE(warm.image == shaded.image);
}

// Every brick arrives corrupt, so every brick fails after its refetches. The headless loop
// notices that nothing is on its way any more and stops, not converged, without waiting for
// its time limit, with the picture drawn from what it has.
TEST(ViewRender, HeadlessStopsEarlyWhenBricksFailForGood) {
  const Scene scene = default_scene();
  SoltexdProcess server({"--fault-corrupt-every", "1"});
  BrickCache cache(256u << 20);
  net::BrickFetcher fetcher(server.grpc_address(), cache);
  PreparedScene prepared = prepare_scene(scene, TextureResolution{6, 16, {}}, fetcher);
  FrameRenderer renderer(cache, RenderOptions{});
  view::HeadlessOptions headless;
  headless.max_time = std::chrono::seconds(60);
  const view::HeadlessResult result = view::render_until_converged(
      renderer, prepared, scene.camera, kWidth, kHeight, fetcher, headless);
  EXPECT_LT(result.converged_ms, 0.0);
  EXPECT_TRUE(result.bricks_failed);
  EXPECT_GT(fetcher.stats().errors, 0u);
  EXPECT_EQ(fetcher.stats().received, 0u);
  // A few frames (the failures settle, then two frames see nothing on its way), not the
  // thousands a loop that waited for its time limit would draw.
  EXPECT_LE(result.frames, 20);
  EXPECT_EQ(result.image.width, kWidth);
}

}  // namespace
}  // namespace soltex
