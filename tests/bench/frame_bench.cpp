// soltex-view's warm frame: deploy/scenes/bunny-marble.json (the Stanford bunny in marble on a
// wood floor) at 1280 x 720, every brick resident (converged once, from an in-process
// LocalBrickSource, before timing), finest level 2^8 where a material does not set its own
// (the bunny's marble sets 2^9).
//   BM_WarmFrame       FrameRenderer::render: raster + brick lookup + shade
//   BM_WarmFrameIsotropic  the same with one lookup per pixel (RenderOptions::anisotropy 1)
//                      instead of taps along grazing footprints, its bricks converged for it
//   BM_Raster          the rasterizer alone on the same view and meshes (mesh_for_view()), into
//                      tile-sized G-buffers as FrameRenderer draws (its raster part, without
//                      shading); /1/5 and /1/6 the spheres on one thread
//   BM_SpherePair      the warm frames of the two spheres (5 and 6 below) in turn, in
//                      alternating order: counters fine_ms and coarse_ms (medians of each
//                      frame's process CPU time) and ratio (median of each pair's ratio,
//                      target 4); the one argument is the thread count
//   BM_ReferenceFrame  FrameRenderer::render_reference: the texture evaluated per pixel
//   BM_ColdFrame       FrameRenderer::render with nothing resident (a client's first frame):
//                      every pixel misses, and the frame lists every brick it wants; third
//                      argument 0 shaded, 1 in false colour with each tile's misses reported
//                      as it is done (soltex-view's headless start before misses-only
//                      frames), 2 misses only (RenderOptions::misses_only), as it draws now
// First argument: the thread count (the caller's thread included). Second: 0 for the scene as
// it is, 1 for the bunny alone (the floor removed): the wood floor's two-colour rings keep the
// whole frame at about 26 dB against the reference, the marble alone is above 40 dB, so the
// speed ratio at PSNR >= 40 dB is read from the second; 2 for the bunny alone drawn with both
// faces (the scene draws front faces only), to show what back-face culling saves; 3 for the
// built-in default scene instead (four objects; a clip plane cuts the marble sphere open, so
// the frame has caps); 4 for the bunny alone in bricks of 8 instead of 16; 5, 6 and 7 a
// marble sphere of a million triangles, of ten thousand, and of a million drawn without its
// simplified levels (sphere_scene()); /1/5 and /1/6 the two spheres on one thread, whose
// instructions valgrind counts whole (it runs threads one at a time). Times are
// wall-clock per frame; the CPU column is the whole process's CPU time (all render threads) per
// frame. Counters: the warm frame's raster and shade wall times (ms) as FrameRenderer reports them,
// and its PSNR against the per-pixel reference (dB).
//   BM_TexturePass     the texturing pass alone, one thread, over the covered pixels of the
//                      bunny's warm G-buffer (raster and lighting excluded): third argument 0
//                      the cached lookup as TileShader makes it (levels from the footprints
//                      in vector lanes, pixels grouped by level, TextureSampler's batch call
//                      per group), 1 the texture evaluated over the footprint (as
//                      TextureAccess::evaluated), 2 the cached lookup pixel by pixel
//                      (locate_rgb, trilinear_rgb a batch later)
//   BM_EqualPsnr       the warm frame (third argument 0) and the per-pixel reference at K x K
//                      sub-pixels (third argument K), each with its PSNR against the 8 x 8
//                      reference (psnr_8x8_db): the reference's K that first reaches the warm
//                      frame's PSNR is the one whose time the warm frame is compared with.
//                      Fourth argument N > 0: the warm frame with edge anti-aliasing at N x N
//                      samples per edge pixel (RenderOptions::edge_antialias; edge_pixels
//                      counts the pixels it blended)

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "converge.h"
#include "cpu_samples.h"
#include "lit_pixels.h"
#include "mesh_for_view.h"
#include "soltex/common/brick_cache.h"
#include "soltex/common/sampling_kernels.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/common/texture_sampler.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/raster/rasterizer.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/image.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/default_scene.h"
#include "soltex/scene/scene_loader.h"
#include "texture_surface.h"

