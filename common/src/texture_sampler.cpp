#include "soltex/common/texture_sampler.h"

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "nearest_levels.h"
#include "soltex/common/check.h"

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

int NearestLevelTable::level_by_formula(const BrickLayout& layout, double bias, float footprint) {
  const double coarsest = static_cast<double>(layout.coarsest_level());
  const double lod = level_of_detail(layout, footprint) + bias;
  if (!(lod >= 0.0)) return std::isnan(lod) ? layout.coarsest_level() : 0;
  return static_cast<int>(std::min(lod, coarsest) + 0.5);
}

NearestLevelTable::NearestLevelTable(const BrickLayout& layout, double bias) {
  const auto level_at = [&](uint32_t bits) {
    return level_by_formula(layout, bias, std::bit_cast<float>(bits));
  };
  constexpr uint32_t kInfinityBits = 0x7f800000u;
  base_level_ = level_at(0);
  nan_level_ = level_by_formula(layout, bias, std::numeric_limits<float>::quiet_NaN());
  non_positive_level_ = level_by_formula(layout, bias, -1.0f);
  const int top = level_at(kInfinityBits);
  thresholds_.fill(std::numeric_limits<int32_t>::max());
  for (int k = 0; k < top - base_level_; ++k) {
    // The smallest bits in (0, +inf] whose level exceeds base_level_ + k.
    uint32_t low = 0, high = kInfinityBits;  // level(low) <= base + k < level(high)
    while (high - low > 1) {
      const uint32_t middle = low + (high - low) / 2;
      if (level_at(middle) > base_level_ + k) {
        high = middle;
      } else {
        low = middle;
      }
    }
    thresholds_[static_cast<std::size_t>(k)] = static_cast<int32_t>(high);
  }
}

void NearestLevelTable::levels(std::span<const float> footprints, int32_t* out) const {
  // The last threshold is never at or below a footprint's bits, so the kernel leaves it out.
  static_assert(NearestLevelSteps::kCount == kThresholds - 1);
  const NearestLevelSteps steps{thresholds_.data(), base_level_, nan_level_, non_positive_level_};
  nearest_levels(steps, footprints.data(), footprints.size(), out);
}

