#include "soltex/net/local_brick_source.h"

#include <algorithm>

#include "soltex/common/brick_codec.h"
#include "soltex/common/texture_id.h"

namespace soltex::net {

LocalBrickSource::LocalBrickSource(BrickCache& cache)
    : cache_(cache), worker_([this] { work(); }) {}

LocalBrickSource::~LocalBrickSource() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  worker_.join();
}

uint64_t LocalBrickSource::register_texture(const TextureSpec& spec, const Volume& volume,
                                            int brick_size, const MipSettings& mip) {
  const uint64_t id = texture_id(spec, volume, brick_size, mip);
  auto texture = std::make_shared<const Texture>(
      Texture{TextureEvaluator(spec), BrickLayout(volume, brick_size), mip});
  std::lock_guard lock(mutex_);
  cache_.pin_levels(id, texture->layout.coarsest_level());
  textures_.emplace(id, std::move(texture));
  return id;
}

void LocalBrickSource::want(std::vector<BrickWant> wants) {
  std::sort(wants.begin(), wants.end(), fetched_before);
  std::unordered_set<BrickKey, BrickKeyHash> seen;
  std::lock_guard lock(mutex_);
  // Waiting keys this frame still wants stay; the others are stale.
  std::unordered_set<BrickKey, BrickKeyHash> wanted;
  for (const BrickWant& w : wants) wanted.insert(w.key);
  for (const BrickWant& w : waiting_) stats_.cancelled += wanted.contains(w.key) ? 0 : 1;
  waiting_.clear();
  for (const BrickWant& w : wants) {
    if (!seen.insert(w.key).second || cache_.contains(w.key)) continue;
    waiting_.push_back(w);
  }
  changed_.notify_all();
}

void LocalBrickSource::work() {
  std::vector<float> samples;
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [this] { return stopping_ || !waiting_.empty(); });
    if (stopping_) return;
    const BrickWant want = waiting_.front();
    waiting_.erase(waiting_.begin());
    auto it = textures_.find(want.key.texture);
    if (it == textures_.end() || !it->second->layout.contains(want.key.level, want.key.brick)) {
      ++stats_.errors;
      changed_.notify_all();
      continue;
    }
    const std::shared_ptr<const Texture> texture = it->second;
    ++busy_;
    ++stats_.requested;
    lock.unlock();
    const int channels = texture->evaluator.spec().channels.sample_count();
    samples.resize(static_cast<std::size_t>(texture->layout.samples_per_brick()) *
                   static_cast<std::size_t>(channels));
    evaluate_brick(texture->evaluator, texture->layout, want.key.level, want.key.brick,
                   texture->mip, samples);
    cache_.insert(want.key, texture->layout.brick_size(), channels, quantize(samples));
    lock.lock();
    --busy_;
    ++stats_.received;
    changed_.notify_all();
  }
}

bool LocalBrickSource::idle() const {
  std::lock_guard lock(mutex_);
  return waiting_.empty() && busy_ == 0;
}

bool LocalBrickSource::wait_idle(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return changed_.wait_for(lock, timeout, [this] { return waiting_.empty() && busy_ == 0; });
}

SourceStats LocalBrickSource::stats() const {
  std::lock_guard lock(mutex_);
  SourceStats s = stats_;
  s.waiting = waiting_.size();
  s.in_flight = busy_;
  s.connected = true;
  return s;
}

}  // namespace soltex::net
