#include "soltex/common/brick_evaluator.h"

#include <stdexcept>
#include <string>
#include <vector>

#include "soltex/common/evaluation_counters.h"

namespace soltex {
namespace {

// One count per call: the octave plan is a few dozen operations next to a brick's thousands
// of samples.
void count_octaves(const TextureEvaluator& texture, double filter_width, std::size_t samples) {
  const int all = texture.evaluated_octaves(0.0);
  const int evaluated = texture.evaluated_octaves(filter_width);
  octave_counters().add(samples, evaluated, all - evaluated);
}

}  // namespace

const char* mip_mode_name(MipMode mode) {
  switch (mode) {
    case MipMode::point:
      return "point";
    case MipMode::band_limited:
      return "band-limited";
    case MipMode::supersampled:
      return "supersampled";
  }
  return "unknown";
}

void evaluate_brick(const TextureEvaluator& texture, const BrickLayout& layout, int level,
                    const glm::ivec3& brick, const MipSettings& mip, std::span<float> out) {
  if (!layout.contains(level, brick)) {
    throw std::invalid_argument("evaluate_brick: level " + std::to_string(level) + " brick (" +
                                std::to_string(brick.x) + ", " + std::to_string(brick.y) + ", " +
                                std::to_string(brick.z) + ") is outside the volume");
  }
  const Grid grid = layout.sample_grid(level, brick);
  switch (mip.mode) {
    case MipMode::point:
      texture.evaluate_grid(grid, 0.0, out);
      count_octaves(texture, 0.0, grid.size());
      return;
    case MipMode::band_limited:
      texture.evaluate_grid(grid, layout.filter_width(level), out);
      count_octaves(texture, layout.filter_width(level), grid.size());
      return;
    case MipMode::supersampled:
      break;
  }
  const int k = mip.supersample;
  if (k < 1 || k > 4) {
    throw std::invalid_argument("evaluate_brick: supersample = " + std::to_string(k) +
                                " must be in [1, 4]");
  }
  const std::size_t total =
      grid.size() * static_cast<std::size_t>(texture.spec().channels.sample_count());
  if (out.size() < total) {
    throw std::invalid_argument("evaluate_brick: output holds " + std::to_string(out.size()) +
                                " floats, the brick needs " + std::to_string(total));
  }
  // Sub-sample offsets ((s + 0.5) / k - 0.5) * h per axis, added to the origin, so every
  // sub-sample position still derives from the global index alone.
  thread_local std::vector<float> sub;
  sub.resize(total);
  std::fill(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(total), 0.0f);
  const double sub_width = layout.filter_width(level) / k;
  const float weight = 1.0f / static_cast<float>(k * k * k);
  for (int sz = 0; sz < k; ++sz) {
    for (int sy = 0; sy < k; ++sy) {
      for (int sx = 0; sx < k; ++sx) {
        Grid shifted = grid;
        const glm::dvec3 offset = (glm::dvec3(sx, sy, sz) + 0.5) / static_cast<double>(k) - 0.5;
        shifted.origin = grid.origin + offset * grid.step;
        texture.evaluate_grid(shifted, sub_width, sub);
        for (std::size_t i = 0; i < total; ++i) out[i] += weight * sub[i];
      }
    }
  }
  count_octaves(texture, sub_width, grid.size() * static_cast<std::size_t>(k * k * k));
}

}  // namespace soltex
