#pragma once

#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "soltex/common/texture_spec.h"

// Sums of noise octaves (turbulence, fBm), band-limited to a filter width.
//
// Octave k has frequency f_k = scale * 2^k lattice cells per texture unit and weight (1/2)^k.
// Sampled with spacing w (the filter width), it is representable only while its lattice
// spacing 1/f_k spans about two samples or more. Its visibility is
//     alpha_k = 1 - smoothstep(0.25, 0.5, f_k * w),
// and the octave contributes (1/2)^k * (alpha_k * noise + (1 - alpha_k) * mean): fully present
// up to four samples per cell, gone at the Nyquist limit of two, replaced by the basis mean.
// An octave with alpha_k = 0 is not evaluated at all. See docs/TEXTURES.md for the sources.
namespace soltex {

// Mean of |gradient noise| over space: 0.22035, measured over 2^24 uniform random points in
// one period (the fractal test re-measures it).
inline constexpr float kGradientAbsMean = 0.2204f;
// The variance of one octave over space, per basis, measured the same way over 2^22 points
// (the fractal test re-measures them): value noise, signed gradient noise, |gradient| noise.
inline constexpr float kValueNoiseVariance = 0.02393f;
inline constexpr float kGradientVariance = 0.07299f;
inline constexpr float kGradientAbsVariance = 0.02440f;

struct Octave {
  double frequency;    // lattice cells per texture unit
  float noise_weight;  // (1/2)^k * alpha_k
  float mean_term;     // (1/2)^k * (1 - alpha_k) * basis mean
};

// The octaves of one fractal for one filter width: computed once per brick or frame.
struct OctavePlan {
  NoiseBasis basis = NoiseBasis::value;
  bool absolute = true;  // fold each octave with |.| (gradient basis only)
  int count = 0;
  std::array<Octave, SpecLimits::kMaxOctaveCount> octaves{};
  float total_weight = 0.0f;  // sum of (1/2)^k: the largest possible raw sum for value noise
  // The variance, in raw-sum units, of what the faded octaves leave out: each contributes
  // (1/2)^k (1 - alpha_k) (noise - mean), taken as independent. A box of the filter's width
  // holds that much variation that the sum at its centre does not show; the colour ramp is
  // averaged over it (fields::fractal_spread).
  double unresolved_variance = 0.0;
  // The octaves again, one array per field and zero-padded past `count`, for the single-point
  // kernel, which loads them as vectors (one octave per lane).
  static constexpr int kLaneRoom = 2 * SpecLimits::kMaxOctaveCount;
  alignas(64) std::array<double, kLaneRoom> lane_frequency{};
  alignas(64) std::array<float, kLaneRoom> lane_noise_weight{};
  alignas(64) std::array<float, kLaneRoom> lane_mean_term{};
  int evaluated_octaves() const;  // octaves with a nonzero noise weight
  // Appends one octave to both layouts and its faded part to unresolved_variance; `weight` is
  // its (1/2)^k before fading. Every plan is built through it (after `basis` and `absolute`
  // are set), so the per-lane copies never disagree with `octaves`.
  void add(const Octave& octave, float weight);
};

// An octave's visibility alpha_k for f_k * w given as `cells_per_sample`:
// 1 - smoothstep(0.25, 0.5, cells_per_sample). Every fractal, built-in or graph, fades by it.
float octave_visibility(float cells_per_sample) noexcept;

// The mean a faded octave is replaced by: value noise's table mean, |gradient| noise's
// measured mean, or 0 for signed gradient noise.
float basis_mean(NoiseBasis basis, bool absolute) noexcept;
// The variance of one octave of the basis (the constants above).
float basis_variance(NoiseBasis basis, bool absolute) noexcept;

// filter_width = 0 means point sampling: every octave is fully present.
OctavePlan plan_octaves(const FractalParams& params, double filter_width);

// The raw sum at one point.
float fractal_sum(const OctavePlan& plan, const glm::dvec3& p) noexcept;

// Fractal sums over rows of points that share their x coordinates (every row of a grid).
// The x half of the work — lattice cells, fractions, and per octave the list of lattice x-faces
// the points' cells touch — is done once here; sum() then evaluates, per row and octave, the
// y-z noise once per face and the finish once per point, in vector kernels chosen at run time
// for the CPU (common/src/noise_kernels.h). The results equal fractal_sum at (x[i], y, z) bit
// for bit on every target.
//
// sum_rows() evaluates up to `rows_at_once` rows in one call with their points end to end in
// the vector lanes: a brick's row of 17 points fills one vector of 16 and one lane of the next,
// and a whole plane of rows at once wastes no more than the last vector's tail.
class FractalRows {
 public:
  FractalRows(const OctavePlan& plan, std::span<const double> x, std::size_t rows_at_once = 1);

  std::size_t size() const { return size_; }

  // out[i] = fractal_sum(plan, (x[i], y, z)); out.size() must be at least size().
  void sum(double y, double z, std::span<float> out) const;

  // out[r * size() + i] = fractal_sum(plan, (x[i], y[r], z[r])) for r < y.size(), which must
  // be at most rows_at_once and equal z.size(); out.size() at least y.size() * size().
  void sum_rows(std::span<const double> y, std::span<const double> z, std::span<float> out) const;

 private:
  // Arrays padded with valid entries to the widest vector (see noise_kernels.h).
  struct OctaveColumns {
    std::vector<float> frac;       // per point: x fraction
    std::vector<int32_t> face_lo;  // per point: its cell's left face; the right one is next
    std::vector<int32_t> face_x;   // per face: lattice x in [0, 256]
    std::size_t faces = 0;         // unpadded face count
    // The same for rows_at_once rows end to end: row r's points read faces r * faces on.
    std::vector<float> rows_frac;
    std::vector<int32_t> rows_face_lo;
  };

  void pack_rows(OctaveColumns& columns) const;

  OctavePlan plan_;
  std::size_t size_;
  std::size_t rows_at_once_;
  std::vector<OctaveColumns> octaves_;
};

// One row's sum without keeping the x work: FractalRows(plan, x).sum(y, z, out).
void fractal_sum_row(const OctavePlan& plan, std::span<const double> x, double y, double z,
                     std::span<float> out);

// One octave of a basis at lattice-unit point t (no scaling, no weight).
float basis_noise(NoiseBasis basis, const glm::dvec3& t) noexcept;

}  // namespace soltex