namespace {

constexpr int kWidth = 1280;
constexpr int kHeight = 720;

// A marble sphere of radius 1 seen from 3.2 away (about 330,000 pixels): 5 with 998,000
// triangles (segments 1000, rings 500), 6 with 9,800 (100, 50), 7 the first without its
// simplified levels (every triangle drawn).
soltex::Scene sphere_scene(int variant) {
  const bool fine = variant != 6;
  const std::string json =
      std::string(R"({
    "camera": {"position": [0, 0.6, 3.2], "target": [0, 0, 0], "fov_y_degrees": 40},
    "lights": [{"directional": {"direction": [-0.5, -1.0, -0.7]}}],
    "objects": [{"name": "sphere", "double_sided": false,
      "mesh": {"sphere": {"radius": 1, )") +
      (fine ? R"("segments": 1000, "rings": 500)" : R"("segments": 100, "rings": 50)") +
      R"(}},
      "material": {"texture": {"marble": {"turbulence": {"scale": 2, "octave_max": 6}}},
                   "specular": 0.5, "shininess": 48}}]})";
  soltex::Scene scene = soltex::parse_scene(json, "<sphere scene>");
  if (variant == 7) {
    for (soltex::SceneObject& object : scene.objects) object.levels.reset();
  }
  return scene;
}

// One converged scene per thread count, kept for the whole run.
struct WarmScene {
  WarmScene(int threads, int variant, int anisotropy)
      : scene(load(variant)),
        cache(std::make_unique<soltex::BrickCache>(512u << 20)),
        source(std::make_unique<soltex::net::LocalBrickSource>(*cache)),
        prepared(soltex::prepare_scene(
            scene, soltex::TextureResolution{8, variant == 4 ? 8 : 16, {}}, *source)),
        renderer(std::make_unique<soltex::FrameRenderer>(
            *cache, soltex::RenderOptions{.threads = threads, .anisotropy = anisotropy})) {
    converge(*renderer, prepared, scene.camera, kWidth, kHeight, *source, "frame_bench");
    const soltex::Image warm = renderer->render(prepared, scene.camera, kWidth, kHeight).image;
    psnr = soltex::psnr(warm, renderer->render_reference(prepared, scene.camera, kWidth, kHeight));
  }

  static soltex::Scene load(int variant) {
    if (variant == 3) return soltex::default_scene();  // 4: the bunny alone, bricks of 8
    if (variant >= 5) return sphere_scene(variant);
    soltex::Scene scene = soltex::load_scene(SOLTEX_SOURCE_DIR "/deploy/scenes/bunny-marble.json");
    if (variant >= 1) {
      std::erase_if(scene.objects, [](const soltex::SceneObject& o) { return o.name == "floor"; });
    }
    if (variant == 2) {
      for (soltex::SceneObject& object : scene.objects) object.double_sided = true;
    }
    return scene;
  }

  soltex::Scene scene;
  std::unique_ptr<soltex::BrickCache> cache;
  std::unique_ptr<soltex::net::LocalBrickSource> source;
  soltex::PreparedScene prepared;
  std::unique_ptr<soltex::FrameRenderer> renderer;
  double psnr = 0.0;
};

// `isotropic`: one lookup per pixel (RenderOptions::anisotropy 1) instead of the default taps.
WarmScene& warm_scene(int threads, int variant, bool isotropic = false) {
  constexpr int kThreadCounts = 3, kVariants = 8;  // threads 0..2, variants 0..7
  static std::unique_ptr<WarmScene> scenes[kThreadCounts][kVariants][2];
  if (threads < 0 || threads >= kThreadCounts || variant < 0 || variant >= kVariants) {
    throw std::out_of_range("frame_bench: no scene slot for these arguments");
  }
  auto& s = scenes[threads][variant][isotropic ? 1 : 0];
  if (!s) {
    s = std::make_unique<WarmScene>(threads, variant,
                                    isotropic ? 1 : soltex::RenderOptions{}.anisotropy);
  }
  return *s;
}

WarmScene& warm_scene(const benchmark::State& state, bool isotropic = false) {
  return warm_scene(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), isotropic);
}

