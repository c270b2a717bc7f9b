#include "soltex/render/frame_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "edge_antialiasing.h"
#include "soltex/common/check.h"
#include "soltex/common/overloaded.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/render/anisotropic_taps.h"
#include "soltex/render/eye_relative_view.h"
#include "soltex/render/shading.h"
#include "tile_shader.h"

namespace soltex {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Rows per block of the reference renderer's pass.
constexpr int kReferenceRows = 8;

bool key_less(const BrickKey& a, const BrickKey& b) {
  if (a.texture != b.texture) return a.texture < b.texture;
  if (a.level != b.level) return a.level < b.level;
  if (a.brick.z != b.brick.z) return a.brick.z < b.brick.z;
  if (a.brick.y != b.brick.y) return a.brick.y < b.brick.y;
  return a.brick.x < b.brick.x;
}

}  // namespace

const char* texture_access_name(TextureAccess access) {
  switch (access) {
    case TextureAccess::automatic:
      return "auto";
    case TextureAccess::cached:
      return "cache";
    case TextureAccess::evaluated:
      return "evaluate";
  }
  return "?";
}

// The automatic rule, one choice per pattern kind, from tests/bench/access_bench: the warm
// frame of one object evaluated per pixel over the cached one, per covered pixel (the figures
// beside each kind; docs/TEXTURES.md, "Cache or evaluate"). A fixed rule rather than a timing
// taken at run time, so that the image never depends on the machine's load. Evaluated: the
// patterns whose box filter is exact in closed form; they cost at most about 1.3 times the
// cached frame and fetch no bricks at all (no server time, bytes, cache memory or wait for the
// first picture). Cached: wood, whose grain filter leaves out the jitter's slope and which
// costs 1.6 times, and the noise patterns, whose band limit fades octaves as the cache's
// band-limited levels do, so evaluating them buys no exactness (single-octave noise 1.3 times,
// turbulence and marble 2.4 and 2.7). Cached too: graphs, whose cost per sample is open-ended.
bool evaluated_per_pixel(const TextureSpec& texture, TextureAccess access) {
  if (access != TextureAccess::automatic) return access == TextureAccess::evaluated;
  if (texture.graph) return false;
  return std::visit(Overloaded{
                        [](const StripesParams&) { return true; },      // 0.94
                        [](const CheckerParams&) { return true; },      // 2D 1.12, 3D 1.29
                        [](const RingsParams&) { return true; },        // 1.31
                        [](const ColourCubeParams&) { return true; },   // 1.13
                        [](const WoodParams&) { return false; },        // 1.58
                        [](const NoiseParams&) { return false; },       // 1.29
                        [](const TurbulenceParams&) { return false; },  // 2.35
                        [](const MarbleParams&) { return false; },      // 2.66
                    },
                    texture.pattern);
}

glm::dmat4 view_projection(const Camera& camera, int width, int height) {
  const double aspect = static_cast<double>(width) / static_cast<double>(std::max(height, 1));
  const glm::dmat4 projection =
      glm::perspective(glm::radians(camera.fov_y_degrees), aspect, camera.near, camera.far);
  return projection * glm::lookAt(camera.position, camera.target, camera.up);
}

FrameRenderer::FrameRenderer(BrickCache& cache, RenderOptions options)
    : cache_(cache), options_(options), rasterizer_(RasterOptions{options.threads, false}) {
  if (options.edge_antialias < 0 || options.edge_antialias > kMaxEdgeGrid) {
    throw std::invalid_argument("RenderOptions::edge_antialias must be 0 (off) to " +
                                std::to_string(kMaxEdgeGrid) + ", got " +
                                std::to_string(options.edge_antialias));
  }
  if (options.anisotropy < 1 || options.anisotropy > render::kMaxTaps) {
    throw std::invalid_argument("RenderOptions::anisotropy must be 1 (one lookup per pixel) to " +
                                std::to_string(render::kMaxTaps) + ", got " +
                                std::to_string(options.anisotropy));
  }
}

void FrameRenderer::prepare_readers(const PreparedScene& scene) {
  const auto threads = static_cast<std::size_t>(rasterizer_.thread_count());
  std::vector<uint64_t> texture_ids;
  for (const PreparedObject& o : scene.objects) texture_ids.push_back(o.texture_id);
  if (samplers_.size() == threads && sampler_textures_ == texture_ids) return;
  samplers_.clear();
  samplers_.resize(threads);
  for (auto& worker_samplers : samplers_) {
    for (const PreparedObject& o : scene.objects) {
      worker_samplers.push_back(
          std::make_unique<TextureSampler>(cache_, o.texture_id, o.layout, o.channels));
    }
  }
  evaluators_.clear();
  for (const PreparedObject& o : scene.objects) {
    evaluators_.push_back(std::make_unique<TextureEvaluator>(o.texture));
  }
  sampler_textures_ = std::move(texture_ids);
}

std::vector<std::unique_ptr<render::TileShader>> FrameRenderer::tile_shaders(
    const render::FrameShading& shading) {
  std::vector<std::unique_ptr<render::TileShader>> shaders;
  for (auto& worker_samplers : samplers_) {
    shaders.push_back(std::make_unique<render::TileShader>(shading, worker_samplers));
  }
  return shaders;
}

