#pragma once

#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>

#include "soltex/common/brick_cache.h"
#include "soltex/common/brick_key.h"
#include "soltex/common/brick_layout.h"
#include "soltex/common/cached_brick.h"

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
  SampleResult sample(const glm::dvec3& p, double lod, SampleFilter filter,
                      MissedBricks* missed = nullptr);

  SampleResult sample_footprint(const glm::dvec3& p, double footprint, SampleFilter filter,
                                MissedBricks* missed = nullptr) {
    return sample(p, level_of_detail(footprint), filter, missed);
  }

  // The key of the brick a trilinear lookup of p at `level` reads.
  BrickKey brick_key(const glm::dvec3& p, int level) const;

  // Adds this sampler's lookup counts to the cache's statistics now.
  void flush_statistics() { accessor_.flush_statistics(); }

 private:
  // Where a point falls at one level: its brick, its cell inside the brick, the fraction.
  struct Location {
    glm::ivec3 brick;
    glm::ivec3 cell;
    glm::vec3 frac;
  };

  Location locate(const glm::dvec3& u0, int level) const;
  // Samples the finest resident level at or above `level`; returns it, or -1.
  int sample_level(const glm::dvec3& u0, int level, bool nearest, float* out, bool& missing,
                   MissedBricks* missed);

  BrickLayout layout_;
  uint64_t texture_;
  int channels_;
  int coarsest_level_;
  int brick_shift_;
  int brick_mask_;
  glm::dvec3 min_;
  glm::dvec3 finest_spacing_;
  // Per level: 2^-level (u at level l is u at level 0 times it, exactly) and cells per axis.
  std::array<double, SpecLimits::kMaxFinestLevelLog2 + 1> level_scale_;
  std::array<double, SpecLimits::kMaxFinestLevelLog2 + 1> cells_;
  BrickCache::Accessor accessor_;
};

}  // namespace soltex
