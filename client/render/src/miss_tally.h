#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>

#include "soltex/common/brick_key.h"

namespace soltex::render {

// Counts the pixels that missed each brick. Neighbouring pixels miss the same few bricks, so a
// handful of recent keys absorb nearly every count before the hash map sees one: a cold frame
// misses at every pixel.
class MissTally {
 public:
  void add(const BrickKey& key, uint32_t pixels = 1) {
    for (Slot& slot : recent_) {
      if (slot.pixels > 0 && slot.key == key) {
        slot.pixels += pixels;
        return;
      }
    }
    Slot& victim = recent_[next_++ % recent_.size()];
    if (victim.pixels > 0) counts_[victim.key] += victim.pixels;
    victim = {key, pixels};
  }
  // Visits every key with its pixel count, and empties the tally.
  template <typename Visit>
  void drain(Visit visit) {
    for (Slot& slot : recent_) {
      if (slot.pixels > 0) counts_[slot.key] += slot.pixels;
      slot.pixels = 0;
    }
    for (const auto& [key, pixels] : counts_) visit(key, pixels);
    counts_.clear();
  }

 private:
  struct Slot {
    BrickKey key{};
    uint32_t pixels = 0;
  };
  std::array<Slot, 8> recent_{};
  unsigned next_ = 0;
  std::unordered_map<BrickKey, uint32_t, BrickKeyHash> counts_;
};

}  // namespace soltex::render
