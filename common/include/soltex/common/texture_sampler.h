#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/common/brick_key.h"
#include "soltex/common/brick_layout.h"
#include "soltex/common/cached_brick.h"
#include "soltex/common/sample_split.h"
#include "soltex/common/sampling_kernels.h"
#include "soltex/common/trilinear_u8.h"

// Sampling one texture through the sparse cache cube.
//
// A texture-space point p becomes, at level l, the continuous sample coordinate
// u = (p - volume.min) / h_l, clamped to [0, cells] (NaN becomes 0, so every input gives a
// defined brick). Its cell i = floor(u), clamped to [0, cells - 1], splits into the paper's
// global and local index: brick = i >> log2(B), local = i & (B - 1), and the fraction
// u - i in [0, 1] weighs the cell's corners, which the brick stores (its (B + 1)^3 samples
// include the shared faces), so a lookup reads exactly one brick.
//
// A brick that is not resident is replaced by the nearest resident coarser level, and its
// key is reported so the caller can fetch it; the next frame refines.
namespace soltex {

enum class SampleFilter : uint8_t {
  nearest,       // the nearest sample of the nearest level
  trilinear,     // trilinear within the nearest level
  quadrilinear,  // trilinear in the two levels around the level of detail, blended by its
                 // fraction (the 3D form of trilinear MIP-mapping)
};

const char* sample_filter_name(SampleFilter filter);

// The continuous level of detail of a footprint (the texture-space size one sample should
// cover): log2(footprint / h_0), h_0 = layout.filter_width(0), clamped to
// [0, coarsest_level]. NaN and +inf give the coarsest level; zero, negative and -inf give 0.
double level_of_detail(const BrickLayout& layout, double footprint);

// The level a nearest or trilinear lookup uses for a footprint: round(level_of_detail(layout,
// footprint) + bias), clamped to [0, coarsest] as TextureSampler::sample clamps it, found by
// comparing the footprint's bits with a table instead of calling log2 per sample. The table
// holds, per level, the smallest float footprint that reaches it, found once by bisecting the
// formula above over the ordered bit patterns of non-negative floats (the formula is monotone
// in the footprint), so level(f) equals the formula for every float f, NaN included.
class NearestLevelTable {
 public:
  NearestLevelTable() = default;
  NearestLevelTable(const BrickLayout& layout, double bias);

  // The formula itself (what the table reproduces), for the table and for tests.
  static int level_by_formula(const BrickLayout& layout, double bias, float footprint);

  int level(float footprint) const {
    const uint32_t bits = std::bit_cast<uint32_t>(footprint);
    const uint32_t magnitude = bits & 0x7fffffffu;
    if (magnitude > 0x7f800000u) return nan_level_;
    if (bits != magnitude) return non_positive_level_;  // negative, -0
    // The number of thresholds at or below the bits, by halving the (ascending) table four
    // times: four compares instead of one per level.
    const auto b = static_cast<int32_t>(bits);
    const int32_t* t = thresholds_.data();
    std::size_t k = t[7] <= b ? 8 : 0;
    k += t[k + 3] <= b ? 4 : 0;
    k += t[k + 1] <= b ? 2 : 0;
    k += t[k] <= b ? 1 : 0;
    return base_level_ + static_cast<int>(k);
  }
  // level() of each of `footprints`, into `out`, all in vector lanes (nearest_levels.h): for
  // a run of pixels, where level()'s search costs the latency of four dependent loads a pixel.
  void levels(std::span<const float> footprints, int32_t* out) const;

