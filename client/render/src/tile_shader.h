#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <glm/vec2.hpp>
#include <memory>
#include <span>
#include <vector>

#include "evaluated_inputs.h"
#include "lit_pixels.h"
#include "material_inputs.h"
#include "miss_tally.h"
#include "soltex/common/sampling_kernels.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/common/texture_sampler.h"
#include "soltex/raster/gbuffer.h"
#include "soltex/render/anisotropic_taps.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/image.h"
#include "texture_surface.h"

namespace soltex::render {

// How one object's texture is read in a frame, and how its values light the surface.
struct ObjectShading {
  MaterialInputs material;
  TextureSurface surface;
  // Set: the texture is evaluated per pixel over the pixel's footprint (TextureAccess::
  // evaluated), and no brick is read or asked for.
  const TextureEvaluator* evaluator = nullptr;
  NearestLevelTable level_table;  // for nearest and trilinear lookups
  double level0_spacing = 0.0;    // h_0, for the inward step of cached lookups
  double cached_inset = 0.0;      // in level spacings: kCachedInset for planar edges, else 0
  // Lit, three channels, a tabled level: the fast path (TextureSampler::locate_rgb()).
  bool rgb_fast_path = false;
};

// What every tile of one frame shares, read-only.
struct FrameShading {
  std::vector<ObjectShading> objects;
  PreparedLights lights;
  SurfaceUnprojection unprojection;
  RenderOptions options;

  // Nearest and trilinear take their level from a table; quadrilinear needs the fraction and
  // keeps the continuous level of detail.
  bool by_table() const { return options.filter != SampleFilter::quadrilinear; }
};

struct TileCounts {
  std::size_t covered = 0, fallback = 0, empty = 0, shaded = 0, evaluated = 0;
  std::size_t tapped = 0, taps = 0;  // pixels that took several taps, and their taps
  std::chrono::steady_clock::duration shading{0};
};

// Shades tiles of a frame on one render thread: per covered pixel, read the texture (a
// cached lookup at the footprint's level, or an evaluation over the footprint), light it (a
// shade() tile in scan order once its lookups are done), and write the image. Keeps the thread's
// samplers (and their microcaches) and tallies the bricks its pixels missed.
class TileShader {
 public:
  // `samplers`: one per object, made for this thread.
  TileShader(const FrameShading& frame, std::vector<std::unique_ptr<TextureSampler>>& samplers)
      : frame_(frame), samplers_(samplers) {}

  // Shades the frame's pixels [x0, x1) x [y0, y1) (at most kTile wide) from `g`, which holds
  // pixel (x, y) at g.index(x - origin_x, y - origin_y), into `image`.
  void shade(const GBuffer& g, int origin_x, int origin_y, int x0, int y0, int x1, int y1,
             Image& image);

  // The same for the listed pixels alone (frame positions, any order), each covered in `g`;
  // no other pixel of `image` is written.
  void shade_pixels(const GBuffer& g, int origin_x, int origin_y,
                    std::span<const glm::ivec2> pixels, Image& image);

  MissTally& misses() { return misses_; }
  const TileCounts& counts() const { return counts_; }
  TileCounts& counts() { return counts_; }

  static constexpr int kTile = LitTile::kSide;

 private:
  // Passed by value: 16 bytes travel in two registers, where a reference made the callee
  // reload it from the caller's stack.
  struct Pixel {
    int x, y;
    std::size_t index;  // in the G-buffer
  };
  // Evaluated pixels wait here (one object at a time) and are evaluated together: the pattern
  // is dispatched once per batch, not per pixel.
  struct EvaluatedPixels {
    static constexpr std::size_t kCapacity = EvaluatedLanes::kCapacity;
    std::size_t count = 0;
    const ObjectShading* object = nullptr;
    std::array<Pixel, kCapacity> pixels;
    // A pixel's taps come one after another: the first holds their count, the others 0.
    std::array<uint8_t, kCapacity> taps;
    EvaluatedLanes lanes;  // the G-buffer's inputs, and the points and boxes made of them
    std::array<Texel, kCapacity> texels;
  };
  // Cached pixels of one object on the fast path wait here, grouped by level, and each
  // level's group is looked up together through TextureSampler's batch call: its kernels are
  // dispatched once per chunk rather than the cell split and read run once per pixel, and a
  // group of several chunks has each chunk's samples fetched while the one before is filtered.
  struct CachedPixels {
    static constexpr std::size_t kCapacity = kSampleBatch;
    static constexpr std::size_t kLevels = SpecLimits::kMaxFinestLevelLog2 + 1;
    struct Group {
      std::size_t count = 0;
      std::array<uint32_t, kCapacity> slots;  // each pixel's slot_of()
      std::array<glm::dvec3, kCapacity> points;

