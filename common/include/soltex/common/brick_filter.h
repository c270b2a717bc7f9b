#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

// Predictive filters for quantized brick planes. A filter replaces every sample by its
// difference (mod 256) from a prediction made of neighbours that come earlier in x-fastest
// order, so smooth fields become small residuals that a compressor codes tightly.
//
// With a, b, c the x-1, y-1, z-1 neighbours (and ab, ... the diagonal ones), samples outside
// the plane reading as 0:
//   delta_x      residual = s - a
//   gradient_xy  residual = s - (a + b - ab)                            (2D gradient)
//   gradient_3d  residual = s - (a + b + c - ab - ac - bc + abc)        (3D Lorenzo)
// Each is a product of backward differences along its axes. Those commute, so a filter is
// applied axis by axis over whole rows and slabs (which vectorizes), and undone by prefix sums
// along the same axes.
namespace soltex {

// Stored in the encoded brick header: never renumber.
enum class BrickFilter : uint8_t { none = 0, delta_x = 1, gradient_xy = 2, gradient_3d = 3 };

inline constexpr uint8_t kMaxBrickFilterId = 3;

const char* brick_filter_name(BrickFilter filter);

// Filters or unfilters, in place, every plane of `planes`: each plane holds side^3 samples,
// x fastest. Throws std::invalid_argument unless side is in [1, 17] (a brick of size 16 has 17
// samples per axis) and planes.size() is a multiple of side^3.
void apply_brick_filter(BrickFilter filter, int side, std::span<uint8_t> planes);
void undo_brick_filter(BrickFilter filter, int side, std::span<uint8_t> planes);

// Bytes past the samples that quantize_and_predict() may write (whole vectors).
inline constexpr std::size_t kQuantizePredictSlack = 256;

// quantize() then apply_brick_filter(gradient_3d), fused into one pass over each slab: the
// server's encoder. `samples` holds planes of side^3 floats; `quantized` receives quantize()
// of each (what the checksum covers), `residual` the predictor's output. Both must hold
// samples.size() + kQuantizePredictSlack bytes. SIMD with runtime dispatch; every target gives
// the bits of the scalar functions. Throws std::invalid_argument as apply_brick_filter() does,
// and for outputs that are too small.
void quantize_and_predict(std::span<const float> samples, int side, std::span<uint8_t> quantized,
                          std::span<uint8_t> residual);

// quantize(float) over a span, vectorized: out.size() >= values.size().
void quantize_values(std::span<const float> values, std::span<uint8_t> out);

// The SIMD targets (Highway's HWY_* bits) compiled for these kernels that this CPU runs: for
// tests that run each one with hwy::SetSupportedTargetsForTest().
std::vector<int64_t> brick_filter_targets();

}  // namespace soltex
