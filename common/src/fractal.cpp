#include "soltex/common/fractal.h"

#include <algorithm>
#include <cmath>

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

// Per-run cell coefficients of one row, reused across calls on the same thread.
struct RunScratch {
  std::vector<float> a, b, c, d;

  void reserve(std::size_t runs) {
    if (a.size() < runs) {
      a.resize(runs);
      b.resize(runs);
      c.resize(runs);
      d.resize(runs);
    }
  }
};

RunScratch& run_scratch(std::size_t runs) {
  thread_local RunScratch scratch;
  scratch.reserve(runs);
  return scratch;
}

// The loops below take __restrict pointers: without them the compiler must assume a store to
// the coefficient arrays may change the noise tables and refuses to vectorise the gathers.

void value_runs(const float* __restrict value, const int32_t* __restrict perm,
                const int32_t* __restrict run_cell, std::size_t runs, const RowHashes& hashes,
                float fy, float fz, float* __restrict e0, float* __restrict e1) {
  for (std::size_t r = 0; r < runs; ++r) {
    const ValueCellEdges edges = value_cell_edges(value, perm, run_cell[r], hashes, fy, fz);
    e0[r] = edges.e0;
    e1[r] = edges.e1;
  }
}

template <bool kAbsolute>
void value_finish(const Octave& octave, const int32_t* __restrict run_of,
                  const float* __restrict frac, const float* __restrict e0,
                  const float* __restrict e1, std::size_t n, float* __restrict acc) {
  const Octave o = octave;
  for (std::size_t i = 0; i < n; ++i) {
    const int32_t r = run_of[i];
    float noise = value_cell_finish(e0[r], e1[r], frac[i]);
    if constexpr (kAbsolute) noise = std::fabs(noise);
    acc[i] += octave_term(o, noise);
  }
}

void gradient_runs(const NoiseTables& tables, const int32_t* __restrict run_cell, std::size_t runs,
                   const GradientRow& row, float* __restrict slope0, float* __restrict offset0,
                   float* __restrict slope1, float* __restrict offset1) {
  for (std::size_t r = 0; r < runs; ++r) {
    const GradientCellEdges e = gradient_cell_edges(tables, run_cell[r], row);
    slope0[r] = e.slope0;
    offset0[r] = e.offset0;
    slope1[r] = e.slope1;
    offset1[r] = e.offset1;
  }
}

template <bool kAbsolute>
void gradient_finish(const Octave& octave, const int32_t* __restrict run_of,
                     const float* __restrict frac, const float* __restrict slope0,
                     const float* __restrict offset0, const float* __restrict slope1,
                     const float* __restrict offset1, std::size_t n, float* __restrict acc) {
  const Octave o = octave;
  for (std::size_t i = 0; i < n; ++i) {
    const int32_t r = run_of[i];
    float noise = gradient_cell_finish(slope0[r], offset0[r], slope1[r], offset1[r], frac[i]);
    if constexpr (kAbsolute) noise = std::fabs(noise);
    acc[i] += octave_term(o, noise);
  }
}

// One octave along one row: corner work per cell run, then the finish per point.
template <bool kAbsolute>
void add_octave(NoiseBasis basis, const Octave& octave, const int32_t* run_of, const float* frac,
                const int32_t* run_cell, std::size_t runs, std::size_t n, double y, double z,
                float* acc) {
  const NoiseTables& tables = noise_tables();
  const LatticeSplit sy = split_lattice(y * octave.frequency);
  const LatticeSplit sz = split_lattice(z * octave.frequency);
  RunScratch& s = run_scratch(runs);
  if (basis == NoiseBasis::value) {
    value_runs(tables.value.data(), tables.perm.data(), run_cell, runs,
               row_hashes(tables, sy.cell, sz.cell), sy.frac, sz.frac, s.a.data(), s.b.data());
    value_finish<kAbsolute>(octave, run_of, frac, s.a.data(), s.b.data(), n, acc);
  } else {
    gradient_runs(tables, run_cell, runs, gradient_row(tables, sy, sz), s.a.data(), s.b.data(),
                  s.c.data(), s.d.data());
    gradient_finish<kAbsolute>(octave, run_of, frac, s.a.data(), s.b.data(), s.c.data(), s.d.data(),
                               n, acc);
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
    // Exact powers of two, as ldexp gives them, without a libm call per octave: a per-pixel
    // reference plans the octaves at every pixel.
    const bool small = k >= 0 && k <= SpecLimits::kMaxOctave;
    const double frequency =
        small ? params.scale * static_cast<double>(uint32_t{1} << k) : std::ldexp(params.scale, k);
    const float weight = small ? 1.0f / static_cast<float>(uint32_t{1} << k) : std::ldexp(1.0f, -k);
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

FractalRows::FractalRows(const OctavePlan& plan, std::span<const double> x)
    : plan_(plan), size_(x.size()), octaves_(static_cast<std::size_t>(plan.count)) {
  std::vector<int32_t> cell(size_);
  for (int k = 0; k < plan_.count; ++k) {
    OctaveColumns& columns = octaves_[static_cast<std::size_t>(k)];
    if (plan_.octaves[k].noise_weight == 0.0f) continue;  // faded out: no noise to evaluate
    const double frequency = plan_.octaves[k].frequency;
    columns.frac.resize(size_);
    columns.run_of.resize(size_);
    for (std::size_t i = 0; i < size_; ++i) {
      const LatticeSplit split = split_lattice(x[i] * frequency);
      cell[i] = split.cell;
      columns.frac[i] = split.frac;
    }
    for (std::size_t i = 0; i < size_; ++i) {
      if (i == 0 || cell[i] != cell[i - 1]) columns.run_cell.push_back(cell[i]);
      columns.run_of[i] = static_cast<int32_t>(columns.run_cell.size() - 1);
    }
  }
}

void FractalRows::sum(double y, double z, std::span<float> out) const {
  float* acc = out.data();
  std::fill(acc, acc + size_, 0.0f);
  for (int k = 0; k < plan_.count; ++k) {
    const Octave& octave = plan_.octaves[k];
    if (octave.noise_weight == 0.0f) {
      for (std::size_t i = 0; i < size_; ++i) acc[i] += octave.mean_term;
      continue;
    }
    const OctaveColumns& c = octaves_[static_cast<std::size_t>(k)];
    const std::size_t runs = c.run_cell.size();
    const int32_t* run_of = c.run_of.data();
    const float* frac = c.frac.data();
    const int32_t* run_cell = c.run_cell.data();
    if (plan_.absolute) {
      add_octave<true>(plan_.basis, octave, run_of, frac, run_cell, runs, size_, y, z, acc);
    } else {
      add_octave<false>(plan_.basis, octave, run_of, frac, run_cell, runs, size_, y, z, acc);
    }
  }
}

void fractal_sum_row(const OctavePlan& plan, std::span<const double> x, double y, double z,
                     std::span<float> out) {
  FractalRows(plan, x).sum(y, z, out);
}

}  // namespace soltex