      // Adds a pixel at `at`, the group's count as the caller holds it (a store to the group
      // may alias `count`, which would then be read back from memory), and moves `at` on;
      // returns whether that filled the group, which is then due for look_up().
      bool push(std::size_t& at, uint32_t slot, const glm::dvec3& p) {
        slots[at] = slot;
        points[at] = p;
        return ++at == kCapacity;
      }
    };
    const ObjectShading* object = nullptr;
    TextureSampler* sampler = nullptr;
    uint32_t pending = 0;  // bit l: groups[l] holds pixels
    std::array<Group, kLevels> groups;
    std::array<SampleResult, kCapacity> results;
  };
  void shade_evaluated(const GBuffer& g, Pixel pixel, const ObjectShading& object, Image& image);
  // The cached pixels that follow are `object`'s: those of another object are looked up first.
  void use_cached_object(const ObjectShading& object, TextureSampler& sampler, Image& image);
  void add_cached(Pixel pixel, const glm::dvec3& p, int level, const ObjectShading& object,
                  TextureSampler& sampler, Image& image);
  // A row's pixels as the fast path takes them: each one's taps (1: a single lookup) and the
  // level it is looked up at (its taps' level where it takes several).
  struct RowLevels {
    const int32_t* levels;
    const uint8_t* taps;
  };
  struct RowLevelArrays {
    std::array<int32_t, static_cast<std::size_t>(kTile)> levels;
    std::array<uint8_t, static_cast<std::size_t>(kTile)> taps;
    RowLevels from(std::size_t k) const { return {&levels[k], &taps[k]}; }
  };
  // Pixels [row, row + count) of `g`, all in `object`'s fast path or not read.
  void make_row_levels(const GBuffer& g, std::size_t row, std::size_t count,
                       const ObjectShading& object, RowLevelArrays& out) const;
  void add_cached_run(const GBuffer& g, int x_begin, int x_end, int y, std::size_t first,
                      const RowLevels& row, const ObjectShading& object, TextureSampler& sampler,
                      Image& image);
  // A pixel of shade()'s fast path whose footprint asks for n > 1 taps: each tap goes to the
  // group of their level with the pixel's slot marked kTapSlot, look_up() adds its value into
  // taps_, and finish_taps() writes each such pixel's average once every lookup is done.
  void add_taps(const GBuffer& g, std::size_t i, uint32_t slot, int n, int level, Image& image);
  void finish_taps();
  void look_up(int level, Image& image);
  void look_up_all(Image& image);
  void evaluate(Image& image);
  void shade_cached(const GBuffer& g, Pixel pixel, const ObjectShading& object,
                    TextureSampler& sampler, Image& image);
  // The n > 1 taps of a pixel at `p` whose footprint's long side is `axis`, each looked up on
  // its own at `lod` (in a misses-only frame, its misses found): their average, whether any
  // missed a brick and whether any found one, the coarsest level drawn. Their misses are
  // tallied.
  struct TapsResult {
    std::array<float, CachedBrick::kMaxChannels> average;
    bool incomplete = false, found = false;
    int coarsest = -1;
  };
  TapsResult look_up_taps(const glm::vec3& axis, const glm::dvec3& p, int n, double lod,
                          TextureSampler& sampler);
  // The taps pixel i takes (1 with anisotropy 1).
  int tap_count_at(const GBuffer& g, std::size_t i) const;
  // Where pixel i looks `object` up at level of detail `lod`: its texture position, stepped
  // inside across a planar pattern's face (cached_inset) by the coarser level's spacing.
  glm::dvec3 lookup_point(const GBuffer& g, std::size_t i, const ObjectShading& object,
                          double lod) const;
  // Pixel i's n > 1 taps, at the level of their share of its footprint: look_up_taps(), and the
  // pixel counted once in the fallback and empty counts.
  TapsResult tapped_lookup(const GBuffer& g, std::size_t i, int n, const ObjectShading& object,
                           TextureSampler& sampler);
  // The level of detail of a lookup whose footprint is `footprint`, as the frame takes it.
  double lod_of(const ObjectShading& object, const TextureSampler& sampler, float footprint) const;
  // Tallies the bricks the lookup that gave `result` missed (in missed_) and its counts, for
  // `pixels` pixels that miss the same.
  void count_lookup(const SampleResult& result, uint32_t pixels = 1);
  // A misses-only frame's run of `count` pixels of `object` from G-buffer index `first`, each
  // pixel's taps and level in `row`: what each would miss, looked up once for each stretch of
  // pixels in one brick (they miss the same bricks).
  void find_run_misses(const GBuffer& g, std::size_t first, std::size_t count, const RowLevels& row,
                       const ObjectShading& object, TextureSampler& sampler);
  void shade_values(Pixel pixel, const MaterialInputs& m, const float* values, Image& image);
  void flush(Image& image);