TextureSampler::TextureSampler(BrickCache& cache, uint64_t texture, const BrickLayout& layout,
                               int channels)
    : layout_(layout),
      texture_(texture),
      channels_(channels),
      coarsest_level_(layout.coarsest_level()),
      coarsest_lod_(layout.coarsest_level()),
      brick_shift_(layout.brick_shift()),
      brick_mask_(layout.brick_size() - 1),
      y_stride_(layout.samples_per_axis() * channels),
      z_stride_(layout.samples_per_axis() * layout.samples_per_axis() * channels),
      min_(layout.volume().min),
      finest_spacing_(layout.spacing(0)),
      level_scale_{},
      cells_{},
      // Clamped: the channel count is checked below, after the members are built.
      accessor_(cache,
                BrickCache::Accessor::set_bits_for(
                    layout.brick_size(), std::clamp(channels, 1, CachedBrick::kMaxChannels))),
      remembered_(std::size_t{1} << kRememberedBits),
      last_{&remembered_[0], &remembered_[0]} {
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

void TextureSampler::sample(std::span<const glm::dvec3> points, double lod, SampleFilter filter,
                            std::span<SampleResult> results) {
  if (results.size() != points.size()) {
    throw std::invalid_argument("TextureSampler::sample: " + std::to_string(results.size()) +
                                " results for " + std::to_string(points.size()) +
                                " points; the counts must be equal");
  }
  // The same test as sample()'s fast path: other cases take it point by point.
  if (filter != SampleFilter::trilinear || channels_ != 3 || !(lod >= 0.0)) {
    for (std::size_t i = 0; i < points.size(); ++i) results[i] = sample(points[i], lod, filter);
    return;
  }
  if (points.empty()) return;
  const int level = static_cast<int>(std::min(lod, coarsest_lod_) + 0.5);
  // One chunk ahead: the next chunk's samples are on their way from memory while this one's
  // are filtered.
  const auto chunk_of = [&](std::size_t first) {
    return points.subspan(first, std::min(kSampleChunk, points.size() - first));
  };
  std::array<StagedChunk, 2> staged;
  stage_rgb_chunk(chunk_of(0), level, staged[0]);
  for (std::size_t first = 0, k = 0; first < points.size(); first += kSampleChunk, ++k) {
    const std::size_t next = first + kSampleChunk;
    if (next < points.size()) stage_rgb_chunk(chunk_of(next), level, staged[(k + 1) & 1]);
    const std::span<const glm::dvec3> chunk = chunk_of(first);
    finish_rgb_chunk(chunk, level, staged[k & 1], results.subspan(first, chunk.size()));
  }
}

namespace {

// What the trilinear kernel leaves to the batch: the fifth value, the level, completeness. They
// and values[3] (which the kernel writes after, as 0) end the result, so one 16-byte store
// starts it.
constexpr std::size_t kResultTailOffset = offsetof(SampleResult, values) + 3 * sizeof(float);
static_assert(offsetof(SampleResult, level) > kResultTailOffset &&
              offsetof(SampleResult, complete) > kResultTailOffset &&
              sizeof(SampleResult) == kResultTailOffset + 16);

std::array<std::byte, 16> result_tail(int level) {
  SampleResult result{};
  result.level = level;
  result.complete = true;
  std::array<std::byte, 16> tail;
  std::memcpy(tail.data(), reinterpret_cast<const std::byte*>(&result) + kResultTailOffset, 16);
  return tail;
}

}  // namespace

void TextureSampler::stage_rgb_chunk(std::span<const glm::dvec3> points, int level,
                                     StagedChunk& staged) {
  SOLTEX_DCHECK(!points.empty() && points.size() <= kSampleChunk);
  const auto l = static_cast<std::size_t>(level);
  CellChunk& chunk = staged.cells;
  split_cells(points, min_, finest_spacing_, level_scale_[l], cells_[l], chunk);
  const auto n = points.size();
  const int bricks = layout_.bricks_per_axis(level);
  uint64_t run_hits = 0, run_misses = 0;  // lookups a run answered, counted as resident() would
  const auto brick_of = [&](std::size_t i) {
    return glm::ivec3(chunk.cell[0][i] >> brick_shift_, chunk.cell[1][i] >> brick_shift_,
                      chunk.cell[2][i] >> brick_shift_);
  };
  const std::ptrdiff_t y_stride = y_stride_, z_stride = z_stride_;
  // The cell's rows asked for now, read a chunk later: the line of its first row in each of
  // the two z planes (measured as fast as asking for all four rows' first and last bytes).
  const auto fetch = [&](std::size_t i, const uint8_t* corner) {
    staged.corners[i] = corner;
    if (corner == nullptr) return;
    __builtin_prefetch(corner);
    __builtin_prefetch(corner + z_stride);
  };
  if (static_cast<int64_t>(bricks) * bricks * bricks <= INT32_MAX) {
    // The flat brick index in one int32 compares a run in one instruction.
    locate_cells(chunk, n, {brick_shift_, brick_mask_, bricks, 3, y_stride_, z_stride_});
    // Run by run: find where the brick changes, ask for the brick once.
    for (std::size_t first = 0; first < n;) {
      const int32_t run_brick = chunk.brick[first];
      std::size_t end = first + 1;
      while (end < n && chunk.brick[end] == run_brick) ++end;
      const Current* found = resident(level, brick_of(first));
      const auto repeats = static_cast<uint64_t>(end - first - 1);
      if (found == nullptr) {
        for (std::size_t i = first; i < end; ++i) staged.corners[i] = nullptr;
        run_misses += repeats;
      } else {
        const uint8_t* samples = found->samples;
        for (std::size_t i = first; i < end; ++i) fetch(i, samples + chunk.offset[i]);
        run_hits += repeats;
      }
      first = end;
    }
  } else {
    glm::ivec3 run_brick(-1);
    const uint8_t* run_samples = nullptr;
    for (std::size_t i = 0; i < n; ++i) {
      const glm::ivec3 brick = brick_of(i);
      if (brick == run_brick) {
        ++(run_samples == nullptr ? run_misses : run_hits);
      } else {
        const Current* found = resident(level, brick);
        run_brick = brick;
        run_samples = found == nullptr ? nullptr : found->samples;
      }
      const glm::ivec3 local(chunk.cell[0][i] & brick_mask_, chunk.cell[1][i] & brick_mask_,
                             chunk.cell[2][i] & brick_mask_);
      fetch(i, run_samples == nullptr
                   ? nullptr
                   : run_samples + local.z * z_stride + local.y * y_stride + local.x * 3);
    }
  }
  accessor_.count_microcache_hit(run_hits);
  accessor_.count_miss(run_misses);
}

void TextureSampler::finish_rgb_chunk(std::span<const glm::dvec3> points, int level,
                                      const StagedChunk& staged, std::span<SampleResult> results) {
  const auto n = points.size();
  SOLTEX_DCHECK(n >= 1 && n <= kSampleChunk && results.size() == n);
  // Never taken (sample() passes no empty chunk); it tells the compiler that the loop below
  // writes the rows the kernel reads.
  if (n == 0) return;
  const std::array<std::byte, 16> tail = result_tail(level);
  // In locals: the row stores below could alias the members, which would be read again per
  // point.
  const std::ptrdiff_t y_stride = y_stride_, z_stride = z_stride_;
  CellRows rows;
  static_assert(kSampleChunk <= 64);
  uint64_t missed = 0;  // bit i: point i's brick is not resident
  // Each result is started in the loop that reads its rows, while its line is being written.
  for (std::size_t i = 0; i < n; ++i) {
    std::memcpy(reinterpret_cast<std::byte*>(&results[i]) + kResultTailOffset, tail.data(), 16);
    if (const uint8_t* corner = staged.corners[i]) {
      rows.read(i, corner, y_stride, z_stride);
    } else {
      missed |= uint64_t{1} << i;
      for (auto& row : rows.row) row[i] = 0;
    }
  }
  static_assert(sizeof(SampleResult) % sizeof(float) == 0);
  trilinear_rgb_rows(rows, staged.cells, n, results[0].values.data(),
                     sizeof(SampleResult) / sizeof(float));
  for (; missed != 0; missed &= missed - 1) {
    const auto i = static_cast<std::size_t>(std::countr_zero(missed));
    sample_general(points[i], static_cast<double>(level), SampleFilter::trilinear, nullptr,
                   results[i]);
  }
}

BrickKey TextureSampler::brick_key(const glm::dvec3& p, int level) const {
  level = std::clamp(level, 0, coarsest_level_);
  return BrickKey{texture_, level, locate(p, level).brick};
}

template <typename Read>
int TextureSampler::walk_levels(const glm::dvec3& p, int level, bool& missing, MissedBricks* missed,
                                Read&& read) {
  if (accessor_.insertions() == 0) {
    // Nothing was ever inserted (a client's first frame): every level misses, so skip the
    // walk, which would locate the point at each level only to find that out, and report what
    // the walk would.
    accessor_.count_miss(static_cast<uint64_t>(std::max(0, coarsest_level_ - level + 1)));
    missing = true;
    if (missed != nullptr) {
      missed->add(BrickKey{texture_, level, locate(p, level).brick});
      missed->add(BrickKey{texture_, coarsest_level_, glm::ivec3(0)});
    }
    return -1;
  }
  for (int l = level; l <= coarsest_level_; ++l) {
    const Location location = locate(p, l);
    if (const Current* brick = resident(l, location.brick)) {
      read(*brick, location);
      return l;
    }
    if (l == level) {
      missing = true;
      if (missed != nullptr) missed->add(BrickKey{texture_, l, location.brick});
    }
  }
  // Not even the coarsest level: ask for it too, it is the fallback of everything.
  if (missed != nullptr) missed->add(BrickKey{texture_, coarsest_level_, glm::ivec3(0)});
  return -1;
}

int TextureSampler::sample_level(const glm::dvec3& p, int level, bool nearest, float* out,
                                 bool& missing, MissedBricks* missed) {
  const int found =
      walk_levels(p, level, missing, missed, [&](const Current& brick, const Location& at) {
        if (nearest) {
          brick.data->nearest(at.cell, at.frac, out);
        } else {
          brick.data->trilinear(at.cell, at.frac, out);
        }
      });
  if (found < 0) std::fill(out, out + CachedBrick::kMaxChannels, 0.0f);
  return found;
}

void TextureSampler::sample_general(const glm::dvec3& p, double lod, SampleFilter filter,
                                    MissedBricks* missed, SampleResult& result) {
  if (missed != nullptr) missed->count = 0;
  lod = clamped_lod(lod);
  result = SampleResult{};
  bool missing = false;
  if (filter != SampleFilter::quadrilinear) {
    const int level = static_cast<int>(lod + 0.5);  // lod >= 0: the nearest level
    result.level = sample_level(p, level, filter == SampleFilter::nearest, result.values.data(),
                                missing, missed);
    result.complete = !missing;
    return;
  }

  const int fine = static_cast<int>(lod);  // lod >= 0: truncation is floor
  const auto t = static_cast<float>(lod - fine);
  result.level = sample_level(p, fine, false, result.values.data(), missing, missed);
  if (t > 0.0f && fine < coarsest_level_) {
    std::array<float, CachedBrick::kMaxChannels> coarse{};
    sample_level(p, fine + 1, false, coarse.data(), missing, missed);
    for (int c = 0; c < channels_; ++c) {
      const auto i = static_cast<std::size_t>(c);
      result.values[i] += t * (coarse[i] - result.values[i]);
    }
  }
  result.complete = !missing;
}

SampleResult TextureSampler::find_misses(const glm::dvec3& p, double lod, SampleFilter filter,
                                         MissedBricks* missed) {
  if (missed != nullptr) missed->count = 0;
  lod = clamped_lod(lod);
  SampleResult result{};
  bool missing = false;
  const auto no_read = [](const Current&, const Location&) {};
  if (filter != SampleFilter::quadrilinear) {
    result.level = walk_levels(p, static_cast<int>(lod + 0.5), missing, missed, no_read);
  } else {
    // As sample_general(): the coarser level only where its weight is above zero.
    const int fine = static_cast<int>(lod);
    result.level = walk_levels(p, fine, missing, missed, no_read);
    if (static_cast<float>(lod - fine) > 0.0f && fine < coarsest_level_) {
      walk_levels(p, fine + 1, missing, missed, no_read);
    }
  }
  result.complete = !missing;
  return result;
}

}  // namespace soltex
