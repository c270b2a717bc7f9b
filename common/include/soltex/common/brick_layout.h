#pragma once

#include <cstdint>
#include <glm/vec3.hpp>

#include "soltex/common/brick_key.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/common/texture_spec.h"

// Levels and bricks of a cache cube (the paper's sparse cache cube).
//
// The volume is sampled at 2^L cells per axis at level 0; level l has 2^(L - l) cells per axis
// and spacing h_l = h_0 * 2^l. Samples are vertex-centred: sample index i at level l sits at
// volume.min + i * h_l, for i in [0, 2^(L - l)]. A brick holds B^3 cells and stores their
// (B + 1)^3 corner samples, so the faces it shares with its neighbours are stored in both and
// trilinear filtering never leaves a brick. The coarsest level is a single brick.
//
// The global/local split of a sample index: brick = i >> log2(B), local = i & (B - 1).
namespace soltex {

inline constexpr int kMinBrickSize = 8;
inline constexpr int kMaxBrickSize = 16;

class BrickLayout {
 public:
  // Throws SpecError when brick_size is not 8 or 16, or when the volume has fewer than
  // brick_size cells per axis at level 0.
  BrickLayout(const Volume& volume, int brick_size);

  const Volume& volume() const { return volume_; }
  int brick_size() const { return brick_size_; }
  int brick_shift() const { return brick_shift_; }
  int samples_per_axis() const { return brick_size_ + 1; }
  int samples_per_brick() const {
    return samples_per_axis() * samples_per_axis() * samples_per_axis();
  }

  int finest_level_log2() const { return volume_.finest_level_log2; }
  int coarsest_level() const { return volume_.finest_level_log2 - brick_shift_; }
  int level_count() const { return coarsest_level() + 1; }
  int cells_per_axis(int level) const { return 1 << (volume_.finest_level_log2 - level); }
  int bricks_per_axis(int level) const { return cells_per_axis(level) >> brick_shift_; }
  uint64_t brick_count(int level) const {
    const auto n = static_cast<uint64_t>(bricks_per_axis(level));
    return n * n * n;
  }

  // Sample spacing per axis at `level` (h_0 * 2^level, exact).
  glm::dvec3 spacing(int level) const;
  // The filter width a level is band-limited to: its largest spacing.
  double filter_width(int level) const;

  bool contains(int level, const glm::ivec3& brick) const;

  // The (B + 1)^3 sample points of one brick, as global lattice indices of its level.
  Grid sample_grid(int level, const glm::ivec3& brick) const;

  // Continuous sample coordinate of texture-space point p at `level`: (p - min) / h_l.
  glm::dvec3 sample_coordinate(const glm::dvec3& p, int level) const;

 private:
  Volume volume_;
  int brick_size_;
  int brick_shift_;
  glm::dvec3 finest_spacing_;
};

}  // namespace soltex