 private:
  static constexpr int kMaxLevels = SpecLimits::kMaxFinestLevelLog2 + 1;
  // Sixteen entries for the four halvings; at most kMaxLevels - 1 of them are ever below
  // INT32_MAX, so the last one always is and the count stays below 16.
  static constexpr std::size_t kThresholds = 16;
  static_assert(kMaxLevels <= static_cast<int>(kThresholds));
  int base_level_ = 0;  // the level of footprint +0
  int nan_level_ = 0;
  int non_positive_level_ = 0;
  // thresholds_[k]: the bits of the smallest footprint at level base_level_ + k + 1, as a
  // signed integer (a positive float's bits order as they do); INT32_MAX, above the bits of
  // every non-negative float but NaN, past the coarsest level.
  std::array<int32_t, kThresholds> thresholds_{};
};

// The bricks one sample wanted and did not find: the level(s) it asked for and, when not
// even a coarser level was resident, the coarsest brick. Filled (from count 0) by each
// TextureSampler::sample call that is given one.
struct MissedBricks {
  static constexpr int kCapacity = 3;

  std::array<BrickKey, kCapacity> keys;
  int count = 0;

  std::span<const BrickKey> view() const { return {keys.data(), static_cast<std::size_t>(count)}; }
  void add(const BrickKey& key) {
    for (int i = 0; i < count; ++i) {
      if (keys[static_cast<std::size_t>(i)] == key) return;
    }
    if (count < kCapacity) keys[static_cast<std::size_t>(count++)] = key;
  }
};

struct SampleResult {
  // The first channels() values, in [0, 1], in channel order R, G, B, opacity, specular
  // (those the texture has). Zero when nothing was resident.
  std::array<float, CachedBrick::kMaxChannels> values;
  // The finest level that contributed: the level asked for, a coarser fallback, or -1 when
  // not even the coarsest level was resident.
  int level;
  // Whether every level the filter asked for was resident (nothing was missed).
  bool complete;
};

// Samples one texture through a cache. Holds a BrickCache::Accessor, so like it this is a
// per-thread object: make one per render thread and texture (construction is cheap), and
// destroy it before the cache.
class TextureSampler {
 public:
  // `channels`: the texture's ChannelSet::sample_count(). A resident brick with a different
  // channel count is treated as not resident.
  TextureSampler(BrickCache& cache, uint64_t texture, const BrickLayout& layout, int channels);

  uint64_t texture() const { return texture_; }
  const BrickLayout& layout() const { return layout_; }
  int channels() const { return channels_; }

  double level_of_detail(double footprint) const {
    return soltex::level_of_detail(layout_, footprint);
  }

  // Samples at texture-space point p at level of detail `lod` (a level index, fractional
  // for quadrilinear; clamped to [0, coarsest], NaN means coarsest). Nearest and trilinear
  // use the nearest level, round(lod). When `missed` is given, it receives the bricks that
  // were asked for and not resident.
  //
  // Inline: the common case (nearest or trilinear, brick resident and in the microcache)
  // is a few dozen instructions around the kernel, and a call per pixel would be a good
  // part of it. Everything else goes through sample_general().
  SampleResult sample(const glm::dvec3& p, double lod, SampleFilter filter,
                      MissedBricks* missed = nullptr) {
    // One named result on every path, so it is built in place in the caller's: a copy of
    // it right after the kernel's vector store would stall on store forwarding.
    SampleResult result{};
    if (filter != SampleFilter::quadrilinear && lod >= 0.0) {  // not NaN, not negative
      // lod + 0.5 >= 0.5: truncation rounds to the nearest level.
      const int level = static_cast<int>(std::min(lod, coarsest_lod_) + 0.5);
      const Location location = locate(p, level);
      if (const Current* brick = resident(level, location.brick)) {
        const glm::ivec3& c = location.cell;
        const glm::vec3& f = location.frac;
        if (filter == SampleFilter::nearest) {
          brick->data->nearest(c, f, result.values.data());
        } else if (channels_ == 3) {
          // RGB straight from the kept sample pointer with the sampler's own strides: one
          // dependent load less than going through the brick.
          trilinear_u8<3>(brick->samples + c.z * z_stride_ + c.y * y_stride_ + c.x * 3, y_stride_,
                          z_stride_, f.x, f.y, f.z, result.values.data());
        } else {
          brick->data->trilinear(c, f, result.values.data());
        }
        result.level = level;
        result.complete = true;
        if (missed != nullptr) missed->count = 0;
        return result;
      }
    }
    sample_general(p, lod, filter, missed, result);
    return result;
  }

