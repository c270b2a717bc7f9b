#pragma once

#include <array>
#include <atomic>
#include <bit>
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
// Accessor with a microcache in front of it (OpenImageIO's per-thread tile microcache,
// OpenVDB's accessors): a lookup of a brick the thread used lately compares a key and a
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
  // Read by accessors with the generation (Accessor::insertions), so kept on its line rather
  // than with the statistics that lookups write.
  std::atomic<uint64_t> insertions_{0};

  // Writer state: guarded by writer_mutex_.
  alignas(64) std::mutex writer_mutex_;
  std::vector<std::shared_ptr<Entry>> clock_;  // resident entries, in no particular order
  std::size_t hand_ = 0;
  std::unordered_map<uint64_t, int> pinned_from_level_;  // texture -> first pinned level

  alignas(64) std::atomic<uint64_t> lookups_{0};
  std::atomic<uint64_t> hits_{0};
  std::atomic<uint64_t> microcache_hits_{0};
  std::atomic<uint64_t> misses_{0};
  std::atomic<uint64_t> refused_insertions_{0};
  std::atomic<uint64_t> evictions_{0};
  std::atomic<uint64_t> resident_bytes_{0};
  std::atomic<uint64_t> peak_resident_bytes_{0};
  std::atomic<uint64_t> resident_bricks_{0};
};

// One thread's window on a BrickCache: a private microcache of the bricks it used lately,
// in front of the shared map. Make one per render thread (per texture, for locality) and do
// not share it; it must not outlive its cache.
//
// The microcache is a four-way set-associative table of sets() * kWays bricks (like a TLB;
// OpenImageIO keeps two tiles, but a pixel's neighbours on the next scanline are often in
// other bricks than the last one or two), with the brick found last checked first; both
// checks are inline. A hit compares a key and the cache's generation number: no lock, no
// shared write, no reference count. The generation changes with every eviction and frame;
// then each slot is checked once against its entry (still resident? stamp it for this
// frame) before it is trusted again.
//
// The table holds references (std::shared_ptr) to its bricks, so a brick evicted while a
// thread reads it stays valid. Evicted bricks are let go when their slot is reused or
// checked, and at the latest on the first lookup of the next frame: an accessor keeps at
// most sets() * kWays evicted bricks alive for at most a frame, outside the cache's budget.
// set_bits_for() sizes the table so that this stays under about kRetainedBytes however small
// the bricks: small bricks get more slots, since a frame touches more of them.
//
// An object rather than a thread_local: a thread_local would be shared by every cache and
// texture the thread touches (so it would need the cache's identity in its key) and could
// outlive the cache it points into; an accessor's lifetime and owner are plain.
//
// Its counters are kept locally (shared atomics written per lookup would bounce between
// cores) and added to the cache's every few thousand lookups that leave the inline path,
// on a new frame, when the accessor is destroyed, and on flush_statistics().
class BrickCache::Accessor {
 public:
  static constexpr std::size_t kWays = 4;
  static constexpr int kMinSetBits = 7;  // 512 bricks
  static constexpr int kMaxSetBits = 9;  // 2,048 bricks
  static constexpr std::size_t kRetainedBytes = std::size_t{8} << 20;

  // A table of 2^set_bits sets, set_bits in [kMinSetBits, kMaxSetBits].
  explicit Accessor(BrickCache& cache, int set_bits = kMinSetBits);
  // The set bits for bricks of this shape: as many slots as kRetainedBytes of such bricks,
  // within the bounds.
  static int set_bits_for(int brick_size, int channels);

  std::size_t sets() const { return next_way_.size(); }
  ~Accessor() { flush_statistics(); }
  Accessor(const Accessor&) = delete;
  Accessor& operator=(const Accessor&) = delete;

  // The brick, or nullptr when it is not resident. A hit pins the brick for the current
  // frame. The pointer stays valid until the next find() on this accessor.
  const CachedBrick* find(const BrickKey& key) {
    // Inline: the brick found last, then the key's set, each valid if validated in this
    // generation. Written so that its branches are predictable both in coherent order (the
    // last brick hits) and in random order (the last brick misses, the set hits): the way
    // is chosen without a branch.
    const uint64_t generation = cache_->generation_.load(std::memory_order_acquire);
    if (holds(*last_, key, generation)) {
      ++microcache_hits_;
      return last_->brick;
    }
    const std::size_t set = set_of(key);
    Slot* ways = &table_[kWays * set];
    unsigned found = 0;  // one bit per way
    for (std::size_t way = 0; way < kWays; ++way) {
      found |= static_cast<unsigned>(holds(ways[way], key, generation)) << way;
    }
    if (found != 0) {
      last_ = &ways[std::countr_zero(found)];
      ++microcache_hits_;
      return last_->brick;
    }
    return find_slow(key, set);
  }

  // The cache's generation: it changes with every eviction and every frame. While it is
  // the one a brick was found in, that brick is still resident and pinned for the frame, so
  // a caller may keep using it without asking again (a layer that keeps its last brick).
  uint64_t generation() const { return cache_->generation_.load(std::memory_order_acquire); }
  // Counts a lookup such a layer answered from the brick it kept.
  void count_microcache_hit(uint64_t lookups = 1) { microcache_hits_ += lookups; }
  // Bricks inserted so far: while generation() and this are unchanged, a brick found missing
  // is still missing, so a layer may remember the miss.
  uint64_t insertions() const { return cache_->insertions_.load(std::memory_order_acquire); }
  // Counts lookups such a layer answered "not resident" from what it remembered.
  void count_miss(uint64_t lookups = 1) { misses_ += lookups; }

  void flush_statistics();

 private:
  struct Slot {
    BrickKey key;
    uint64_t generation = 0;  // cache generation when last validated; 0: never
    std::shared_ptr<Entry> entry;
    const CachedBrick* brick = nullptr;
  };

  static constexpr uint64_t kFlushEvery = 4096;  // counted lookups before a flush

  // Compared with & rather than &&: no branch per field.
  static bool holds(const Slot& slot, const BrickKey& key, uint64_t generation) {
    return (slot.key.texture == key.texture) & (slot.key.level == key.level) &
           (slot.key.brick.x == key.brick.x) & (slot.key.brick.y == key.brick.y) &
           (slot.key.brick.z == key.brick.z) & (slot.generation == generation);
  }
  // A multiplicative hash of the key, cheap enough for the inline path; neighbouring bricks
  // land in different sets.
  std::size_t set_of(const BrickKey& key) const {
    const uint32_t h = static_cast<uint32_t>(key.brick.x) * 0x9E3779B1u +
                       static_cast<uint32_t>(key.brick.y) * 0x85EBCA77u +
                       static_cast<uint32_t>(key.brick.z) * 0xC2B2AE3Du +
                       static_cast<uint32_t>(key.level) * 0x27D4EB2Fu +
                       static_cast<uint32_t>(key.texture ^ (key.texture >> 32)) * 0x165667B1u;
    return h >> set_shift_;
  }

  const CachedBrick* find_slow(const BrickKey& key, std::size_t set);
  void let_go_of_evicted();

  BrickCache* cache_;
  uint64_t frame_seen_ = 0;
  int set_shift_;                  // 32 - set bits: set_of() keeps the hash's top bits
  std::vector<Slot> table_;        // set s: slots kWays * s ...
  std::vector<uint8_t> next_way_;  // per set, the way filled next (round robin)
  const Slot* last_;               // the slot found last
  // Not yet flushed.
  uint64_t microcache_hits_ = 0;
  uint64_t map_hits_ = 0;
  uint64_t misses_ = 0;
};

}  // namespace soltex