void warm_frame(benchmark::State& state, WarmScene& w) {
  double raster_ms = 0.0, shade_ms = 0.0;
  std::size_t covered = 0, triangles = 0;
  for (auto _ : state) {
    soltex::Frame frame = w.renderer->render(w.prepared, w.scene.camera, kWidth, kHeight);
    if (!frame.complete()) state.SkipWithError("warm frame missed a brick");
    raster_ms += frame.stats.raster_ms;
    shade_ms += frame.stats.shade_ms;
    covered = frame.stats.covered_pixels;
    triangles = frame.stats.raster.triangles_in;
    benchmark::DoNotOptimize(frame.image);
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["raster_ms"] = raster_ms / n;
  state.counters["shade_ms"] = shade_ms / n;
  state.counters["covered"] = static_cast<double>(covered);
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["psnr_db"] = w.psnr;
}

void BM_WarmFrame(benchmark::State& state) {
  warm_frame(state, warm_scene(state));
}

void BM_WarmFrameIsotropic(benchmark::State& state) {
  warm_frame(state, warm_scene(state, true));
}

// Target 4 as one figure: the fine and the coarse sphere's warm frames rendered in turn, in
// alternating order, each pair's CPU-time ratio taken at once. A shared machine's load changes
// over seconds; within a pair both frames meet the same load, so the median of the pairs'
// ratios is far steadier than a ratio of two benchmarks' medians measured seconds apart.
void BM_SpherePair(benchmark::State& state) {
  const auto threads = static_cast<int>(state.range(0));
  std::array<WarmScene*, 2> scenes = {&warm_scene(threads, 5), &warm_scene(threads, 6)};
  std::array<std::vector<double>, 2> cpu_ms;
  std::vector<double> ratio;
  bool fine_first = true;
  for (auto _ : state) {
    std::array<double, 2> spent{};
    for (int k = 0; k < 2; ++k) {
      const int which = fine_first ? k : 1 - k;
      WarmScene& w = *scenes[static_cast<std::size_t>(which)];
      const double start = cpu_clock_ns(CLOCK_PROCESS_CPUTIME_ID);
      soltex::Frame frame = w.renderer->render(w.prepared, w.scene.camera, kWidth, kHeight);
      spent[static_cast<std::size_t>(which)] =
          (cpu_clock_ns(CLOCK_PROCESS_CPUTIME_ID) - start) * 1e-6;
      if (!frame.complete()) state.SkipWithError("warm frame missed a brick");
      benchmark::DoNotOptimize(frame.image);
    }
    fine_first = !fine_first;
    cpu_ms[0].push_back(spent[0]);
    cpu_ms[1].push_back(spent[1]);
    ratio.push_back(spent[0] / spent[1]);
  }
  state.counters["fine_ms"] = median(cpu_ms[0]);
  state.counters["coarse_ms"] = median(cpu_ms[1]);
  state.counters["ratio"] = median(ratio);
}

void BM_Raster(benchmark::State& state) {
  WarmScene& w = warm_scene(state);
  // The same view and objects FrameRenderer draws (eye-relative), through a rasterizer of its
  // own so that FrameRenderer's G-buffer stays untouched.
  soltex::Rasterizer rasterizer({.threads = static_cast<int>(state.range(0))});
  const soltex::Camera& camera = w.scene.camera;
  soltex::Camera at_origin = camera;
  at_origin.target = camera.target - camera.position;
  at_origin.position = glm::dvec3(0.0);
  const glm::dmat4 from_world = glm::translate(glm::dmat4(1.0), -camera.position);
  std::vector<soltex::RasterObject> objects;
  for (const soltex::PreparedObject& o : w.prepared.objects) {
    soltex::RasterObject object = o.raster;
    object.model = glm::mat4(from_world * o.world_from_object);
    object.mesh = soltex::render::mesh_for_view(o, camera, kHeight);
    objects.push_back(object);
  }
  soltex::RasterView view;
  view.width = kWidth;
  view.height = kHeight;
  view.view_projection = glm::mat4(soltex::view_projection(at_origin, kWidth, kHeight));
  std::size_t covered = 0;
  for (auto _ : state) {
    const soltex::RasterStats stats = rasterizer.render_tiles(
        view, objects, [](const soltex::GBuffer& tile, int, int, int, int, int) {
          benchmark::DoNotOptimize(tile.depth.data());
        });
    covered = stats.pixels_covered;
  }
  state.counters["covered"] = static_cast<double>(covered);
}

void BM_ReferenceFrame(benchmark::State& state) {
  WarmScene& w = warm_scene(state);
  for (auto _ : state) {
    soltex::Image image = w.renderer->render_reference(w.prepared, w.scene.camera, kWidth, kHeight);
    benchmark::DoNotOptimize(image);
  }
}

// How BM_ColdFrame draws: shaded, or only for the bricks it misses (soltex-view's headless
// start) in false colour as before, or finding misses alone.
enum class ColdFrameWay { shaded = 0, false_colour = 1, misses_only = 2 };

void BM_ColdFrame(benchmark::State& state) {
  WarmScene& w = warm_scene(state);
  const auto way = static_cast<ColdFrameWay>(state.range(2));
  std::size_t misses = 0;
  std::size_t reported = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto empty = std::make_unique<soltex::BrickCache>(512u << 20);
    auto renderer = std::make_unique<soltex::FrameRenderer>(
        *empty, soltex::RenderOptions{.threads = static_cast<int>(state.range(0))});
    if (way != ColdFrameWay::shaded) {
      // As soltex-view's headless start draws its first frame: each tile's misses handed on
      // as the tile is done.
      renderer->set_on_tile_misses(
          [&reported](std::vector<soltex::net::BrickWant> wants) { reported += wants.size(); });
      renderer->set_false_colour_levels(way == ColdFrameWay::false_colour);
      renderer->set_misses_only(way == ColdFrameWay::misses_only);
    }
    state.ResumeTiming();
    soltex::Frame frame = renderer->render(w.prepared, w.scene.camera, kWidth, kHeight);
    misses = frame.misses.size();
    benchmark::DoNotOptimize(frame.image);
    state.PauseTiming();
    renderer.reset();
    empty.reset();
    state.ResumeTiming();
  }
  state.counters["bricks_wanted"] = static_cast<double>(misses);
  state.counters["reported_per_frame"] =
      static_cast<double>(reported) / static_cast<double>(state.iterations());
}