  // sample(points[i], lod, filter) for every i into results[i], bit for bit; results.size()
  // must equal points.size() (std::invalid_argument otherwise). Missed bricks are not
  // listed: a result with complete == false names them through brick_key(). Trilinear RGB
  // runs the runtime-dispatched kernels of sampling_kernels.h, chosen once per kSampleChunk
  // points, so a generic build uses the CPU's widest vectors, and locates each chunk while
  // the one before is filtered, so batches of kSampleBatch points or more wait less on
  // memory; other filters and channel counts go point by point.
  void sample(std::span<const glm::dvec3> points, double lod, SampleFilter filter,
              std::span<SampleResult> results);

  // sample()'s nearest and trilinear fast path in two steps, for callers that look many points
  // up and prefetch in between. For a three-channel texture and a level in [0, coarsest]: the
  // address of the cell's first sample in its resident brick (bricks found in this frame stay
  // resident until the next BrickCache::begin_frame()), and the fraction; nullptr when the
  // brick is not resident, and then sample_after_miss() gives what sample() would have.
  const uint8_t* locate_rgb(const glm::dvec3& p, int level, glm::vec3& frac) {
    const Location location = locate(p, level);
    const Current* brick = resident(level, location.brick);
    if (brick == nullptr) return nullptr;
    frac = location.frac;
    const glm::ivec3& c = location.cell;
    return brick->samples + c.z * z_stride_ + c.y * y_stride_ + c.x * 3;
  }
  // The lookup of locate_rgb()'s cell: writes four floats, R, G, B and 0, as sample() gives them.
  void trilinear_rgb(const uint8_t* cell, const glm::vec3& frac, float* out) const {
    trilinear_u8<3>(cell, y_stride_, z_stride_, frac.x, frac.y, frac.z, out);
  }
  // The nearest sample of locate_rgb()'s cell: writes R, G, B as sample() gives them.
  void nearest_rgb(const uint8_t* cell, const glm::vec3& frac, float* out) const {
    const uint8_t* s = cell + (frac.x >= 0.5f ? 3 : 0) + (frac.y >= 0.5f ? y_stride_ : 0) +
                       (frac.z >= 0.5f ? z_stride_ : 0);
    for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(s[c]) * (1.0f / 255.0f);
  }
  // The strides of a cell's four sample rows from its first sample, for prefetching.
  int y_stride() const { return y_stride_; }
  int z_stride() const { return z_stride_; }
  // sample(p, level, filter, missed), filter nearest or trilinear, after locate_rgb(p, level)
  // returned nullptr, without looking the missing brick up a second time.
  SampleResult sample_after_miss(const glm::dvec3& p, int level, SampleFilter filter,
                                 MissedBricks* missed) {
    SampleResult result{};
    sample_general(p, static_cast<double>(level), filter, missed, result);
    return result;
  }

  SampleResult sample_footprint(const glm::dvec3& p, double footprint, SampleFilter filter,
                                MissedBricks* missed = nullptr) {
    return sample(p, level_of_detail(footprint), filter, missed);
  }

  // What sample(p, lod, filter, missed) would report, without reading a sample: the bricks it
  // misses into `missed`, and its result's level and completeness (the values stay zero). For
  // a frame drawn only to find what it has to fetch.
  SampleResult find_misses(const glm::dvec3& p, double lod, SampleFilter filter,
                           MissedBricks* missed);
  // The key of the brick a trilinear lookup of p at `level` reads.
  BrickKey brick_key(const glm::dvec3& p, int level) const;
  // Its brick, inline, for a level in [0, coarsest]. Points in one brick at a level are in one
  // brick at every coarser level too (the cells halve exactly), so they miss the same bricks.
  glm::ivec3 brick_of(const glm::dvec3& p, int level) const { return locate(p, level).brick; }

