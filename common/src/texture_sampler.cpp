#include "soltex/common/texture_sampler.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace soltex {

const char* sample_filter_name(SampleFilter filter) {
  switch (filter) {
    case SampleFilter::nearest:
      return "nearest";
    case SampleFilter::trilinear:
      return "trilinear";
    case SampleFilter::quadrilinear:
      return "quadrilinear";
  }
  return "unknown";
}

double level_of_detail(const BrickLayout& layout, double footprint) {
  const auto coarsest = static_cast<double>(layout.coarsest_level());
  if (std::isnan(footprint)) return coarsest;
  if (!(footprint > 0.0)) return 0.0;  // zero, negative, -inf
  // +inf gives +inf and a quotient that underflows gives -inf: both clamp.
  return std::clamp(std::log2(footprint / layout.filter_width(0)), 0.0, coarsest);
}

TextureSampler::TextureSampler(BrickCache& cache, uint64_t texture, const BrickLayout& layout,
                               int channels)
    : layout_(layout),
      texture_(texture),
      channels_(channels),
      coarsest_level_(layout.coarsest_level()),
      brick_shift_(layout.brick_shift()),
      brick_mask_(layout.brick_size() - 1),
      min_(layout.volume().min),
      finest_spacing_(layout.spacing(0)),
      level_scale_{},
      cells_{},
      accessor_(cache) {
  if (channels < 1 || channels > CachedBrick::kMaxChannels) {
    throw std::invalid_argument("TextureSampler: channels = " + std::to_string(channels) +
                                " must be in [1, " + std::to_string(CachedBrick::kMaxChannels) +
                                "]");
  }
  for (int level = 0; level <= coarsest_level_; ++level) {
    const auto l = static_cast<std::size_t>(level);
    level_scale_[l] = std::ldexp(1.0, -level);
    cells_[l] = static_cast<double>(layout.cells_per_axis(level));
  }
}

TextureSampler::Location TextureSampler::locate(const glm::dvec3& u0, int level) const {
  const auto l = static_cast<std::size_t>(level);
  const double scale = level_scale_[l];
  const double cells = cells_[l];
  const int last_cell = static_cast<int>(cells) - 1;
  Location location;
  for (int axis = 0; axis < 3; ++axis) {
    double u = u0[axis] * scale;
    u = u >= 0.0 ? std::min(u, cells) : 0.0;  // NaN and negatives to 0, before any int cast
    const int i = std::min(static_cast<int>(std::floor(u)), last_cell);
    location.frac[axis] = static_cast<float>(u - i);  // 1 on the far face of the volume
    location.brick[axis] = i >> brick_shift_;
    location.cell[axis] = i & brick_mask_;
  }
  return location;
}

BrickKey TextureSampler::brick_key(const glm::dvec3& p, int level) const {
  level = std::clamp(level, 0, coarsest_level_);
  return BrickKey{texture_, level, locate((p - min_) / finest_spacing_, level).brick};
}

int TextureSampler::sample_level(const glm::dvec3& u0, int level, bool nearest, float* out,
                                 bool& missing, MissedBricks* missed) {
  for (int l = level; l <= coarsest_level_; ++l) {
    const Location location = locate(u0, l);
    const BrickKey key{texture_, l, location.brick};
    const CachedBrick* brick = accessor_.find(key);
    // A brick of another shape under this key would be read out of bounds: treat it as
    // absent (keys are content-addressed, so this is a caller's mistake).
    if (brick != nullptr && brick->channels() == channels_ &&
        brick->brick_size() == brick_mask_ + 1) {
      if (nearest) {
        brick->nearest(location.cell, location.frac, out);
      } else {
        brick->trilinear(location.cell, location.frac, out);
      }
      return l;
    }
    if (l == level) {
      missing = true;
      if (missed != nullptr) missed->add(key);
    }
  }
  // Not even the coarsest level: ask for it too, it is the fallback of everything.
  if (missed != nullptr) missed->add(BrickKey{texture_, coarsest_level_, glm::ivec3(0)});
  std::fill(out, out + CachedBrick::kMaxChannels, 0.0f);
  return -1;
}

SampleResult TextureSampler::sample(const glm::dvec3& p, double lod, SampleFilter filter,
                                    MissedBricks* missed) {
  if (missed != nullptr) missed->count = 0;
  const auto coarsest = static_cast<double>(coarsest_level_);
  if (!(lod >= 0.0)) lod = std::isnan(lod) ? coarsest : 0.0;
  lod = std::min(lod, coarsest);
  // Level 0 coordinates once; each level scales them by a power of two (exact).
  const glm::dvec3 u0 = (p - min_) / finest_spacing_;

  SampleResult result{};
  bool missing = false;
  if (filter != SampleFilter::quadrilinear) {
    const int level = std::min(static_cast<int>(std::floor(lod + 0.5)), coarsest_level_);
    result.level = sample_level(u0, level, filter == SampleFilter::nearest, result.values.data(),
                                missing, missed);
    result.complete = !missing;
    return result;
  }

  const int fine = static_cast<int>(std::floor(lod));
  const auto t = static_cast<float>(lod - fine);
  result.level = sample_level(u0, fine, false, result.values.data(), missing, missed);
  if (t > 0.0f && fine < coarsest_level_) {
    std::array<float, CachedBrick::kMaxChannels> coarse{};
    sample_level(u0, fine + 1, false, coarse.data(), missing, missed);
    for (int c = 0; c < channels_; ++c) {
      const auto i = static_cast<std::size_t>(c);
      result.values[i] += t * (coarse[i] - result.values[i]);
    }
  }
  result.complete = !missing;
  return result;
}

}  // namespace soltex