// The tile shader's tiles: pixels on a side.
constexpr std::size_t kShadingTile = soltex::render::LitTile::kSide;

// The covered pixels of one object in a warm G-buffer: what the texturing pass reads.
struct TexturedPixels {
  std::vector<glm::dvec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<float> footprints;
};

const TexturedPixels& bunny_pixels(WarmScene& w) {
  static std::unique_ptr<TexturedPixels> pixels;
  if (pixels) return *pixels;
  pixels = std::make_unique<TexturedPixels>();
  soltex::FrameRenderer keeping(
      *w.cache, soltex::RenderOptions{.threads = 1, .anisotropy = 1, .keep_gbuffer = true});
  keeping.render(w.prepared, w.scene.camera, kWidth, kHeight);
  const soltex::GBuffer& g = keeping.last_gbuffer();
  // In the tile shader's order: its tiles, rows within a tile.
  constexpr int kTile = static_cast<int>(kShadingTile);
  for (int ty = 0; ty < kHeight; ty += kTile) {
    for (int tx = 0; tx < kWidth; tx += kTile) {
      for (int y = ty; y < std::min(kHeight, ty + kTile); ++y) {
        for (int x = tx; x < std::min(kWidth, tx + kTile); ++x) {
          const std::size_t i = g.index(x, y);
          if (!g.covered(i) || g.object_id[i] != 0) continue;
          pixels->positions.push_back(g.texture_position[i]);
          pixels->normals.push_back(g.normal[i]);
          pixels->footprints.push_back(g.footprint[i]);
        }
      }
    }
  }
  return *pixels;
}

