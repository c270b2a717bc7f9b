#pragma once

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "accuracy_setting.h"
#include "soltex/common/brick_key.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/render/prepared_scene.h"

namespace soltex::bench {

// What a set of bricks costs to make and to move with one codec.
struct BrickCost {
  std::size_t bricks = 0;
  uint64_t encoded_bytes = 0;  // the sum over the bricks, 28-byte headers included
  // Medians per brick, in microseconds of CPU time of the measuring thread:
  double server_us = 0.0;  // evaluate + quantize + encode: soltexd's work for a brick it lacks
  double encode_us = 0.0;  // encode alone
  double decode_us = 0.0;  // decode with the checksum check, the client's work per brick
};

// Makes a frame's bricks again as soltexd does (evaluate_brick, quantize, encode_brick with
// one codec), one at a time on the calling thread, and decodes each as a client does,
// pooling the per-brick times of every pass. CPU time rather than wall time: on a shared
// machine a brick that waits for a core would otherwise count the wait as its cost.
class BrickCostMeter {
 public:
  // `keys` name textures of `scene` (throws std::invalid_argument otherwise); `scene` must
  // outlive the meter.
  BrickCostMeter(const PreparedScene& scene, const MipSettings& mip, std::vector<BrickKey> keys,
                 const CodecChoice& codec);

  // One pass over every brick. Throws std::runtime_error if a brick does not round-trip.
  void measure_pass();
  // Medians over every pass so far; bytes from the last pass (they do not change).
  BrickCost cost() const;

 private:
  struct Texture {
    const PreparedObject* object;
    TextureEvaluator evaluator;
  };

  MipSettings mip_;
  std::vector<BrickKey> keys_;
  CodecOptions codec_;
  std::unordered_map<uint64_t, Texture> textures_;
  std::vector<double> server_us_, encode_us_, decode_us_;
  uint64_t encoded_bytes_ = 0;
};

}  // namespace soltex::bench
