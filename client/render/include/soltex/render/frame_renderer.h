#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <unordered_map>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/common/texture_sampler.h"
#include "soltex/net/brick_source.h"
#include "soltex/raster/gbuffer.h"
#include "soltex/raster/raster_stats.h"
#include "soltex/raster/rasterizer.h"
#include "soltex/render/image.h"
#include "soltex/render/prepared_scene.h"

namespace soltex {
namespace render {
struct FrameShading;
struct SurfaceUnprojection;
class TileShader;
class EdgeAntialiasing;
}  // namespace render
class TextureEvaluator;

// How a texture is read per pixel.
enum class TextureAccess : uint8_t {
  automatic,  // evaluated where that is exact and cheaper than a cached lookup, else cached
  cached,     // through the brick cache, at the level the footprint asks for
  evaluated,  // evaluated per pixel, band-limited and box-filtered over the footprint
};

const char* texture_access_name(TextureAccess access);

// Whether `access` evaluates `texture` per pixel (and so fetches no brick for it). Automatic
// evaluates the analytic patterns whose filtered form is exact and which cost at most about 1.3
// times a cached lookup per pixel: stripes, checkers, rings and the colour cube; a rule per
// pattern kind, measured by tests/bench/access_bench (docs/TEXTURES.md, "Cache or evaluate").
bool evaluated_per_pixel(const TextureSpec& texture, TextureAccess access);

struct RenderOptions {
  TextureAccess access = TextureAccess::automatic;
  SampleFilter filter = SampleFilter::trilinear;
  double level_bias = 0.0;           // added to every pixel's level of detail (negative: finer)
  bool false_colour_levels = false;  // show the level each pixel drew from instead of shading
  // Find the bricks the frame misses and draw nothing else (the image is not a picture and may
  // hold anything): a client's first frame, drawn only to learn what to fetch. Frame::misses
  // and the pixel counts are those the shaded frame would give.
  bool misses_only = false;
  int threads = 0;  // 0: one per core
  // Anisotropic lookups: at most this many taps along a footprint's long side, each at the
  // level its share of the side asks for, or for a texture evaluated per pixel over its share
  // (soltex/render/anisotropic_taps.h); 1: one lookup or evaluation over the long side
  // (isotropic). The reference (render_reference) keeps one evaluation per sub-pixel.
  int anisotropy = 8;
  // Sub-pixels per axis (1..4) whose colours each pixel averages: silhouettes, clip edges and
  // textures anti-aliased by supersampling, each sub-pixel textured at its own level, at about
  // antialias^2 times the frame's raster and shading work.
  int antialias = 1;
  // Edge anti-aliasing: 0 off, else N (2..8): the pixels beside a change of surface or a
  // break in depth (silhouettes, object and clip edges; a few percent of the covered pixels)
  // get N x N coverage samples, each surface they see is shaded once, and the pixel is their
  // coverage-weighted average. Everything else is shaded once, as without it.
  int edge_antialias = 0;
  // Keep the whole frame's G-buffer for last_gbuffer() (tests, tools). Off, each tile is
  // shaded from a tile-sized G-buffer as soon as it is rasterized, and no frame-sized one is
  // written, read back, or (on the first frame) faulted in.
  bool keep_gbuffer = false;
};

struct FrameStats {
  // Tiles are shaded as soon as they are rasterized, in one pass: its wall time (plus the
  // frame's set-up) is split between these two by the share of render-thread time spent
  // shading, so raster_ms + shade_ms is the frame's wall time.
  double raster_ms = 0.0;
  double shade_ms = 0.0;
  std::size_t covered_pixels = 0;
  std::size_t fallback_pixels = 0;   // drawn from a coarser level than they asked for
  std::size_t empty_pixels = 0;      // nothing resident at all yet
  std::size_t shaded_pixels = 0;     // lit (not unlit materials)
  std::size_t evaluated_pixels = 0;  // textures evaluated per pixel, not looked up
  std::size_t edge_pixels = 0;       // blended from coverage samples (edge_antialias)
  // Pixels whose footprint took several taps (RenderOptions::anisotropy), cached or evaluated,
  // and those taps in all.
  std::size_t tapped_pixels = 0;
  std::size_t taps = 0;
  // Objects whose texture this frame evaluated per pixel (and fetched no bricks for), and
  // objects whose texture it looked up in the brick cache (RenderOptions::access).
  std::size_t evaluated_objects = 0;
  std::size_t cached_objects = 0;
  RasterStats raster;
};

struct Frame {
  Image image;
  std::vector<net::BrickWant> misses;  // distinct keys, with the pixels that wanted each
  FrameStats stats;
  bool complete() const { return misses.empty(); }
};

// Draws a prepared scene from what the cache holds: rasterize into a G-buffer, and per pixel
// (each tile right after it is rasterized) look the texture up at the level its footprint asks
// for (a coarser resident level when that one is missing), and shade (Lambert + Blinn-Phong,
// the texture as albedo). Reports the
// bricks it missed so the caller can fetch them; the next frame refines.
class FrameRenderer {
 public:
  FrameRenderer(BrickCache& cache, RenderOptions options);

