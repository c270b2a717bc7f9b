// Runtime dispatch of interleave_channels (channel_interleave.h). Highway compiles this file
// once per target (hwy/foreach_target.h re-includes it); HWY_EXPORT builds the table of
// per-target functions and HWY_DYNAMIC_DISPATCH calls the best one for the CPU.
#include "channel_interleave.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "channel_interleave.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace soltex::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void InterleaveChannelsKernel(const uint8_t* planar, std::size_t plane, int channels,
                              uint8_t* out) {
  std::size_t i = 0;
  if (channels == 3) {
    // RGB, every brick of the default scenes: three planes in, whole vectors out.
    const hn::ScalableTag<uint8_t> d;
    const std::size_t lanes = hn::Lanes(d);
    for (; i + lanes <= plane; i += lanes) {
      hn::StoreInterleaved3(hn::LoadU(d, planar + i), hn::LoadU(d, planar + plane + i),
                            hn::LoadU(d, planar + 2 * plane + i), d, out + 3 * i);
    }
  }
  const auto c_count = static_cast<std::size_t>(channels);
  for (; i < plane; ++i) {
    for (std::size_t c = 0; c < c_count; ++c) out[i * c_count + c] = planar[c * plane + i];
  }
}

int64_t TargetOfInterleave() {
  return HWY_TARGET;
}

}  // namespace soltex::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex {

HWY_EXPORT(InterleaveChannelsKernel);
HWY_EXPORT(TargetOfInterleave);

void interleave_channels(const uint8_t* planar, std::size_t plane, int channels, uint8_t* out) {
  HWY_DYNAMIC_DISPATCH(InterleaveChannelsKernel)(planar, plane, channels, out);
}

int64_t interleave_compiled_targets() {
  return HWY_TARGETS;
}

int64_t interleave_dispatched_target() {
  return HWY_DYNAMIC_DISPATCH(TargetOfInterleave)();
}

}  // namespace soltex
#endif  // HWY_ONCE
