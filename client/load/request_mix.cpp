#include "request_mix.h"

#include <algorithm>
#include <random>
#include <stdexcept>
#include <unordered_set>

namespace soltex::load {
namespace {

// Differs in every stream and from the hot-set draw, however the seed was chosen.
uint64_t mix_seed(uint64_t seed, uint64_t stream) {
  uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// Redraws before a freely choosing mix accepts a key the stream already waits for.
constexpr int kRedraws = 8;

// A uniformly random brick of the whole pyramid: brick index -> level -> coordinates.
BrickKey uniform_brick(const TextureShape& shape, std::mt19937_64& rng) {
  uint64_t index = std::uniform_int_distribution<uint64_t>(0, shape.brick_count() - 1)(rng);
  for (int level = 0; level < shape.level_count; ++level) {
    const auto n = static_cast<uint64_t>(shape.bricks_per_axis(level));
    if (index < n * n * n) {
      return {shape.texture_id,
              level,
              {static_cast<int>(index % n), static_cast<int>((index / n) % n),
               static_cast<int>(index / (n * n))}};
    }
    index -= n * n * n;
  }
  return {shape.texture_id, shape.level_count - 1, {0, 0, 0}};
}

class HotMix final : public RequestMix {
 public:
  HotMix(std::shared_ptr<const std::vector<BrickKey>> keys, uint64_t seed)
      : keys_(std::move(keys)), rng_(seed) {}

  PlannedWant next(const Busy& busy) override {
    std::uniform_int_distribution<std::size_t> pick(0, keys_->size() - 1);
    std::size_t i = pick(rng_);
    for (int tries = 0; tries < kRedraws && busy((*keys_)[i]); ++tries) i = pick(rng_);
    return {(*keys_)[i], 0, InvalidKind::none};
  }

 private:
  std::shared_ptr<const std::vector<BrickKey>> keys_;
  std::mt19937_64 rng_;
};

class UniformMix final : public RequestMix {
 public:
  UniformMix(TextureShape shape, uint64_t seed) : shape_(shape), rng_(seed) {}

  PlannedWant next(const Busy& busy) override {
    BrickKey key = uniform_brick(shape_, rng_);
    for (int tries = 0; tries < kRedraws && busy(key); ++tries) key = uniform_brick(shape_, rng_);
    return {key, 0, InvalidKind::none};
  }

 private:
  TextureShape shape_;
  std::mt19937_64 rng_;
};

class ReplayMix final : public RequestMix {
 public:
  ReplayMix(std::shared_ptr<const std::vector<RecordedRequest>> log, uint64_t texture_id,
            int stream, int streams)
      : log_(std::move(log)), texture_id_(texture_id), next_(stream), stride_(streams) {}

  PlannedWant next(const Busy&) override {
    const RecordedRequest& r = (*log_)[next_ % log_->size()];
    next_ += stride_;
    return {{texture_id_, r.level, {r.x, r.y, r.z}}, r.priority, InvalidKind::none};
  }

 private:
  std::shared_ptr<const std::vector<RecordedRequest>> log_;
  uint64_t texture_id_;
  uint64_t next_;
  uint64_t stride_;
};

// Replaces a fraction of another mix's requests by keys the server must refuse.
class InvalidKeys final : public RequestMix {
 public:
  InvalidKeys(std::unique_ptr<RequestMix> inner, TextureShape shape, double fraction, uint64_t seed)
      : inner_(std::move(inner)), shape_(shape), fraction_(fraction), rng_(seed) {}

  PlannedWant next(const Busy& busy) override {
    if (!std::bernoulli_distribution(fraction_)(rng_)) return inner_->next(busy);
    BrickKey key = uniform_brick(shape_, rng_);
    const bool out_of_range = (invalid_made_++ % 2) == 0;
    if (out_of_range) {
      // Beyond the level's last brick along x, by a random amount so repeats are rare.
      key.brick.x =
          shape_.bricks_per_axis(key.level) + std::uniform_int_distribution<int>(0, 1 << 20)(rng_);
    } else {
      key.texture ^= 0xA5A5'5A5A'C3C3'3C3CULL;  // nonzero: never the registered id
    }
    return {key, 0, out_of_range ? InvalidKind::out_of_range : InvalidKind::unknown_texture};
  }

 private:
  std::unique_ptr<RequestMix> inner_;
  TextureShape shape_;
  double fraction_;
  std::mt19937_64 rng_;
  uint64_t invalid_made_ = 0;
};

std::shared_ptr<const std::vector<BrickKey>> draw_hot_set(const TextureShape& shape, int size,
                                                          uint64_t seed) {
  const auto wanted = static_cast<std::size_t>(
      std::min<uint64_t>(static_cast<uint64_t>(size), shape.brick_count()));
  std::mt19937_64 rng(mix_seed(seed, ~uint64_t{0}));
  std::unordered_set<BrickKey, BrickKeyHash> seen;
  auto keys = std::make_shared<std::vector<BrickKey>>();
  while (keys->size() < wanted) {
    const BrickKey key = uniform_brick(shape, rng);
    if (seen.insert(key).second) keys->push_back(key);
  }
  return keys;
}

}  // namespace

uint64_t TextureShape::brick_count() const {
  uint64_t total = 0;
  for (int level = 0; level < level_count; ++level) {
    const auto n = static_cast<uint64_t>(bricks_per_axis(level));
    total += n * n * n;
  }
  return total;
}

std::vector<std::unique_ptr<RequestMix>> make_request_mixes(const MixSettings& settings,
                                                            const TextureShape& shape,
                                                            int streams) {
  std::shared_ptr<const std::vector<BrickKey>> hot;
  std::shared_ptr<const std::vector<RecordedRequest>> log;
  if (settings.kind == MixKind::hot) hot = draw_hot_set(shape, settings.hot_set, settings.seed);
  if (settings.kind == MixKind::replay) {
    if (settings.replay.empty()) throw std::invalid_argument("the replay log has no requests");
    log = std::make_shared<const std::vector<RecordedRequest>>(settings.replay);
  }
  std::vector<std::unique_ptr<RequestMix>> mixes;
  for (int s = 0; s < streams; ++s) {
    const uint64_t seed = mix_seed(settings.seed, static_cast<uint64_t>(s));
    std::unique_ptr<RequestMix> mix;
    switch (settings.kind) {
      case MixKind::hot:
        mix = std::make_unique<HotMix>(hot, seed);
        break;
      case MixKind::uniform:
        mix = std::make_unique<UniformMix>(shape, seed);
        break;
      case MixKind::replay:
        mix = std::make_unique<ReplayMix>(log, shape.texture_id, s, streams);
        break;
    }
    if (settings.invalid_fraction > 0.0) {
      mix = std::make_unique<InvalidKeys>(std::move(mix), shape, settings.invalid_fraction,
                                          seed ^ 0x5DEECE66DULL);
    }
    mixes.push_back(std::move(mix));
  }
  return mixes;
}

}  // namespace soltex::load
