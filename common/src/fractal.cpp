#include "soltex/common/fractal.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "soltex/common/gradient_noise.h"
#include "soltex/common/value_noise.h"

namespace soltex {
namespace {

float smoothstep(float lo, float hi, float x) {
  const float t = std::clamp((x - lo) / (hi - lo), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

float basis_mean(const OctavePlan& plan) {
  if (plan.basis == NoiseBasis::value) return noise_tables().value_mean;
  return plan.absolute ? kGradientAbsMean : 0.0f;
}

// One octave's contribution, the same expression in the point and row paths.
inline float octave_term(const Octave& octave, float noise) {
  return octave.noise_weight * noise + octave.mean_term;
}

// Per-row scratch: lattice cells and fractions of the x coordinates.
struct RowScratch {
  std::vector<int> cell;
  std::vector<float> frac;
};

RowScratch& row_scratch(std::size_t n) {
  thread_local RowScratch scratch;
  if (scratch.cell.size() < n) {
    scratch.cell.resize(n);
    scratch.frac.resize(n);
  }
  return scratch;
}

// Calls emit(i, noise) for every x[i]; cells are walked in runs so that the corner work of a
// cell is done once per run. Edges and finish are the value or gradient cell functions.
template <typename Edges, typename Finish, typename Emit>
inline void for_each_noise(std::span<const double> x, double frequency, double y, double z,
                           Edges edges_of, Finish finish, Emit emit) {
  const std::size_t n = x.size();
  RowScratch& scratch = row_scratch(n);
  int* cell = scratch.cell.data();
  float* frac = scratch.frac.data();
  for (std::size_t i = 0; i < n; ++i) {
    const LatticeSplit split = split_lattice(x[i] * frequency);
    cell[i] = split.cell;
    frac[i] = split.frac;
  }
  const LatticeSplit sy = split_lattice(y * frequency);
  const LatticeSplit sz = split_lattice(z * frequency);
  std::size_t begin = 0;
  while (begin < n) {
    std::size_t end = begin + 1;
    while (end < n && cell[end] == cell[begin]) ++end;
    const auto edges = edges_of(cell[begin], sy, sz);
    for (std::size_t i = begin; i < end; ++i) emit(i, finish(edges, frac[i]));
    begin = end;
  }
}

template <typename Emit>
inline void dispatch_basis(NoiseBasis basis, std::span<const double> x, double frequency, double y,
                           double z, Emit emit) {
  const NoiseTables& tables = noise_tables();
  if (basis == NoiseBasis::value) {
    for_each_noise(
        x, frequency, y, z,
        [&](int ix, const LatticeSplit& sy, const LatticeSplit& sz) {
          return value_cell_edges(tables, ix, sy, sz);
        },
        value_cell_finish, emit);
  } else {
    for_each_noise(
        x, frequency, y, z,
        [&](int ix, const LatticeSplit& sy, const LatticeSplit& sz) {
          return gradient_cell_edges(tables, ix, sy, sz);
        },
        gradient_cell_finish, emit);
  }
}

}  // namespace

int OctavePlan::evaluated_octaves() const {
  int n = 0;
  for (int k = 0; k < count; ++k) n += octaves[k].noise_weight != 0.0f ? 1 : 0;
  return n;
}

OctavePlan plan_octaves(const FractalParams& params, double filter_width) {
  OctavePlan plan;
  plan.basis = params.basis;
  plan.absolute = params.basis == NoiseBasis::gradient && !params.signed_octaves;
  const float mean = basis_mean(plan);
  const double width = std::isfinite(filter_width) ? std::max(filter_width, 0.0) : 0.0;
  for (int k = params.octave_min;
       k <= params.octave_max && plan.count < SpecLimits::kMaxOctaveCount; ++k) {
    const double frequency = std::ldexp(params.scale, k);
    const float weight = std::ldexp(1.0f, -k);
    const float alpha = 1.0f - smoothstep(0.25f, 0.5f, static_cast<float>(frequency * width));
    plan.octaves[plan.count++] = {frequency, weight * alpha, weight * (1.0f - alpha) * mean};
    plan.total_weight += weight;
  }
  return plan;
}

float basis_noise(NoiseBasis basis, const glm::dvec3& t) noexcept {
  return basis == NoiseBasis::value ? value_noise(t) : gradient_noise(t);
}

float fractal_sum(const OctavePlan& plan, const glm::dvec3& p) noexcept {
  float sum = 0.0f;
  for (int k = 0; k < plan.count; ++k) {
    const Octave& octave = plan.octaves[k];
    if (octave.noise_weight == 0.0f) {
      sum += octave.mean_term;
      continue;
    }
    float noise = basis_noise(plan.basis, p * octave.frequency);
    if (plan.absolute) noise = std::fabs(noise);
    sum += octave_term(octave, noise);
  }
  return sum;
}

void fractal_sum_row(const OctavePlan& plan, std::span<const double> x, double y, double z,
                     std::span<float> out) {
  std::fill(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(x.size()), 0.0f);
  float* acc = out.data();
  for (int k = 0; k < plan.count; ++k) {
    const Octave& octave = plan.octaves[k];
    if (octave.noise_weight == 0.0f) {
      for (std::size_t i = 0; i < x.size(); ++i) acc[i] += octave.mean_term;
      continue;
    }
    if (plan.absolute) {
      dispatch_basis(plan.basis, x, octave.frequency, y, z, [&](std::size_t i, float noise) {
        acc[i] += octave_term(octave, std::fabs(noise));
      });
    } else {
      dispatch_basis(plan.basis, x, octave.frequency, y, z,
                     [&](std::size_t i, float noise) { acc[i] += octave_term(octave, noise); });
    }
  }
}

void noise_row(NoiseBasis basis, std::span<const double> x, double y, double z, double frequency,
               std::span<float> out) {
  float* acc = out.data();
  dispatch_basis(basis, x, frequency, y, z, [&](std::size_t i, float noise) { acc[i] += noise; });
}

}  // namespace soltex