  Frame render(const PreparedScene& scene, const Camera& camera, int width, int height);

  // The same frame with every texture evaluated per pixel (band-limited and box-filtered over
  // the footprint, as TextureAccess::evaluated does, and averaged over supersample^2 sub-pixels
  // when supersample > 1): the reference the cached path is compared with.
  Image render_reference(const PreparedScene& scene, const Camera& camera, int width, int height,
                         int supersample = 1);

  const RenderOptions& options() const { return options_; }
  // The G-buffer of the last render() (eye-relative world space), for tests and tools; empty
  // unless RenderOptions::keep_gbuffer.
  const GBuffer& last_gbuffer() const { return gbuffer_; }
  void set_level_bias(double bias) { options_.level_bias = bias; }
  void set_false_colour_levels(bool on) { options_.false_colour_levels = on; }
  void set_misses_only(bool on) { options_.misses_only = on; }
  // Called while a frame is drawn, on the render thread that shaded a raster tile, with the
  // keys that tile missed and its thread had not missed before in this frame (each with the
  // pixels that wanted it so far): a client can ask for them before the frame ends. The
  // frame's misses are the same with or without it. Null (the default): not called.
  using TileMisses = std::function<void(std::vector<net::BrickWant>)>;
  void set_on_tile_misses(TileMisses on_tile_misses) {
    on_tile_misses_ = std::move(on_tile_misses);
  }

 private:
  // Samplers (per render thread and object) and evaluators (per object), kept across frames
  // while the scene's textures stay the same.
  void prepare_readers(const PreparedScene& scene);
  render::FrameShading frame_shading(const PreparedScene& scene,
                                     const render::SurfaceUnprojection& unprojection,
                                     const RenderOptions& options) const;
  // One tile shader per render thread, over that thread's samplers.
  std::vector<std::unique_ptr<render::TileShader>> tile_shaders(
      const render::FrameShading& shading);
  Frame render_pixels(const PreparedScene& scene, const Camera& camera, int width, int height,
                      const RenderOptions& options);
  void gather(std::vector<std::unique_ptr<render::TileShader>>& shaders, Frame& frame);
  // Moves the misses `shader` has tallied into its thread's reported_ and hands the keys new
  // to that thread to on_tile_misses_.
  void report_tile_misses(render::TileShader& shader, int worker_index);

  BrickCache& cache_;
  RenderOptions options_;
  Rasterizer rasterizer_;
  GBuffer gbuffer_;
  // render_reference()'s buffers, kept (at 1x) so that repeated references (benchmarks,
  // comparisons) measure the per-pixel evaluation and not the page faults of fresh buffers.
  GBuffer reference_gbuffer_;
  Image reference_image_;
  std::vector<std::vector<std::unique_ptr<TextureSampler>>> samplers_;  // [thread][object]
  std::vector<std::unique_ptr<TextureEvaluator>> evaluators_;           // [object]
  std::vector<uint64_t> sampler_textures_;           // the textures samplers_ was made for
  std::shared_ptr<render::EdgeAntialiasing> edges_;  // made on the first edge-anti-aliased frame
  TileMisses on_tile_misses_;
  // Per render thread, the misses already handed to on_tile_misses_ in this frame.
  std::vector<std::unordered_map<BrickKey, uint32_t, BrickKeyHash>> reported_;
};

// Camera matrices shared by the renderer and tools.
glm::dmat4 view_projection(const Camera& camera, int width, int height);

}  // namespace soltex
