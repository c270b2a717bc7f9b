#include "soltex/common/brick_cache.h"

#include <algorithm>
#include <shared_mutex>
#include <utility>

namespace soltex {

struct BrickCache::Entry {
  Entry(const BrickKey& k, CachedBrick&& b, std::size_t charged, bool pinned)
      : key(k), brick(std::move(b)), charged_bytes(charged), pinned_level(pinned) {}

  const BrickKey key;
  const CachedBrick brick;
  const std::size_t charged_bytes;
  // The frame of the last hit (kEvicted once evicted). Readers advance it and the evictor
  // swaps it for kEvicted with compare-and-swap, so a brick is either hit in this frame or
  // evicted, never both.
  std::atomic<uint64_t> stamp{0};
  // CLOCK's reference bit. Set on insertion so a new brick survives one sweep.
  std::atomic<bool> referenced{true};
  bool pinned_level;  // guarded by writer_mutex_
};

// Aligned so that two shards' mutexes never share a cache line.
struct alignas(64) BrickCache::Shard {
  mutable std::shared_mutex mutex;
  std::unordered_map<BrickKey, std::shared_ptr<Entry>, BrickKeyHash> map;
};

namespace {

constexpr int kShardBits = 6;  // 64 shards
constexpr std::size_t kAllocationHeader = 16;

}  // namespace

std::size_t BrickCache::charged_bytes(int brick_size, int channels) {
  using Node = std::pair<const BrickKey, std::shared_ptr<Entry>>;
  constexpr std::size_t kControlBlock = 2 * sizeof(long);  // use and weak counts
  constexpr std::size_t kEntry = kAllocationHeader + kControlBlock + sizeof(Entry);
  constexpr std::size_t kMapNode = kAllocationHeader + sizeof(void*) /* next */ + sizeof(Node) +
                                   sizeof(std::size_t) /* cached hash */ +
                                   sizeof(void*) /* bucket, load factor <= 1 */;
  constexpr std::size_t kClockSlot = sizeof(std::shared_ptr<Entry>);
  return CachedBrick::sample_bytes(brick_size, channels) + kAllocationHeader + kEntry + kMapNode +
         kClockSlot;
}

BrickCache::BrickCache(std::size_t budget_bytes)
    : budget_bytes_(budget_bytes),
      shards_(std::make_unique<Shard[]>(std::size_t{1} << kShardBits)) {}

BrickCache::~BrickCache() = default;

BrickCache::Shard& BrickCache::shard_for(const BrickKey& key) const {
  // The top bits: the maps inside a shard index their buckets with the low bits.
  return shards_[BrickKeyHash{}(key) >> (64 - kShardBits)];
}

std::shared_ptr<BrickCache::Entry> BrickCache::find_entry(const BrickKey& key) const {
  const Shard& shard = shard_for(key);
  std::shared_lock lock(shard.mutex);
  const auto it = shard.map.find(key);
  return it == shard.map.end() ? nullptr : it->second;
}

bool BrickCache::touch(Entry& entry, uint64_t frame) {
  uint64_t stamp = entry.stamp.load(std::memory_order_acquire);
  while (stamp < frame) {
    if (entry.stamp.compare_exchange_weak(stamp, frame, std::memory_order_acq_rel)) break;
  }
  if (stamp == kEvicted) return false;
  // Written only when clear: hot bricks are read by many threads, and a store per hit
  // would bounce their cache line between cores.
  if (!entry.referenced.load(std::memory_order_relaxed)) {
    entry.referenced.store(true, std::memory_order_relaxed);
  }
  return true;
}

bool BrickCache::is_pinned_level(const BrickKey& key) const {
  const auto it = pinned_from_level_.find(key.texture);
  return it != pinned_from_level_.end() && key.level >= it->second;
}

void BrickCache::begin_frame() {
  // Frame before generation: an accessor that sees the new generation also sees the new
  // frame, and stamps its bricks with it.
  frame_.fetch_add(1, std::memory_order_acq_rel);
  generation_.fetch_add(1, std::memory_order_acq_rel);
}

void BrickCache::pin_levels(uint64_t texture, int from_level) {
  std::lock_guard writer(writer_mutex_);
  pinned_from_level_[texture] = from_level;
  for (const auto& entry : clock_) {
    if (entry->key.texture == texture) entry->pinned_level = entry->key.level >= from_level;
  }
}

bool BrickCache::insert(const BrickKey& key, int brick_size, int channels,
                        std::span<const uint8_t> planar) {
  // Converted before taking the writer lock: readers never wait for it, writers little.
  return insert(key, CachedBrick(brick_size, channels, planar));
}

bool BrickCache::insert(const BrickKey& key, CachedBrick brick) {
  const std::size_t bytes = charged_bytes(brick.brick_size(), brick.channels());
  std::lock_guard writer(writer_mutex_);
  Shard& shard = shard_for(key);
  // Only writers change the maps, and we are the writer: reading without the shard lock
  // is safe.
  if (shard.map.contains(key)) return true;
  if (!make_room(bytes)) {
    refused_insertions_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  auto entry = std::make_shared<Entry>(key, std::move(brick), bytes, is_pinned_level(key));
  {
    std::unique_lock lock(shard.mutex);
    shard.map.emplace(key, entry);
  }
  clock_.push_back(std::move(entry));
  const uint64_t resident = resident_bytes_.load(std::memory_order_relaxed) + bytes;
  resident_bytes_.store(resident, std::memory_order_relaxed);
  peak_resident_bytes_.store(
      std::max(peak_resident_bytes_.load(std::memory_order_relaxed), resident),
      std::memory_order_relaxed);
  resident_bricks_.fetch_add(1, std::memory_order_relaxed);
  // Release: an accessor that reads the new count also finds the brick.
  insertions_.fetch_add(1, std::memory_order_release);
  return true;
}

bool BrickCache::make_room(std::size_t bytes) {
  if (bytes > budget_bytes_) return false;
  while (resident_bytes_.load(std::memory_order_relaxed) + bytes > budget_bytes_) {
    const uint64_t frame = frame_.load(std::memory_order_acquire);
    const std::size_t sweep = clock_.size();
    // Two sweeps: the first may only clear reference bits. A brick whose bit a reader set
    // again during the second sweep is remembered and taken if nothing else can go.
    std::size_t fallback = sweep;
    bool evicted = false;
    for (std::size_t step = 0; step < 2 * sweep && !evicted; ++step) {
      if (hand_ >= clock_.size()) hand_ = 0;
      Entry& entry = *clock_[hand_];
      const bool pinned =
          entry.pinned_level || entry.stamp.load(std::memory_order_acquire) >= frame;
      if (!pinned) {
        if (entry.referenced.exchange(false, std::memory_order_relaxed)) {
          if (step >= sweep && fallback == sweep) fallback = hand_;
        } else {
          evicted = try_evict(hand_, frame);
          if (evicted) break;  // the hand now points at the entry moved into this slot
        }
      }
      ++hand_;
    }
    if (!evicted && fallback < clock_.size()) evicted = try_evict(fallback, frame);
    if (!evicted) return false;
  }
  return true;
}

bool BrickCache::try_evict(std::size_t clock_index, uint64_t frame) {
  Entry& entry = *clock_[clock_index];
  {
    Shard& shard = shard_for(entry.key);
    std::unique_lock lock(shard.mutex);
    // A reader may have hit it since it was checked: the compare-and-swap decides.
    uint64_t stamp = entry.stamp.load(std::memory_order_acquire);
    if (stamp >= frame ||
        !entry.stamp.compare_exchange_strong(stamp, kEvicted, std::memory_order_acq_rel)) {
      return false;
    }
    // A new generation before the map lets go of the entry: whoever releases its last
    // reference afterwards has seen the new generation, so nobody trusts a freed brick.
    // Accessors holding it check its stamp on their next lookup.
    generation_.fetch_add(1, std::memory_order_acq_rel);
    shard.map.erase(entry.key);
  }
  resident_bytes_.store(resident_bytes_.load(std::memory_order_relaxed) - entry.charged_bytes,
                        std::memory_order_relaxed);
  resident_bricks_.fetch_sub(1, std::memory_order_relaxed);
  evictions_.fetch_add(1, std::memory_order_relaxed);
  // Swap-remove; readers still holding the entry keep it alive.
  clock_[clock_index] = std::move(clock_.back());
  clock_.pop_back();
  return true;
}

std::shared_ptr<const CachedBrick> BrickCache::find(const BrickKey& key) {
  const uint64_t frame = frame_.load(std::memory_order_acquire);
  std::shared_ptr<Entry> entry = find_entry(key);
  if (entry && touch(*entry, frame)) {
    add_lookups(1, 0, 0);
    const CachedBrick* brick = &entry->brick;
    return std::shared_ptr<const CachedBrick>(std::move(entry), brick);
  }
  add_lookups(0, 0, 1);
  return nullptr;
}

bool BrickCache::contains(const BrickKey& key) const {
  return find_entry(key) != nullptr;
}

void BrickCache::add_lookups(uint64_t hits, uint64_t microcache_hits, uint64_t misses) {
  if (hits + misses == 0) return;
  lookups_.fetch_add(hits + misses, std::memory_order_relaxed);
  if (hits != 0) hits_.fetch_add(hits, std::memory_order_relaxed);
  if (microcache_hits != 0) microcache_hits_.fetch_add(microcache_hits, std::memory_order_relaxed);
  if (misses != 0) misses_.fetch_add(misses, std::memory_order_relaxed);
}

BrickCacheStats BrickCache::stats() const {
  BrickCacheStats s;
  s.lookups = lookups_.load(std::memory_order_relaxed);
  s.hits = hits_.load(std::memory_order_relaxed);
  s.microcache_hits = microcache_hits_.load(std::memory_order_relaxed);
  s.misses = misses_.load(std::memory_order_relaxed);
  s.insertions = insertions_.load(std::memory_order_relaxed);
  s.refused_insertions = refused_insertions_.load(std::memory_order_relaxed);
  s.evictions = evictions_.load(std::memory_order_relaxed);
  s.resident_bytes = resident_bytes_.load(std::memory_order_relaxed);
  s.peak_resident_bytes = peak_resident_bytes_.load(std::memory_order_relaxed);
  s.resident_bricks = resident_bricks_.load(std::memory_order_relaxed);
  s.budget_bytes = budget_bytes_;
  s.frame = frame_.load(std::memory_order_relaxed);
  return s;
}

// ---- Accessor -----------------------------------------------------------------------------

BrickCache::Accessor::Accessor(BrickCache& cache, int set_bits)
    : cache_(&cache),
      set_shift_(32 - std::clamp(set_bits, kMinSetBits, kMaxSetBits)),
      table_(kWays << (32 - set_shift_)),
      next_way_(std::size_t{1} << (32 - set_shift_), 0),
      last_(&table_[0]) {}

int BrickCache::Accessor::set_bits_for(int brick_size, int channels) {
  const std::size_t bricks = kRetainedBytes / charged_bytes(brick_size, channels);
  int bits = kMinSetBits;
  while (bits < kMaxSetBits && (kWays << (bits + 1)) <= bricks) ++bits;
  return bits;
}

void BrickCache::Accessor::let_go_of_evicted() {
  for (Slot& slot : table_) {
    if (slot.entry != nullptr && slot.entry->stamp.load(std::memory_order_acquire) == kEvicted) {
      slot = Slot{};
    }
  }
}

const CachedBrick* BrickCache::Accessor::find_slow(const BrickKey& key, std::size_t set) {
  // Generation before frame (begin_frame() bumps them in the other order): a slot validated
  // under this generation carries this frame's stamp.
  const uint64_t generation = cache_->generation_.load(std::memory_order_acquire);
  const uint64_t frame = cache_->frame_.load(std::memory_order_acquire);
  if (frame != frame_seen_) {
    frame_seen_ = frame;
    let_go_of_evicted();
    flush_statistics();
  } else if (microcache_hits_ + map_hits_ + misses_ >= kFlushEvery) {
    flush_statistics();
  }

  Slot* ways = &table_[kWays * set];
  for (std::size_t way = 0; way < kWays; ++way) {
    Slot& slot = ways[way];
    if (slot.entry == nullptr || !(slot.key == key)) continue;
    // From an older generation: trust it again once it is stamped for this frame.
    if (slot.generation == generation || touch(*slot.entry, frame)) {
      slot.generation = generation;
      ++microcache_hits_;
      last_ = &slot;
      return slot.brick;
    }
    slot = Slot{};  // evicted
    break;
  }

  std::shared_ptr<Entry> entry = cache_->find_entry(key);
  if (entry == nullptr || !touch(*entry, frame)) {
    ++misses_;
    return nullptr;
  }
  ++map_hits_;
  // An empty way if there is one, else round robin.
  std::size_t way = next_way_[set];
  for (std::size_t w = 0; w < kWays; ++w) {
    if (ways[w].entry == nullptr) {
      way = w;
      break;
    }
  }
  next_way_[set] = static_cast<uint8_t>((way + 1) % kWays);
  const CachedBrick* brick = &entry->brick;
  ways[way] = Slot{key, generation, std::move(entry), brick};
  last_ = &ways[way];
  return brick;
}

void BrickCache::Accessor::flush_statistics() {
  cache_->add_lookups(microcache_hits_ + map_hits_, microcache_hits_, misses_);
  microcache_hits_ = map_hits_ = misses_ = 0;
}

}  // namespace soltex
