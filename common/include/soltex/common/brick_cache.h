#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <unordered_map>
#include <vector>

#include "soltex/common/brick_key.h"
#include "soltex/common/cached_brick.h"

// The sparse cache cube: decoded bricks by BrickKey, under a byte budget.
//
// Reading: a sharded hash map (64 shards, each behind its own std::shared_mutex, as in
// pbrt-v4's BufferCache) so render threads never share a global lock, and per thread an
// Accessor with a two-brick microcache in front of it (OpenImageIO's per-thread tile
// microcache, OpenVDB's accessors): a run of lookups in one brick compares a key and a
// generation number and takes no lock and writes nothing shared.
//
// Lifetime: entries are reference counted (std::shared_ptr). Eviction removes an entry from
// the map; a reader that still holds it keeps reading valid samples until it lets go, so an
// evicted brick is never freed under a reader.
//
// Eviction: CLOCK (second chance) over all resident bricks, under a byte budget that counts
// sample bytes and per-entry bookkeeping (charged_bytes()). Never evicted:
//   - bricks hit during the current frame: a hit stamps the brick with the frame number, and
//     begin_frame() starts the next frame (so what is on screen now is not thrown out by
//     the bricks arriving for it);
//   - bricks of pinned levels (pin_levels(), meant for each texture's coarsest levels, so a
//     lookup always has a coarser fallback).
// When everything resident is pinned, an insertion that does not fit is refused (returns
// false): the budget is never exceeded.
//
// Insertions and evictions are serialised by one writer mutex; they are rare next to
// lookups (one per brick that arrives, against one lookup per pixel).
namespace soltex {

// A snapshot of the cache's counters. Lookup counters include what Accessors have flushed
// (see Accessor::flush_statistics()).
struct BrickCacheStats {
  uint64_t lookups = 0;             // hits + misses
  uint64_t hits = 0;                // found resident, microcache hits included
  uint64_t microcache_hits = 0;     // found in an accessor's microcache, no map lookup
  uint64_t misses = 0;              // not resident
  uint64_t insertions = 0;          // bricks that became resident
  uint64_t refused_insertions = 0;  // did not fit: what would have had to go was pinned
  uint64_t evictions = 0;
  uint64_t resident_bytes = 0;  // charged bytes of the resident bricks, <= budget_bytes
  uint64_t peak_resident_bytes = 0;
  uint64_t resident_bricks = 0;
  uint64_t budget_bytes = 0;
  uint64_t frame = 0;

  double hit_rate() const {
    return lookups == 0 ? 0.0 : static_cast<double>(hits) / static_cast<double>(lookups);
  }
};

class BrickCache {
 public:
  class Accessor;

  explicit BrickCache(std::size_t budget_bytes);
  ~BrickCache();
  BrickCache(const BrickCache&) = delete;
  BrickCache& operator=(const BrickCache&) = delete;

  // What one brick is charged against the budget: its sample bytes plus the bookkeeping it
  // brings (entry and control block, map node and bucket, CLOCK slot, allocator headers).
  static std::size_t charged_bytes(int brick_size, int channels);
  std::size_t budget_bytes() const { return budget_bytes_; }

  // Makes a brick resident; `planar` as CachedBrick takes it (channel-planar, as decoded).
  // Returns true when the brick is resident afterwards (a key already resident is kept:
  // keys are content-addressed, so its samples are the same) and false when it does not
  // fit because everything that would have to be evicted is pinned. Throws
  // std::invalid_argument on malformed sizes.
  bool insert(const BrickKey& key, int brick_size, int channels, std::span<const uint8_t> planar);
  bool insert(const BrickKey& key, CachedBrick brick);

  // Starts a new frame. Bricks hit in earlier frames become evictable again; call it once
  // per rendered frame (a cache whose frame never advances keeps every brick it has hit).
  void begin_frame();
  uint64_t frame() const { return frame_.load(std::memory_order_acquire); }

  // Bricks of `texture` at level >= from_level are never evicted, resident ones and those
  // inserted later. A later call for the same texture replaces the bound; a from_level
  // beyond the texture's coarsest level unpins it.
  void pin_levels(uint64_t texture, int from_level);

  // A lookup without a microcache: counted and pinning as Accessor::find. The handle keeps
  // the samples alive after an eviction.
  std::shared_ptr<const CachedBrick> find(const BrickKey& key);

  // Whether a brick is resident. Not counted as a lookup and pins nothing.
  bool contains(const BrickKey& key) const;

  BrickCacheStats stats() const;

