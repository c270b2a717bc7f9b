#include "brick_producer.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <vector>

#include "soltex/common/brick_evaluator.h"
#include "soltex/common/texture_id.h"

namespace soltex::server {

void BrickProducer::produce(const WorkItem& item, Deliver deliver) {
  if (faults_) faults_->delay_brick();
  EncodedBrickPtr cached;
  switch (store_.claim(item.key, item.codec, cached, deliver)) {
    case BrickStore::Claim::hit:
      deliver(cached);
      return;
    case BrickStore::Claim::waiter:
      return;  // the owner's publish() calls deliver
    case BrickStore::Claim::owner:
      break;
  }
  if (EncodedBrickPtr shared = from_shared_cache(item)) {
    store_.publish(shared);
    deliver(shared);
    return;
  }
  EncodedBrickPtr brick;
  try {
    brick = evaluate(item);
  } catch (const std::exception& e) {
    spdlog::error("brick {} level {} ({}, {}, {}) failed: {}", texture_id_hex(item.key.texture),
                  item.key.level, item.key.brick.x, item.key.brick.y, item.key.brick.z, e.what());
    store_.abandon(item.key, item.codec);
    deliver(nullptr);
    return;
  }
  store_.publish(brick);
  deliver(brick);
  // After the client has it: the other replicas need not evaluate it again.
  if (shared_) shared_->store(item.key, item.codec, brick->payload());
}

EncodedBrickPtr BrickProducer::cached(const BrickKey& key, Codec codec) {
  if (faults_ && faults_->delay().count() > 0) return nullptr;
  return store_.find(key, codec);
}

EncodedBrickPtr BrickProducer::from_shared_cache(const WorkItem& item) {
  if (!shared_) return nullptr;
  std::optional<std::string> payload = shared_->fetch(item.key, item.codec);
  if (!payload) return nullptr;
  try {
    const uint64_t checksum = encoded_brick_checksum(
        std::span(reinterpret_cast<const uint8_t*>(payload->data()), payload->size()));
    metrics_.bricks_from_shared_cache.fetch_add(1, std::memory_order_relaxed);
    return std::make_shared<const EncodedBrick>(item.key, item.codec, *payload, checksum);
  } catch (const CodecError& e) {
    spdlog::warn("shared-cache value for brick {} level {} has no valid header: {}",
                 texture_id_hex(item.key.texture), item.key.level, e.what());
    return nullptr;
  }
}

EncodedBrickPtr BrickProducer::evaluate(const WorkItem& item) {
  const RegisteredTexture& texture = *item.texture;
  const int channels = texture.evaluator.spec().channels.sample_count();
  thread_local std::vector<float> samples;
  samples.resize(static_cast<std::size_t>(texture.layout.samples_per_brick()) *
                 static_cast<std::size_t>(channels));
  const auto start = std::chrono::steady_clock::now();
  evaluate_brick(texture.evaluator, texture.layout, item.key.level, item.key.brick, texture.mip,
                 samples);
  const auto evaluated = std::chrono::steady_clock::now();
  const CodecOptions options = served_codec_options(item.codec, zstd_level_);
  thread_local std::vector<uint8_t> buffer;
  const std::span<const uint8_t> encoded =
      encode_brick_samples(samples, texture.layout.brick_size(), channels, options, buffer);
  const uint64_t checksum = encoded_brick_checksum(encoded);
  metrics_.record(BrickStage::evaluate, evaluated - start);
  metrics_.record(BrickStage::encode, std::chrono::steady_clock::now() - evaluated);
  metrics_.bricks_evaluated.fetch_add(1, std::memory_order_relaxed);
  return std::make_shared<const EncodedBrick>(
      item.key, item.codec,
      std::string_view(reinterpret_cast<const char*>(encoded.data()), encoded.size()), checksum);
}

}  // namespace soltex::server