// As the tile shader reads them: pixels grouped by level, each group of kSampleBatch looked up
// through the sampler's batch call.
void batched_pass(benchmark::State& state, WarmScene& w, const TexturedPixels& pixels) {
  const soltex::PreparedObject& o = w.prepared.objects.front();
  soltex::TextureSampler sampler(*w.cache, o.texture_id, o.layout, o.channels);
  const soltex::NearestLevelTable table(o.layout, 0.0);
  constexpr std::size_t kBatch = soltex::kSampleBatch;
  constexpr std::size_t kLevels = soltex::SpecLimits::kMaxFinestLevelLog2 + 1;
  std::vector<std::array<glm::dvec3, kBatch>> groups(kLevels);
  std::array<std::size_t, kLevels> counts{};
  std::array<soltex::SampleResult, kBatch> results;
  bool missed = false;
  const auto look_up = [&](std::size_t level) {
    const std::size_t n = counts[level];
    counts[level] = 0;
    sampler.sample({groups[level].data(), n}, static_cast<double>(level),
                   soltex::SampleFilter::trilinear, {results.data(), n});
    float sum = 0.0f;
    for (std::size_t j = 0; j < n; ++j) {
      missed |= !results[j].complete;
      sum += results[j].values[0] + results[j].values[1] + results[j].values[2];
    }
    return sum;
  };
  // Levels made in vector lanes, as TileShader makes them a tile row at a time; here 32
  // covered pixels at a time (the shader's rows also hold uncovered pixels, 0 to 31 of them).
  constexpr std::size_t kRow = kShadingTile;
  std::array<int32_t, kRow> row_levels;
  const std::size_t total = pixels.positions.size();
  for (auto _ : state) {
    float sum = 0.0f;
    for (std::size_t first = 0; first < total; first += kRow) {
      const std::size_t n = std::min(kRow, total - first);
      table.levels({&pixels.footprints[first], n}, row_levels.data());
      for (std::size_t j = 0; j < n; ++j) {
        const auto level = static_cast<std::size_t>(row_levels[j]);
        groups[level][counts[level]++] = pixels.positions[first + j];
        if (counts[level] == kBatch) sum += look_up(level);
      }
    }
    for (std::size_t level = 0; level < kLevels; ++level) {
      if (counts[level] > 0) sum += look_up(level);
    }
    benchmark::DoNotOptimize(sum);
  }
  if (missed) state.SkipWithError("texture pass missed a brick");
}

// The per-pixel form it replaced: each pixel located (and its cell prefetched), read a batch
// later.
void located_pass(benchmark::State& state, WarmScene& w, const TexturedPixels& pixels) {
  const soltex::PreparedObject& o = w.prepared.objects.front();
  soltex::TextureSampler sampler(*w.cache, o.texture_id, o.layout, o.channels);
  const soltex::NearestLevelTable table(o.layout, 0.0);
  // As the tile shader reads them: a batch of cells located (and prefetched), then read.
  constexpr std::size_t kBatch = 64;
  std::array<const uint8_t*, kBatch> cells;
  std::array<glm::vec3, kBatch> fractions;
  for (auto _ : state) {
    float sum = 0.0f;
    for (std::size_t first = 0; first < pixels.positions.size(); first += kBatch) {
      const std::size_t n = std::min(kBatch, pixels.positions.size() - first);
      for (std::size_t j = 0; j < n; ++j) {
        const int level = table.level(pixels.footprints[first + j]);
        cells[j] = sampler.locate_rgb(pixels.positions[first + j], level, fractions[j]);
        if (cells[j] == nullptr) {
          state.SkipWithError("texture pass missed a brick");
          return;
        }
        __builtin_prefetch(cells[j]);
        __builtin_prefetch(cells[j] + sampler.y_stride());
        __builtin_prefetch(cells[j] + sampler.z_stride());
        __builtin_prefetch(cells[j] + sampler.y_stride() + sampler.z_stride());
      }
      for (std::size_t j = 0; j < n; ++j) {
        alignas(16) float rgb[4];
        sampler.trilinear_rgb(cells[j], fractions[j], rgb);
        sum += rgb[0] + rgb[1] + rgb[2];
      }
    }
    benchmark::DoNotOptimize(sum);
  }
}