render::FrameShading FrameRenderer::frame_shading(const PreparedScene& scene,
                                                  const render::SurfaceUnprojection& unprojection,
                                                  const RenderOptions& options) const {
  render::FrameShading shading{{}, prepare_lights(*scene.scene), unprojection, options};
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const PreparedObject& o = scene.objects[i];
    SOLTEX_DCHECK(o.raster.object_id == i);
    shading.unprojection.add_object(o.world_from_object, o.raster.texture_from_object);
    render::ObjectShading object;
    object.material = render::material_inputs(o);
    object.surface = render::TextureSurface(o);
    if (o.evaluated_here || evaluated_per_pixel(o.texture, options.access)) {
      object.evaluator = evaluators_[i].get();
    }
    if (shading.by_table()) object.level_table = NearestLevelTable(o.layout, options.level_bias);
    object.level0_spacing = o.layout.filter_width(0);
    object.cached_inset = render::has_planar_edges(o.texture) ? render::kCachedInset : 0.0;
    object.rgb_fast_path = shading.by_table() && !options.false_colour_levels &&
                           !options.misses_only && !object.material.unlit && o.channels == 3;
    shading.objects.push_back(object);
  }
  return shading;
}

Frame FrameRenderer::render(const PreparedScene& scene, const Camera& camera, int width,
                            int height) {
  const int k = options_.antialias;
  if (k <= 1) return render_pixels(scene, camera, width, height, options_);
  // A frame k times as wide and high, each pixel the average of its k x k sub-pixels:
  // silhouettes and clip edges get their coverage, and every sub-pixel reads its texture at
  // its own level of detail, as the supersampled reference does (about k^2 the raster and
  // shading work, and bricks one or two levels finer where the finest level allows).
  Frame frame = render_pixels(scene, camera, width * k, height * k, options_);
  frame.image = box_downsample(frame.image, k);
  return frame;
}

// A frame's one way through: each raster tile is shaded by the thread that rasterized it, right
// after, while its G-buffer is still in that core's cache (a tile no triangle reached comes as
// the shared empty buffer), in square pieces whose pixels read few bricks; then the threads'
// misses and counts are gathered.
Frame FrameRenderer::render_pixels(const PreparedScene& scene, const Camera& camera, int width,
                                   int height, const RenderOptions& options) {
  Frame frame;
  frame.image = Image(width, height);
  const auto start = Clock::now();
  const EyeRelativeView relative = eye_relative_view(scene, camera, width, height, true);
  const glm::dmat4& vp = relative.view_projection;
  const RasterView view{width, height, glm::mat4(vp), relative.clip_planes,
                        options.edge_antialias > 0};
  cache_.begin_frame();
  prepare_readers(scene);
  const render::FrameShading shading = frame_shading(
      scene, render::SurfaceUnprojection{glm::inverse(vp), camera.position, width, height},
      options);
  std::vector<std::unique_ptr<render::TileShader>> shaders = tile_shaders(shading);
  reported_.assign(on_tile_misses_ ? shaders.size() : 0, {});
  render::EdgeAntialiasing* edges = nullptr;
  if (options.edge_antialias > 0) {
    if (!edges_) edges_ = std::make_shared<render::EdgeAntialiasing>();
    edges = edges_.get();
    edges->begin_frame(width, height, relative.near, camera.far, options.edge_antialias,
                       rasterizer_.thread_count());
  }
  const auto shade_raster_tile = [&](const GBuffer& g, int origin_x, int origin_y, int x0, int y0,
                                     int x1, int y1, int worker_index) {
    render::TileShader& shader = *shaders[static_cast<std::size_t>(worker_index)];
    const auto shade_start = Clock::now();
    constexpr int kTile = render::TileShader::kTile;
    for (int ty = y0; ty < y1; ty += kTile) {
      for (int tx = x0; tx < x1; tx += kTile) {
        shader.shade(g, origin_x, origin_y, tx, ty, std::min(x1, tx + kTile),
                     std::min(y1, ty + kTile), frame.image);
      }
    }
    if (edges != nullptr) {
      edges->antialias_tile(rasterizer_, shader, g, origin_x, origin_y, x0, y0, x1, y1,
                            worker_index, frame.image);
    }
    if (on_tile_misses_) report_tile_misses(shader, worker_index);
    shader.counts().shading += Clock::now() - shade_start;
  };
  if (options.keep_gbuffer) {
    frame.stats.raster = rasterizer_.render(
        view, relative.objects, gbuffer_, [&](int x0, int y0, int x1, int y1, int worker_index) {
          shade_raster_tile(gbuffer_, 0, 0, x0, y0, x1, y1, worker_index);
        });
  } else {
    frame.stats.raster = rasterizer_.render_tiles(
        view, relative.objects,
        [&](const GBuffer& tile, int x0, int y0, int x1, int y1, int worker_index) {
          shade_raster_tile(tile, x0, y0, x0, y0, x1, y1, worker_index);
        });
  }
  if (edges != nullptr) frame.stats.edge_pixels = edges->blended();
  gather(shaders, frame);
  for (const render::ObjectShading& object : shading.objects) {
    ++(object.evaluator != nullptr ? frame.stats.evaluated_objects : frame.stats.cached_objects);
  }
  // One pass does both: split its wall time by the share of render-thread time spent shading
  // (an estimate; the threads are busy throughout the pass).
  Clock::duration shading_time{0};
  for (const auto& shader : shaders) shading_time += shader->counts().shading;
  const double total_ms = ms_since(start);
  const double shading_ms = std::chrono::duration<double, std::milli>(shading_time).count() /
                            static_cast<double>(shaders.size());
  frame.stats.shade_ms = std::min(total_ms, shading_ms);
  frame.stats.raster_ms = total_ms - frame.stats.shade_ms;
  return frame;
}