  // Adds this sampler's lookup counts to the cache's statistics now.
  void flush_statistics() { accessor_.flush_statistics(); }

 private:
  // A brick resident() found, kept with what its samples are read through.
  struct Current {
    glm::ivec3 brick{0};
    int level = -1;
    uint64_t generation = 0;
    const CachedBrick* data = nullptr;
    const uint8_t* samples = nullptr;  // data->sample(0, 0, 0)
  };

  // The brick resident() last failed to find at one level, with the cache's generation
  // (0: none; generations start at 1) and insertion count when it did.
  struct Missing {
    glm::ivec3 brick{0};
    uint64_t generation = 0;
    uint64_t insertions = 0;
  };

  // Where a point falls at one level: its brick, its cell inside the brick, the fraction.
  struct Location {
    glm::ivec3 brick;
    glm::ivec3 cell;
    glm::vec3 frac;
  };

  Location locate(const glm::dvec3& p, int level) const {
    const auto l = static_cast<std::size_t>(level);
    // h_l = h_0 * 2^level, so (p - min) / h_0 * 2^-level is (p - min) / h_l exactly.
    const CellSplit split = split_cell(p, min_, finest_spacing_, level_scale_[l], cells_[l]);
    const glm::ivec3& i = split.cell;
    return {{i.x >> brick_shift_, i.y >> brick_shift_, i.z >> brick_shift_},
            {i.x & brick_mask_, i.y & brick_mask_, i.z & brick_mask_},
            split.frac};
  }

  // The resident brick, or nullptr (also for a brick of the wrong shape: keys are
  // content-addressed, so that is a caller's mistake, but it must not be read out of bounds).
  const CachedBrick* find(int level, const glm::ivec3& brick) {
    const CachedBrick* found = accessor_.find(BrickKey{texture_, level, brick});
    if (found != nullptr &&
        (found->channels() != channels_ || found->brick_size() != brick_mask_ + 1)) {
      return nullptr;
    }
    return found;
  }

  // find() with the bricks found lately kept in front of it, in a small direct-mapped table
  // of this sampler's own (a page table in the small: one probe, and the entry holds the
  // sample pointer itself), and the entry used last at this level's parity checked first
  // (OpenVDB's accessors keep the last leaf the same way; two, so that quadrilinear's two
  // adjacent levels each keep theirs). An entry is valid while the cache's generation is
  // the one it was found in: no eviction since, so the brick is still resident and alive.
  const Current* resident(int level, const glm::ivec3& brick) {
    const uint64_t generation = accessor_.generation();
    const Current*& last = last_[static_cast<std::size_t>(level & 1)];
    if (holds(*last, level, brick, generation)) {
      accessor_.count_microcache_hit();
      return last;
    }
    Current& entry = remembered_[remembered_slot(level, brick)];
    if (holds(entry, level, brick, generation)) {
      accessor_.count_microcache_hit();
      last = &entry;
      return last;
    }
    // A brick found missing is still missing while nothing was inserted or evicted since: a
    // cold frame misses at nearly every pixel, over and over in the same few bricks per level.
    Missing& missing = missing_[static_cast<std::size_t>(level)];
    const uint64_t insertions = accessor_.insertions();
    if ((brick.x == missing.brick.x) & (brick.y == missing.brick.y) & (brick.z == missing.brick.z) &
        (generation == missing.generation) & (insertions == missing.insertions)) {
      accessor_.count_miss();
      return nullptr;
    }
    const CachedBrick* found = find(level, brick);
    if (found == nullptr) {
      missing = Missing{brick, generation, insertions};
      return nullptr;
    }
    entry = Current{brick, level, generation, found, found->sample(0, 0, 0)};
    last = &entry;
    return last;
  }

