#pragma once

#include <glm/vec3.hpp>
#include <span>

#include "soltex/common/brick_layout.h"
#include "soltex/common/texture_evaluator.h"

// Evaluating one brick of one level: the (B + 1)^3 corner samples of its B^3 cells, every
// channel, channel-planar, in one batch call.
namespace soltex {

// How a MIP level is made from the texture function.
enum class MipMode : uint8_t {
  point,         // sample the function at the level's lattice points (aliases at coarse levels)
  band_limited,  // sample with the level's spacing as filter width: octaves it cannot show
                 // are replaced by their mean (the default)
  supersampled,  // average k^3 samples spread over each sample's cell-sized box, each
                 // band-limited to the sub-sample spacing
};

const char* mip_mode_name(MipMode mode);

struct MipSettings {
  MipMode mode = MipMode::band_limited;
  int supersample = 2;  // k, for MipMode::supersampled; 1..4
};

// Writes layout.samples_per_brick() floats per channel into `out` (channel-planar, x fastest).
// Samples on a face, edge or corner shared with a neighbouring brick are bit-identical in both
// bricks: every position is computed from its global lattice index. Throws
// std::invalid_argument when the brick is outside the layout or `out` is too small.
void evaluate_brick(const TextureEvaluator& texture, const BrickLayout& layout, int level,
                    const glm::ivec3& brick, const MipSettings& mip, std::span<float> out);

}  // namespace soltex
