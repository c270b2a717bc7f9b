#include "brick_cost.h"

#include <time.h>

#include <stdexcept>

#include "percentile.h"
#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"

namespace soltex::bench {
namespace {

double thread_cpu_us() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) * 1e6 + static_cast<double>(now.tv_nsec) / 1e3;
}

}  // namespace

BrickCostMeter::BrickCostMeter(const PreparedScene& scene, const MipSettings& mip,
                               std::vector<BrickKey> keys, const CodecChoice& codec)
    : mip_(mip), keys_(std::move(keys)), codec_(codec.options()) {
  // One evaluator per texture, as soltexd builds one per registration.
  for (const PreparedObject& object : scene.objects) {
    textures_.try_emplace(object.texture_id, Texture{&object, TextureEvaluator(object.texture)});
  }
  for (const BrickKey& key : keys_) {
    if (!textures_.contains(key.texture)) {
      throw std::invalid_argument("BrickCostMeter: a brick of a texture not in the scene");
    }
  }
}

void BrickCostMeter::measure_pass() {
  std::vector<float> samples;
  encoded_bytes_ = 0;
  for (const BrickKey& key : keys_) {
    const Texture& texture = textures_.at(key.texture);
    const PreparedObject& object = *texture.object;
    samples.resize(static_cast<std::size_t>(object.layout.samples_per_brick()) *
                   static_cast<std::size_t>(object.channels));
    const double start = thread_cpu_us();
    evaluate_brick(texture.evaluator, object.layout, key.level, key.brick, mip_, samples);
    const std::vector<uint8_t> quantized = quantize(samples);
    const double encode_start = thread_cpu_us();
    const std::vector<uint8_t> encoded =
        encode_brick(quantized, object.layout.brick_size(), object.channels, codec_);
    const double encoded_at = thread_cpu_us();
    const DecodedBrick decoded = decode_brick(encoded);
    const double decoded_at = thread_cpu_us();
    if (decoded.samples != quantized) {
      throw std::runtime_error("BrickCostMeter: a brick did not survive encoding");
    }
    server_us_.push_back(encoded_at - start);
    encode_us_.push_back(encoded_at - encode_start);
    decode_us_.push_back(decoded_at - encoded_at);
    encoded_bytes_ += encoded.size();
  }
}

BrickCost BrickCostMeter::cost() const {
  BrickCost cost;
  cost.bricks = keys_.size();
  cost.encoded_bytes = encoded_bytes_;
  cost.server_us = median(server_us_);
  cost.encode_us = median(encode_us_);
  cost.decode_us = median(decode_us_);
  return cost;
}

}  // namespace soltex::bench