  // Compared with & rather than &&: no branch per field.
  static bool holds(const Current& entry, int level, const glm::ivec3& brick, uint64_t generation) {
    return (level == entry.level) & (brick.x == entry.brick.x) & (brick.y == entry.brick.y) &
           (brick.z == entry.brick.z) & (generation == entry.generation);
  }

  static constexpr int kRememberedBits = 11;  // 2,048 bricks, 80 KiB
  static std::size_t remembered_slot(int level, const glm::ivec3& brick) {
    // Brick coordinates are below 2^11 (SpecLimits) and levels below 2^4: the key is exact.
    const uint64_t key = static_cast<uint64_t>(level) << 60 |
                         static_cast<uint64_t>(static_cast<uint32_t>(brick.x)) << 40 |
                         static_cast<uint64_t>(static_cast<uint32_t>(brick.y)) << 20 |
                         static_cast<uint32_t>(brick.z);
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15u) >> (64 - kRememberedBits));
  }

  // Up to kSampleChunk trilinear RGB lookups at one level, located: each cell's split and the
  // address of its first sample in its resident brick (nullptr where the brick is not).
  struct StagedChunk {
    CellChunk cells;
    std::array<const uint8_t*, kSampleChunk> corners;
  };
  // The batch's lookups in two steps, so that one chunk's samples come from memory while the
  // chunk before is filtered: stage_rgb_chunk() locates the points, finds their bricks and
  // prefetches the samples; finish_rgb_chunk() reads them and filters into results (a point
  // whose brick is missing takes sample_general()). Bricks found stay resident for the frame,
  // so the addresses hold from one step to the next.
  void stage_rgb_chunk(std::span<const glm::dvec3> points, int level, StagedChunk& staged);
  void finish_rgb_chunk(std::span<const glm::dvec3> points, int level, const StagedChunk& staged,
                        std::span<SampleResult> results);

  void sample_general(const glm::dvec3& p, double lod, SampleFilter filter, MissedBricks* missed,
                      SampleResult& result);
  // Samples the finest resident level at or above `level`; returns it, or -1.
  int sample_level(const glm::dvec3& p, int level, bool nearest, float* out, bool& missing,
                   MissedBricks* missed);
  // The finest resident level at or above `level`, or -1, with `read(brick, location)` called
  // for it; sets `missing` and lists in `missed` what sample_level() reports.
  template <typename Read>
  int walk_levels(const glm::dvec3& p, int level, bool& missing, MissedBricks* missed, Read&& read);
  // `lod` as sample_general() reads it: NaN the coarsest level, below 0 level 0.
  double clamped_lod(double lod) const {
    if (!(lod >= 0.0)) lod = std::isnan(lod) ? coarsest_lod_ : 0.0;
    return std::min(lod, coarsest_lod_);
  }

  BrickLayout layout_;
  uint64_t texture_;
  int channels_;
  int coarsest_level_;
  double coarsest_lod_;  // coarsest_level_ as a double
  int brick_shift_;
  int brick_mask_;
  int y_stride_;  // bytes between samples along y in a brick of this texture: (B + 1) * channels
  int z_stride_;  // ... along z: (B + 1)^2 * channels
  glm::dvec3 min_;
  glm::dvec3 finest_spacing_;
  // Per level: 2^-level and cells per axis.
  std::array<double, SpecLimits::kMaxFinestLevelLog2 + 1> level_scale_;
  std::array<double, SpecLimits::kMaxFinestLevelLog2 + 1> cells_;
  BrickCache::Accessor accessor_;
  // The bricks resident() found lately (remembered_, indexed by remembered_slot()), and the
  // entries it returned last, per level parity; each valid while the cache's generation is
  // the one it was found in.
  std::vector<Current> remembered_;
  std::array<const Current*, 2> last_;
  // Per level, the brick last found missing.
  std::array<Missing, SpecLimits::kMaxFinestLevelLog2 + 1> missing_{};
};

}  // namespace soltex
