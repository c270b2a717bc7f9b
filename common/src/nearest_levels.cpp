// Runtime dispatch of nearest_levels (nearest_levels.h). Highway compiles this file once per
// target (hwy/foreach_target.h re-includes it); HWY_EXPORT builds the table of per-target
// functions and HWY_DYNAMIC_DISPATCH calls the best one for the CPU.
#include "nearest_levels.h"

#include <algorithm>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "nearest_levels.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace soltex::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// One vector of footprints' levels. Their bits compare as signed integers: a non-negative
// footprint's bits, +inf's included, are at most 0x7f800000, below INT32_MAX; NaN and
// negative footprints, whose bits would not order, take their own levels by select.
template <class D, class V>
HWY_INLINE V levels_of(D d, const V (&thresholds)[NearestLevelSteps::kCount],
                       const NearestLevelSteps& steps, V bits) {
  // The base level plus the thresholds at or below the bits: all of them, less each above.
  auto level = hn::Set(d, steps.base_level + static_cast<int32_t>(NearestLevelSteps::kCount));
  for (const V& threshold : thresholds) {
    level = hn::Add(level, hn::VecFromMask(d, hn::Gt(threshold, bits)));  // true: -1
  }
  const auto magnitude = hn::And(bits, hn::Set(d, 0x7fffffff));
  const auto nan = hn::Gt(magnitude, hn::Set(d, 0x7f800000));
  const auto negative = hn::Lt(bits, hn::Zero(d));
  level = hn::IfThenElse(negative, hn::Set(d, steps.non_positive_level), level);
  return hn::IfThenElse(nan, hn::Set(d, steps.nan_level), level);
}

void NearestLevelsKernel(const NearestLevelSteps& steps, const float* footprints, std::size_t n,
                         int32_t* levels) {
  const hn::ScalableTag<int32_t> d;
  const hn::Rebind<float, decltype(d)> df;
  using V = hn::Vec<decltype(d)>;
  // An array of vectors: not possible with SVE's sizeless vectors, which the build disables.
  V thresholds[NearestLevelSteps::kCount];
  for (std::size_t k = 0; k < NearestLevelSteps::kCount; ++k) {
    thresholds[k] = hn::Set(d, steps.thresholds[k]);
  }
  const std::size_t lanes = hn::Lanes(d);
  std::size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    const V bits = hn::BitCast(d, hn::LoadU(df, footprints + i));
    hn::StoreU(levels_of(d, thresholds, steps, bits), d, levels + i);
  }
  if (i == n) return;
  if (n >= lanes) {
    // The last whole vector, ending at n: the lanes before i again, with the same levels.
    // Copied into a buffer of our own, the part vector was read back before its stores had
    // landed, and waited for them.
    const std::size_t last = n - lanes;
    const V bits = hn::BitCast(d, hn::LoadU(df, footprints + last));
    hn::StoreU(levels_of(d, thresholds, steps, bits), d, levels + last);
    return;
  }
  // Fewer than a vector: through a whole one of our own, since reading past the caller's
  // footprints could leave their allocation.
  constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(int32_t);
  HWY_ALIGN float part[kMaxLanes] = {};
  HWY_ALIGN int32_t out[kMaxLanes];
  std::copy(footprints + i, footprints + n, part);
  hn::Store(levels_of(d, thresholds, steps, hn::BitCast(d, hn::Load(df, part))), d, out);
  std::copy_n(out, n - i, levels + i);
}

int64_t TargetOfNearestLevels() {
  return HWY_TARGET;
}

}  // namespace soltex::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex {

HWY_EXPORT(NearestLevelsKernel);
HWY_EXPORT(TargetOfNearestLevels);

void nearest_levels(const NearestLevelSteps& steps, const float* footprints, std::size_t n,
                    int32_t* levels) {
  HWY_DYNAMIC_DISPATCH(NearestLevelsKernel)(steps, footprints, n, levels);
}

int64_t nearest_levels_compiled_targets() {
  return HWY_TARGETS;
}

int64_t nearest_levels_dispatched_target() {
  return HWY_DYNAMIC_DISPATCH(TargetOfNearestLevels)();
}

}  // namespace soltex
#endif
