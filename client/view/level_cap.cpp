#include "level_cap.h"

#include <algorithm>

namespace soltex::view {

LevelCap::LevelCap(const PreparedScene& scene) {
  for (const PreparedObject& object : scene.objects) {
    add_texture(object.texture_id, object.layout, object.channels);
  }
}

void LevelCap::add_texture(uint64_t texture, const BrickLayout& layout, int channels) {
  Texture t;
  t.finest_log2 = layout.finest_level_log2();
  t.coarsest_level = layout.coarsest_level();
  t.brick_bytes = BrickCache::charged_bytes(layout.brick_size(), channels);
  textures_[texture] = t;
  finest_log2_ = std::max(finest_log2_, t.finest_log2);
}

std::vector<net::BrickWant> LevelCap::apply_at(int cap_log2,
                                               const std::vector<net::BrickWant>& wants) const {
  std::vector<net::BrickWant> capped;
  capped.reserve(wants.size());
  std::unordered_map<BrickKey, std::size_t, BrickKeyHash> index;  // key -> position in capped
  for (net::BrickWant want : wants) {
    const auto texture = textures_.find(want.key.texture);
    if (texture != textures_.end()) {
      const Texture& t = texture->second;
      // Level l has resolution 2^(finest - l): the cap's level is finest - cap.
      const int lowest = std::clamp(t.finest_log2 - cap_log2, 0, t.coarsest_level);
      if (want.key.level < lowest) {
        // Each level halves the cells and keeps the brick size: the ancestor's index is the
        // brick's shifted by the levels between them.
        const int shift = lowest - want.key.level;
        want.key.level = lowest;
        want.key.brick = {want.key.brick.x >> shift, want.key.brick.y >> shift,
                          want.key.brick.z >> shift};
      }
    }
    const auto [at, added] = index.try_emplace(want.key, capped.size());
    if (added) {
      capped.push_back(want);
    } else {
      uint32_t& pixels = capped[at->second].screen_pixels;
      pixels = want.screen_pixels > UINT32_MAX - pixels ? UINT32_MAX : pixels + want.screen_pixels;
    }
  }
  return capped;
}

std::size_t LevelCap::cache_bytes(const std::vector<net::BrickWant>& wants) const {
  std::size_t bytes = 0;
  for (const net::BrickWant& want : wants) {
    const auto texture = textures_.find(want.key.texture);
    if (texture != textures_.end()) bytes += texture->second.brick_bytes;
  }
  return bytes;
}

std::vector<net::BrickWant> not_resident(std::vector<net::BrickWant> wants,
                                         const BrickCache& cache) {
  std::erase_if(wants, [&](const net::BrickWant& want) { return cache.contains(want.key); });
  return wants;
}

FrameNeeds needs_of(const Frame& frame, const LevelCap* cap, const BrickCache* cache,
                    bool arrived_while_drawing) {
  if (cap == nullptr) return {frame.misses, frame.complete()};
  FrameNeeds needs;
  needs.wants = not_resident(cap->apply(frame.misses), *cache);
  // Every brick the cap allows is resident and none arrived during the frame: each pixel
  // drew from the brick it draws from at this cap (a pixel asking for a finer level falls
  // back to its ancestor at the cap).
  needs.complete = needs.wants.empty() && !arrived_while_drawing;
  return needs;
}

int next_cap(const LevelCap& cap, const std::vector<net::BrickWant>& misses,
             const BrickCache& cache, int max_step, double fill) {
  const int current = cap.cap_log2();
  if (!cap.active() || max_step < 1) return current;
  const double room = fill * static_cast<double>(cache.budget_bytes()) -
                      static_cast<double>(cache.stats().resident_bytes);
  // max_step may be INT_MAX (all the way): never add it to the cap.
  const int finest =
      cap.finest_log2() - current <= max_step ? cap.finest_log2() : current + max_step;
  for (int candidate = finest; candidate > current; --candidate) {
    const std::size_t bytes = cap.cache_bytes(not_resident(cap.apply_at(candidate, misses), cache));
    if (static_cast<double>(bytes) <= room) return candidate;
  }
  return current;
}

}  // namespace soltex::view
