#pragma once

// Real bricks for the cache tests: evaluated by soltex::evaluate_brick (band-limited MIP) on a
// BrickLayout and quantized to 8 bits by the brick codec, exactly as a client receives them.

#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/common/brick_codec.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/brick_layout.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/common/texture_id.h"
#include "soltex/common/texture_spec.h"

namespace soltex::testing {

// One texture on one layout, with its content id and a way to make any of its bricks.
struct RealTexture {
  RealTexture(const TextureSpec& spec, const Volume& volume, int brick_size)
      : evaluator(spec),
        layout(volume, brick_size),
        id(texture_id(spec, volume, brick_size)),
        channels(evaluator.spec().channels.sample_count()) {}

  // Quantized, channel-planar: the form insert() takes.
  std::vector<uint8_t> brick(int level, const glm::ivec3& b) const {
    std::vector<float> samples(static_cast<std::size_t>(layout.samples_per_brick()) *
                               static_cast<std::size_t>(channels));
    evaluate_brick(evaluator, layout, level, b, MipSettings{}, samples);
    return quantize(samples);
  }

  BrickKey key(int level, const glm::ivec3& b) const { return BrickKey{id, level, b}; }

  bool insert(BrickCache& cache, int level, const glm::ivec3& b) const {
    return cache.insert(key(level, b), layout.brick_size(), channels, brick(level, b));
  }

  void insert_level(BrickCache& cache, int level) const {
    const int n = layout.bricks_per_axis(level);
    for (int z = 0; z < n; ++z) {
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) insert(cache, level, {x, y, z});
      }
    }
  }

  void insert_all_levels(BrickCache& cache) const {
    for (int level = 0; level <= layout.coarsest_level(); ++level) insert_level(cache, level);
  }

  // The channels the cache stores for a direct evaluation, in brick channel order.
  std::vector<float> direct(const glm::dvec3& p, int level) const {
    const TextureSpec& spec = evaluator.spec();
    const Texel texel = evaluator.sample(p, layout.filter_width(level));
    std::vector<float> values;
    if (spec.channels.colour) values = {texel.colour.r, texel.colour.g, texel.colour.b};
    if (spec.channels.opacity) {
      values.push_back(spec.opacity.low + (spec.opacity.high - spec.opacity.low) * texel.field);
    }
    if (spec.channels.specular) {
      values.push_back(spec.specular.low + (spec.specular.high - spec.specular.low) * texel.field);
    }
    return values;
  }

  TextureEvaluator evaluator;
  BrickLayout layout;
  uint64_t id;
  int channels;
};

inline TextureSpec spec_of(const Pattern& pattern, ChannelSet channels = {}) {
  TextureSpec spec;
  spec.pattern = pattern;
  spec.channels = channels;
  return spec;
}

}  // namespace soltex::testing