void FrameRenderer::gather(std::vector<std::unique_ptr<render::TileShader>>& shaders,
                           Frame& frame) {
  for (auto& worker_samplers : samplers_) {
    for (auto& sampler : worker_samplers) sampler->flush_statistics();
  }
  std::unordered_map<BrickKey, uint32_t, BrickKeyHash> misses;
  for (auto& reported : reported_) {
    for (const auto& [key, pixels] : reported) misses[key] += pixels;
  }
  reported_.clear();
  for (auto& shader : shaders) {
    shader->misses().drain([&](const BrickKey& key, uint32_t pixels) { misses[key] += pixels; });
    const render::TileCounts& counts = shader->counts();
    frame.stats.covered_pixels += counts.covered;
    frame.stats.fallback_pixels += counts.fallback;
    frame.stats.empty_pixels += counts.empty;
    frame.stats.shaded_pixels += counts.shaded;
    frame.stats.evaluated_pixels += counts.evaluated;
    frame.stats.tapped_pixels += counts.tapped;
    frame.stats.taps += counts.taps;
  }
  frame.misses.reserve(misses.size());
  for (const auto& [key, pixels] : misses) frame.misses.push_back({key, pixels});
  // Which thread drew which tile varies from frame to frame; the list does not.
  std::sort(
      frame.misses.begin(), frame.misses.end(),
      [](const net::BrickWant& a, const net::BrickWant& b) { return key_less(a.key, b.key); });
}

void FrameRenderer::report_tile_misses(render::TileShader& shader, int worker_index) {
  auto& reported = reported_[static_cast<std::size_t>(worker_index)];
  std::vector<net::BrickWant> fresh;
  shader.misses().drain([&](const BrickKey& key, uint32_t pixels) {
    const auto [it, first] = reported.try_emplace(key, 0u);
    it->second += pixels;
    if (first) fresh.push_back({key, pixels});
  });
  if (!fresh.empty()) on_tile_misses_(std::move(fresh));
}

// Every pixel evaluated over its footprint, as TileShader does for evaluated textures, at k x k
// sub-pixels, averaged.
Image FrameRenderer::render_reference(const PreparedScene& scene, const Camera& camera, int width,
                                      int height, int supersample) {
  const int k = std::clamp(supersample, 1, 8);
  const int w = width * k, h = height * k;
  const EyeRelativeView relative = eye_relative_view(scene, camera, w, h, false);
  const glm::dmat4& vp = relative.view_projection;
  const RasterView view{w, h, glm::mat4(vp), relative.clip_planes};
  GBuffer& g = reference_gbuffer_;
  rasterizer_.render(view, relative.objects, g);
  prepare_readers(scene);
  RenderOptions evaluated = options_;
  evaluated.access = TextureAccess::evaluated;
  evaluated.false_colour_levels = false;
  // The ground truth stays what it was: each sub-pixel evaluated over its own footprint.
  evaluated.anisotropy = 1;
  const render::FrameShading shading = frame_shading(
      scene, render::SurfaceUnprojection{glm::inverse(vp), camera.position, w, h}, evaluated);
  Image& sub_pixels = reference_image_;
  sub_pixels = Image(w, h);
  const int row_blocks = (h + kReferenceRows - 1) / kReferenceRows;
  std::vector<std::unique_ptr<render::TileShader>> shaders = tile_shaders(shading);
  rasterizer_.parallel_for(static_cast<std::size_t>(row_blocks), [&](std::size_t block,
                                                                     int worker_index) {
    render::TileShader& shader = *shaders[static_cast<std::size_t>(worker_index)];
    const int first = static_cast<int>(block) * kReferenceRows;
    const int end = std::min(h, first + kReferenceRows);
    for (int x = 0; x < w; x += render::TileShader::kTile) {
      shader.shade(g, 0, 0, x, first, std::min(w, x + render::TileShader::kTile), end, sub_pixels);
    }
  });
  Image image = box_downsample(sub_pixels, k);
  if (k > 1) {
    // Kept only at 1x: a supersampled reference is k^2 frames of memory, and a one-off.
    reference_gbuffer_ = GBuffer{};
    reference_image_ = Image{};
  }
  return image;
}

}  // namespace soltex