void evaluated_pass(benchmark::State& state, WarmScene& w, const TexturedPixels& pixels) {
  const soltex::PreparedObject& o = w.prepared.objects.front();
  const soltex::TextureEvaluator evaluator(o.texture);
  const soltex::render::TextureSurface surface(o);
  constexpr std::size_t kBatch = 64;  // as TileShader batches evaluated pixels
  std::array<glm::dvec3, kBatch> points;
  std::array<soltex::SampleFootprint, kBatch> footprints;
  std::array<soltex::Texel, kBatch> texels;
  for (auto _ : state) {
    float sum = 0.0f;
    for (std::size_t first = 0; first < pixels.positions.size(); first += kBatch) {
      const std::size_t n = std::min(kBatch, pixels.positions.size() - first);
      for (std::size_t j = 0; j < n; ++j) {
        const glm::dvec3 normal = surface.normal(pixels.normals[first + j]);
        const double footprint = pixels.footprints[first + j];
        points[j] = soltex::render::inset(pixels.positions[first + j], normal,
                                          soltex::render::kEvaluatedInset * footprint);
        footprints[j] = soltex::render::surface_footprint(footprint, normal);
      }
      evaluator.sample({points.data(), n}, {footprints.data(), n}, {texels.data(), n});
      for (std::size_t j = 0; j < n; ++j) sum += texels[j].colour.r;
    }
    benchmark::DoNotOptimize(sum);
  }
}