  const FrameShading& frame_;
  std::vector<std::unique_ptr<TextureSampler>>& samplers_;
  MissTally misses_;
  // The last lookup's misses, refilled by each (kept: not zeroed per pixel); a misses-only
  // run reads them again for the pixels and taps that reuse that lookup.
  MissedBricks missed_;
  TileCounts counts_;
  // Where a cached pixel's colour goes, kept in its group: its place in tile_ (shade()), or
  // its index in the list (shade_pixels(), which sets list_at_ to each pixel's in turn).
  uint32_t slot_of(Pixel pixel) const {
    return by_tile_ ? static_cast<uint32_t>(tile_.slot(pixel.x, pixel.y)) : list_at_;
  }

  const GBuffer* gbuffer_ = nullptr;  // the tile being shaded
  std::span<const glm::ivec2> list_;  // shade_pixels()'s pixels, with their G-buffer's origin
  int list_origin_x_ = 0, list_origin_y_ = 0;
  uint32_t list_at_ = 0;
  // Set while shade() takes a tile: lit pixels go to tile_ and are lit in scan order at its
  // end; shade_pixels()'s pixels, in any order, go through the batch lit_ by index.
  bool by_tile_ = false;
  LitTile tile_;               // about 25 KB
  LitPixels lit_;              // about 40 KB, uninitialised but for the count
  EvaluatedPixels evaluated_;  // about 10 KB, likewise
  CachedPixels cached_;        // about 40 KB, likewise
  // The fast path's pixels that take several taps, by slot: the sum of their taps' values, the
  // weight of one tap, and whether any tap missed or found something.
  static constexpr uint32_t kTapSlot = 1u << 31;
  struct TappedPixels {
    std::array<glm::vec3, LitTile::kPixels> sum;
    std::array<float, LitTile::kPixels> weight;
    std::array<uint8_t, LitTile::kPixels> incomplete, found;
    std::vector<uint32_t> slots;  // those taken in this tile, in order
  };
  TappedPixels taps_;  // about 22 KB, uninitialised but for the slots taken
  static_assert(kMaxTaps <= static_cast<int>(EvaluatedPixels::kCapacity) &&
                    kMaxTaps <= static_cast<int>(CachedPixels::kCapacity) && kMaxTaps <= 255,
                "a pixel's taps fit one evaluated batch, one cached group and a uint8_t count");
  // The bricks one tapped pixel (`slot`) has reported missing: each once, however many of its
  // taps missed it, so that a brick's count of pixels stays a count of pixels.
  struct PixelMisses {
    static constexpr uint32_t kNone = ~uint32_t{0};
    uint32_t slot = kNone;
    std::vector<BrickKey> keys;
    void begin(uint32_t pixel) {
      if (pixel == slot) return;
      slot = pixel;
      keys.clear();
    }
    bool first_time(const BrickKey& key) {
      for (const BrickKey& k : keys) {
        if (k == key) return false;
      }
      keys.push_back(key);
      return true;
    }
  };
  // One for the fast path's tapped pixels (their taps looked up together, in one group), and
  // one for look_up_taps().
  PixelMisses tile_tap_misses_, pixel_tap_misses_;
  // Tallies missed_'s keys for the tapped pixel `pixel` holds, those it had not yet.
  void count_tap_misses(PixelMisses& pixel);
  // A pixel of n > 1 taps counted (tapped, taps); begin_tapped_lookups() also starts the
  // pixel's own tally of the bricks its taps miss (pixel_tap_misses_), and
  // count_tapped_result() counts it once in the fallback and empty counts.
  void count_tapped_pixel(int n);
  void begin_tapped_lookups(int n);
  void count_tapped_result(bool incomplete, bool found);
};

}  // namespace soltex::render