 private:
  struct Entry;
  struct Shard;

  // Entry::stamp of an evicted entry; otherwise the stamp is the frame of the last hit.
  static constexpr uint64_t kEvicted = ~uint64_t{0};

  static bool touch(Entry& entry, uint64_t frame);
  Shard& shard_for(const BrickKey& key) const;
  std::shared_ptr<Entry> find_entry(const BrickKey& key) const;
  bool is_pinned_level(const BrickKey& key) const;
  bool make_room(std::size_t bytes);
  bool try_evict(std::size_t clock_index, uint64_t frame);
  void add_lookups(uint64_t hits, uint64_t microcache_hits, uint64_t misses);

  const std::size_t budget_bytes_;
  std::unique_ptr<Shard[]> shards_;

  // Starts at 1: an accessor's empty slot (generation 0) never matches. Bumped by every
  // eviction and frame, which sends microcache hits back to check their entry once.
  alignas(64) std::atomic<uint64_t> generation_{1};
  std::atomic<uint64_t> frame_{1};  // entries start with stamp 0: unpinned

  // Writer state: guarded by writer_mutex_.
  alignas(64) std::mutex writer_mutex_;
  std::vector<std::shared_ptr<Entry>> clock_;  // resident entries, in no particular order
  std::size_t hand_ = 0;
  std::unordered_map<uint64_t, int> pinned_from_level_;  // texture -> first pinned level

  alignas(64) std::atomic<uint64_t> lookups_{0};
  std::atomic<uint64_t> hits_{0};
  std::atomic<uint64_t> microcache_hits_{0};
  std::atomic<uint64_t> misses_{0};
  std::atomic<uint64_t> insertions_{0};
  std::atomic<uint64_t> refused_insertions_{0};
  std::atomic<uint64_t> evictions_{0};
  std::atomic<uint64_t> resident_bytes_{0};
  std::atomic<uint64_t> peak_resident_bytes_{0};
  std::atomic<uint64_t> resident_bricks_{0};
};

// One thread's window on a BrickCache, with a microcache of the two bricks it found last.
// Make one per render thread (per texture, for locality) and do not share it; it must not
// outlive its cache.
//
// An object rather than a thread_local microcache: a thread_local would be shared by every
// cache and texture the thread touches (so it would need the cache's identity in its key)
// and could outlive the cache it points into; an accessor's lifetime and owner are plain.
//
// Its counters are kept locally (shared atomics written per lookup would bounce between
// cores) and added to the cache's on the first lookup past the microcache after every
// few thousand lookups, when the accessor is destroyed, and on flush_statistics().
class BrickCache::Accessor {
 public:
  explicit Accessor(BrickCache& cache) : cache_(&cache) {}
  ~Accessor() { flush_statistics(); }
  Accessor(const Accessor&) = delete;
  Accessor& operator=(const Accessor&) = delete;

  // The brick, or nullptr when it is not resident. A hit pins the brick for the current
  // frame. The pointer stays valid while this accessor lives and until it has been asked
  // for two other bricks (the microcache holds a reference to the last two it found).
  const CachedBrick* find(const BrickKey& key) {
    // The fast path: one of the last two bricks, with no eviction and no new frame since
    // it was validated. No lock, no shared write.
    const uint64_t generation = cache_->generation_.load(std::memory_order_acquire);
    const Slot& last = slots_[last_];
    if (last.key == key && last.generation == generation) {
      ++microcache_hits_;
      return last.brick;
    }
    const Slot& other = slots_[last_ ^ 1];
    if (other.key == key && other.generation == generation) {
      last_ ^= 1;
      ++microcache_hits_;
      return other.brick;
    }
    return find_slow(key);
  }

  void flush_statistics();

 private:
  struct Slot {
    BrickKey key;
    uint64_t generation = 0;  // cache generation when last validated; 0: empty or evicted
    std::shared_ptr<Entry> entry;
    const CachedBrick* brick = nullptr;
  };

  static constexpr uint64_t kFlushEvery = 4096;  // counted lookups before a flush

  const CachedBrick* find_slow(const BrickKey& key);

  BrickCache* cache_;
  Slot slots_[2];
  int last_ = 0;  // the slot found last; the other is replaced next
  // Not yet flushed. Fast-path hits count only microcache_hits_; the rest count slow_.
  uint64_t microcache_hits_ = 0;
  uint64_t slow_microcache_hits_ = 0;
  uint64_t slow_hits_ = 0;
  uint64_t misses_ = 0;
};

}  // namespace soltex
