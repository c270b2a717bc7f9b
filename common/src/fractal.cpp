#include "soltex/common/fractal.h"

#include <algorithm>
#include <cmath>

#include "noise_kernels.h"
#include "soltex/common/check.h"
#include "soltex/common/gradient_noise.h"
#include "soltex/common/value_noise.h"

namespace soltex {

float octave_visibility(float cells_per_sample) noexcept {
  const float t = std::clamp((cells_per_sample - 0.25f) / (0.5f - 0.25f), 0.0f, 1.0f);
  return 1.0f - t * t * (3.0f - 2.0f * t);
}

float basis_mean(NoiseBasis basis, bool absolute) noexcept {
  if (basis == NoiseBasis::value) return noise_tables().value_mean;
  return absolute ? kGradientAbsMean : 0.0f;
}

float basis_variance(NoiseBasis basis, bool absolute) noexcept {
  if (basis == NoiseBasis::value) return kValueNoiseVariance;
  return absolute ? kGradientAbsVariance : kGradientVariance;
}

int OctavePlan::evaluated_octaves() const {
  int n = 0;
  for (int k = 0; k < count; ++k) n += octaves[k].noise_weight != 0.0f ? 1 : 0;
  return n;
}

OctavePlan plan_octaves(const FractalParams& params, double filter_width) {
  OctavePlan plan;
  plan.basis = params.basis;
  plan.absolute = params.basis == NoiseBasis::gradient && !params.signed_octaves;
  const float mean = basis_mean(plan.basis, plan.absolute);
  const double width = std::isfinite(filter_width) ? std::max(filter_width, 0.0) : 0.0;
  for (int k = params.octave_min;
       k <= params.octave_max && plan.count < SpecLimits::kMaxOctaveCount; ++k) {
    // Exact powers of two, as ldexp gives them, without a libm call per octave: a per-pixel
    // reference plans the octaves at every pixel.
    const bool small = k >= 0 && k <= SpecLimits::kMaxOctave;
    const double frequency =
        small ? params.scale * static_cast<double>(uint32_t{1} << k) : std::ldexp(params.scale, k);
    const float weight = small ? 1.0f / static_cast<float>(uint32_t{1} << k) : std::ldexp(1.0f, -k);
    const float alpha = octave_visibility(static_cast<float>(frequency * width));
    plan.add({frequency, weight * alpha, weight * (1.0f - alpha) * mean}, weight);
  }
  return plan;
}

void OctavePlan::add(const Octave& octave, float weight) {
  SOLTEX_DCHECK(count < SpecLimits::kMaxOctaveCount);
  lane_frequency[count] = octave.frequency;
  lane_noise_weight[count] = octave.noise_weight;
  lane_mean_term[count] = octave.mean_term;
  octaves[count++] = octave;
  total_weight += weight;
  const double left_out = static_cast<double>(weight) - static_cast<double>(octave.noise_weight);
  unresolved_variance += left_out * left_out * static_cast<double>(basis_variance(basis, absolute));
}

float basis_noise(NoiseBasis basis, const glm::dvec3& t) noexcept {
  return basis == NoiseBasis::value ? value_noise(t) : gradient_noise(t);
}

// One octave per vector lane in the gradient basis (noise_kernels.cpp), the terms added in
// octave order as the loop of value_fractal_sum does; both compiled for the CPU's target.
float fractal_sum(const OctavePlan& plan, const glm::dvec3& p) noexcept {
  return noise_kernels::fractal_sum_point(plan, p);
}

FractalRows::FractalRows(const OctavePlan& plan, std::span<const double> x,
                         std::size_t rows_at_once)
    : plan_(plan),
      size_(x.size()),
      rows_at_once_(std::max<std::size_t>(rows_at_once, 1)),
      octaves_(static_cast<std::size_t>(plan.count)) {
  const std::size_t points = noise_kernels::padded(size_);
  for (int k = 0; k < plan_.count; ++k) {
    OctaveColumns& columns = octaves_[static_cast<std::size_t>(k)];
    if (plan_.octaves[k].noise_weight == 0.0f || size_ == 0) continue;  // no noise to evaluate
    const double frequency = plan_.octaves[k].frequency;
    columns.frac.assign(points, 0.0f);
    columns.face_lo.assign(points, 0);
    // Each cell contributes its left face (unless the previous point's cell ended on it) and
    // its right face, so a point's right face always directly follows its left one.
    int previous_cell = -1;
    for (std::size_t i = 0; i < size_; ++i) {
      const LatticeSplit split = split_lattice(x[i] * frequency);
      columns.frac[i] = split.frac;
      if (split.cell == previous_cell) {
        columns.face_lo[i] = columns.face_lo[i - 1];
        continue;
      }
      previous_cell = split.cell;
      if (columns.face_x.empty() || columns.face_x.back() != split.cell) {
        columns.face_x.push_back(split.cell);
      }
      columns.face_lo[i] = static_cast<int32_t>(columns.face_x.size() - 1);
      columns.face_x.push_back(split.cell + 1);
    }
    // Padding points repeat the last point's faces, so that a final partial vector still
    // finds its faces by lane lookup rather than by gather.
    std::fill(columns.face_lo.begin() + static_cast<std::ptrdiff_t>(size_), columns.face_lo.end(),
              columns.face_lo[size_ - 1]);
    columns.faces = columns.face_x.size();
    // Padding continues the last face's x (up to 256, the table's reach) so that a final
    // partial vector of consecutive faces still loads its hashes contiguously.
    while (columns.face_x.size() < noise_kernels::padded(columns.faces)) {
      columns.face_x.push_back(std::min(columns.face_x.back() + 1, kLatticePeriod));
    }
    if (rows_at_once_ > 1) pack_rows(columns);
  }
}

void FractalRows::pack_rows(OctaveColumns& columns) const {
  const std::size_t points = size_ * rows_at_once_;
  columns.rows_frac.resize(noise_kernels::padded(points));
  columns.rows_face_lo.resize(noise_kernels::padded(points));
  for (std::size_t r = 0; r < rows_at_once_; ++r) {
    const auto offset = static_cast<int32_t>(r * columns.faces);
    for (std::size_t i = 0; i < size_; ++i) {
      columns.rows_frac[r * size_ + i] = columns.frac[i];
      columns.rows_face_lo[r * size_ + i] = columns.face_lo[i] + offset;
    }
  }
  // As in one row: padding repeats the last point, so a final partial vector stays local.
  std::fill(columns.rows_frac.begin() + static_cast<std::ptrdiff_t>(points),
            columns.rows_frac.end(), columns.rows_frac[points - 1]);
  std::fill(columns.rows_face_lo.begin() + static_cast<std::ptrdiff_t>(points),
            columns.rows_face_lo.end(), columns.rows_face_lo[points - 1]);
}

void FractalRows::sum(double y, double z, std::span<float> out) const {
  SOLTEX_DCHECK(out.size() >= size_);
  // Only the plan's octaves are set and read: zeroing all 16 was a 512-byte memset per row.
  std::array<noise_kernels::OctaveColumnsView, SpecLimits::kMaxOctaveCount> views;
  for (std::size_t k = 0; k < octaves_.size(); ++k) {
    const OctaveColumns& c = octaves_[k];
    views[k] = {c.frac.data(), c.face_lo.data(), c.face_x.data(), c.faces};
  }
  noise_kernels::fractal_row({&plan_, views.data(), size_, y, z, out.data()});
}

void FractalRows::sum_rows(std::span<const double> y, std::span<const double> z,
                           std::span<float> out) const {
  SOLTEX_DCHECK(y.size() == z.size() && y.size() <= rows_at_once_);
  SOLTEX_DCHECK(out.size() >= y.size() * size_);
  if (y.size() == 1 || rows_at_once_ == 1) {
    for (std::size_t r = 0; r < y.size(); ++r) sum(y[r], z[r], out.subspan(r * size_, size_));
    return;
  }
  std::array<noise_kernels::OctaveColumnsView, SpecLimits::kMaxOctaveCount> views;
  for (std::size_t k = 0; k < octaves_.size(); ++k) {
    const OctaveColumns& c = octaves_[k];
    views[k] = {c.rows_frac.data(), c.rows_face_lo.data(), c.face_x.data(), c.faces};
  }
  noise_kernels::fractal_rows(
      {&plan_, views.data(), size_, y.size(), y.data(), z.data(), out.data()});
}

void fractal_sum_row(const OctavePlan& plan, std::span<const double> x, double y, double z,
                     std::span<float> out) {
  FractalRows(plan, x).sum(y, z, out);
}

}  // namespace soltex