void BM_TexturePass(benchmark::State& state) {
  // One lookup, or one evaluation, per pixel at its footprint's level: the isotropic frame's
  // cache holds those bricks (the tapped frame's holds finer ones where its taps fall).
  WarmScene& w = warm_scene(state, /*isotropic=*/true);
  const TexturedPixels& pixels = bunny_pixels(w);
  if (state.range(2) == 0) {
    batched_pass(state, w, pixels);
  } else if (state.range(2) == 1) {
    evaluated_pass(state, w, pixels);
  } else {
    located_pass(state, w, pixels);
  }
  state.counters["pixels"] = static_cast<double>(pixels.positions.size());
  state.counters["ns_per_pixel"] = benchmark::Counter(
      static_cast<double>(pixels.positions.size()) * 1e-9,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// The 8 x 8 reference of the bunny-alone view, made once: the ground truth of BM_EqualPsnr.
const soltex::Image& ground_truth(WarmScene& w) {
  static std::unique_ptr<soltex::Image> image;
  if (!image) {
    image = std::make_unique<soltex::Image>(
        w.renderer->render_reference(w.prepared, w.scene.camera, kWidth, kHeight, 8));
  }
  return *image;
}

// The warm frame of a renderer with edge anti-aliasing at grid x grid samples, on the scene's
// cache, converged once (its extra surfaces may read bricks the plain frame did not).
soltex::FrameRenderer& edge_renderer(WarmScene& w, int threads, int grid) {
  static std::unique_ptr<soltex::FrameRenderer> renderers[soltex::kMaxEdgeGrid + 1];
  auto& r = renderers[grid];
  if (!r) {
    r = std::make_unique<soltex::FrameRenderer>(
        *w.cache, soltex::RenderOptions{.threads = threads, .edge_antialias = grid});
    converge(*r, w.prepared, w.scene.camera, kWidth, kHeight, *w.source, "frame_bench");
  }
  return *r;
}

void BM_EqualPsnr(benchmark::State& state) {
  WarmScene& w = warm_scene(state);
  const soltex::Image& truth = ground_truth(w);
  const auto k = static_cast<int>(state.range(2));
  const auto grid = static_cast<int>(state.range(3));
  soltex::FrameRenderer& renderer =
      grid > 0 ? edge_renderer(w, static_cast<int>(state.range(0)), grid) : *w.renderer;
  soltex::Image image;
  std::size_t edge_pixels = 0;
  for (auto _ : state) {
    if (k == 0) {
      soltex::Frame frame = renderer.render(w.prepared, w.scene.camera, kWidth, kHeight);
      if (!frame.complete()) state.SkipWithError("warm frame missed a brick");
      image = std::move(frame.image);
      edge_pixels = frame.stats.edge_pixels;
    } else {
      image = w.renderer->render_reference(w.prepared, w.scene.camera, kWidth, kHeight, k);
    }
    benchmark::DoNotOptimize(image.rgb.data());
  }
  state.counters["psnr_8x8_db"] = soltex::psnr(image, truth);
  if (grid > 0) state.counters["edge_pixels"] = static_cast<double>(edge_pixels);
}

// Wall time per frame, with the whole process's CPU (all render threads) beside it.
void wall_and_process_cpu_ms(benchmark::internal::Benchmark* b) {
  b->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
}

BENCHMARK(BM_WarmFrame)
    ->Args({1, 0})
    ->Args({1, 5})
    ->Args({1, 6})
    ->Args({2, 0})
    ->Args({2, 1})
    ->Args({2, 2})
    ->Args({2, 3})
    ->Args({2, 4})
    ->Args({2, 5})
    ->Args({2, 6})
    ->Args({2, 7})
    ->Apply(wall_and_process_cpu_ms);
BENCHMARK(BM_WarmFrameIsotropic)->Args({2, 0})->Args({2, 3})->Apply(wall_and_process_cpu_ms);
// Each iteration is a pair of frames: its time is theirs together.
BENCHMARK(BM_SpherePair)->Args({1})->Args({2})->Apply(wall_and_process_cpu_ms);
BENCHMARK(BM_Raster)->Args({1, 0})->Args({2, 0})->Args({2, 1})->Args({1, 5})->Args({1, 6})->Apply(
    wall_and_process_cpu_ms);
BENCHMARK(BM_ColdFrame)
    ->Args({2, 0, 0})
    ->Args({2, 1, 0})
    ->Args({2, 3, 0})
    ->Args({2, 3, 1})
    ->Args({2, 3, 2})
    ->Args({2, 4, 0})
    ->Apply(wall_and_process_cpu_ms);
BENCHMARK(BM_ReferenceFrame)
    ->Args({2, 0})
    ->Args({2, 1})
    ->Args({2, 2})
    ->Apply(wall_and_process_cpu_ms);
BENCHMARK(BM_TexturePass)
    ->Args({2, 1, 0})
    ->Args({2, 1, 1})
    ->Args({2, 1, 2})
    ->Unit(benchmark::kMillisecond);  // one thread: its CPU time, steadier than wall time here
BENCHMARK(BM_EqualPsnr)
    ->Args({2, 1, 0, 0})
    ->Args({2, 1, 0, 2})
    ->Args({2, 1, 0, 3})
    ->Args({2, 1, 0, 4})
    ->Args({2, 1, 1, 0})
    ->Args({2, 1, 2, 0})
    ->Args({2, 1, 3, 0})
    ->Args({2, 1, 4, 0})
    ->Apply(wall_and_process_cpu_ms);

}  // namespace

BENCHMARK_MAIN();
