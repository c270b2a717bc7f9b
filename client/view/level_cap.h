#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/common/brick_layout.h"
#include "soltex/net/brick_source.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/prepared_scene.h"

namespace soltex::view {

// A cap on how fine the bricks a client fetches are, for a scene prepared at its finest
// level. The capability choice sets where the cap starts; it keeps a slow link or a busy
// client to coarse bricks, and lifting it refines the picture to the prepared levels.
//
// A cap is a resolution, log2 samples per axis, the same for every texture: a texture
// prepared finer than the cap fetches no level finer than the one with that resolution. A
// brick asked for below the cap becomes its ancestor at the cap's level, which is the brick
// the renderer falls back to (its nearest resident coarser level), so a capped picture is the
// picture a scene prepared at the cap's resolution draws, from the same bricks a finer cap
// uses later: the coarse levels of a fine volume are the same bricks, with the same ids.
class LevelCap {
 public:
  LevelCap() = default;
  explicit LevelCap(const PreparedScene& scene);

  void add_texture(uint64_t texture, const BrickLayout& layout, int channels);

  // The finest prepared resolution over all textures (0 without textures).
  int finest_log2() const { return finest_log2_; }
  int cap_log2() const { return cap_log2_; }
  // Any value; at or above finest_log2() nothing is capped. Starts uncapped.
  void set_cap_log2(int cap_log2) { cap_log2_ = cap_log2; }
  bool active() const { return cap_log2_ < finest_log2_; }

  // `wants` as the current cap (or `cap_log2`) allows: bricks below the cap replaced by their
  // ancestors at the cap's level, duplicates merged with their screen pixels summed.
  std::vector<net::BrickWant> apply(const std::vector<net::BrickWant>& wants) const {
    return apply_at(cap_log2_, wants);
  }
  std::vector<net::BrickWant> apply_at(int cap_log2,
                                       const std::vector<net::BrickWant>& wants) const;

  // What `wants` would take in a BrickCache (its charged bytes); unknown textures count 0.
  std::size_t cache_bytes(const std::vector<net::BrickWant>& wants) const;

 private:
  struct Texture {
    int finest_log2 = 0;
    int coarsest_level = 0;
    std::size_t brick_bytes = 0;
  };
  std::unordered_map<uint64_t, Texture> textures_;
  int finest_log2_ = 0;
  int cap_log2_ = 1 << 20;
};

// Those of `wants` that `cache` does not hold.
std::vector<net::BrickWant> not_resident(std::vector<net::BrickWant> wants,
                                         const BrickCache& cache);

// A frame's misses as the cap lets them be fetched, and whether the frame is final at that
// cap. Without a cap (null; `cache` is then not read) that is the frame's own verdict.
struct FrameNeeds {
  std::vector<net::BrickWant> wants;
  bool complete = false;
};
FrameNeeds needs_of(const Frame& frame, const LevelCap* cap, const BrickCache* cache,
                    bool arrived_while_drawing);

// The cap to refine to from the current one, after a frame at the current cap has
// converged: the finest cap in (current, current + max_step] (clamped to the prepared
// levels) whose bricks `misses` (the frame's wants before capping) ask for fit the cache
// with what it holds now, so that refining never evicts what the picture still draws from.
// `fill` is the share of the budget they may fill. Returns the current cap when none fits.
int next_cap(const LevelCap& cap, const std::vector<net::BrickWant>& misses,
             const BrickCache& cache, int max_step, double fill = 0.9);

}  // namespace soltex::view
