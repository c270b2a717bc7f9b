#include "noise_kernels.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "graph_batch.h"
#include "soltex/common/lattice.h"
#include "soltex/common/noise_tables.h"

namespace soltex::graph {
namespace {

// Where a vector-valued noise node samples its y and z components: far enough from x's
// sample point that the three are uncorrelated.
constexpr glm::dvec3 kComponentOffset[3] = {
    {0.0, 0.0, 0.0}, {31.416, 47.853, 12.793}, {-73.117, 19.271, 57.331}};

// Plans for the widths of a batch: one for a uniform batch, else remade when the width changes.
class PlanCache {
 public:
  explicit PlanCache(const NoiseSetup& setup) : setup_(setup) {}
  const OctavePlan& at(double width) {
    if (!plan_ || width != width_) {
      plan_ = graph_octave_plan(setup_, width);
      width_ = width;
    }
    return *plan_;
  }

 private:
  NoiseSetup setup_;
  std::optional<OctavePlan> plan_;
  double width_ = 0.0;
};

// One component of a fractal node's raw sum into `out` (floats, batch.size of them).
void fractal_component(const Instruction& instr, const Register& position, int position_reg,
                       const glm::dvec3& offset, Batch& batch, float* out) {
  const double* px = batch.plane(position_reg, 0);
  const double* py = batch.plane(position_reg, 1);
  const double* pz = batch.plane(position_reg, 2);
  const std::size_t n = batch.size;
  PlanCache plans(instr.noise);
  if (batch.uniform_width && batch.row_length > 0 && position.separable) {
    // Every row shares its x coordinates: the lattice work along x is done once per batch.
    const std::size_t length = batch.row_length;
    std::vector<double> xs(length);
    for (std::size_t i = 0; i < length; ++i) xs[i] = px[i] + offset.x;
    const FractalRows rows(plans.at(position.width_scale * batch.widths[0]), xs);
    for (std::size_t start = 0; start < n; start += length) {
      rows.sum(py[start] + offset.y, pz[start] + offset.z, {out + start, length});
    }
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 p(px[i] + offset.x, py[i] + offset.y, pz[i] + offset.z);
    out[i] = fractal_sum(plans.at(position.width_scale * batch.widths[i]), p);
  }
}

void run_fractal(const Program& program, const Instruction& instr, Batch& batch) {
  const bool single = instr.op == Op::noise3d;
  const int position_reg = instr.in[single ? 2 : 1];
  const Register& position = program.registers[static_cast<std::size_t>(position_reg)];
  const int comps = program.registers[static_cast<std::size_t>(instr.out)].components;
  thread_local std::vector<float> raw;
  raw.resize(batch.size);
  for (int c = 0; c < comps; ++c) {
    fractal_component(instr, position, position_reg, kComponentOffset[c], batch, raw.data());
    const double* amplitude = batch.operand(program, instr.in[0], c);
    const double* pivot = single ? batch.plane(instr.in[1], 0) : nullptr;
    double* out = batch.plane(instr.out, c);
    for (std::size_t i = 0; i < batch.size; ++i) {
      const double scaled = static_cast<double>(raw[i]) * amplitude[i];
      out[i] = finite_or_zero(pivot ? scaled + pivot[i] : scaled);
    }
  }
  if (instr.variance_out >= 0) {
    // The faded octaves' variance, scaled as the sum is.
    PlanCache plans(instr.noise);
    const double* amplitude = batch.operand(program, instr.in[0], 0);
    double* variance = batch.plane(instr.variance_out, 0);
    for (std::size_t i = 0; i < batch.size; ++i) {
      const double raw = plans.at(position.width_scale * batch.widths[i]).unresolved_variance;
      variance[i] = finite_or_zero(raw * (amplitude[i] * amplitude[i]));
    }
  }
}

template <typename F>
void run_cells(const Program& program, const Instruction& instr, Batch& batch, float mean,
               F value) {
  const int position_reg = instr.in[0];
  const double scale = program.registers[static_cast<std::size_t>(position_reg)].width_scale;
  const double *px = batch.plane(position_reg, 0), *py = batch.plane(position_reg, 1),
               *pz = batch.plane(position_reg, 2);
  double* out = batch.plane(instr.out, 0);
  for (std::size_t i = 0; i < batch.size; ++i) {
    const float alpha = lattice_visibility(scale * batch.widths[i]);
    const float v = alpha > 0.0f ? value(glm::dvec3(px[i], py[i], pz[i])) : 0.0f;
    const float faded = alpha * v + (1.0f - alpha) * mean;
    out[i] = static_cast<double>(faded);
  }
}

}  // namespace

float lattice_visibility(double filter_width) {
  const double w = std::isfinite(filter_width) ? std::max(filter_width, 0.0) : 0.0;
  return octave_visibility(static_cast<float>(w));
}

OctavePlan graph_octave_plan(const NoiseSetup& setup, double filter_width) {
  OctavePlan plan;
  plan.basis = setup.basis;
  plan.absolute = setup.absolute;
  const float mean = basis_mean(setup.basis, setup.absolute);
  const double width = std::isfinite(filter_width) ? std::max(filter_width, 0.0) : 0.0;
  double frequency = 1.0;
  float weight = 1.0f;
  const int octaves = std::min(setup.octaves, static_cast<int>(plan.octaves.size()));
  for (int k = 0; k < octaves; ++k) {
    const float alpha = octave_visibility(static_cast<float>(frequency * width));
    plan.add({frequency, weight * alpha, weight * (1.0f - alpha) * mean}, weight);
    frequency *= setup.lacunarity;
    weight *= static_cast<float>(setup.diminish);
  }
  return plan;
}

float cell_value(const glm::dvec3& p) noexcept {
  const NoiseTables& tables = noise_tables();
  const LatticeSplit x = split_lattice(p.x), y = split_lattice(p.y), z = split_lattice(p.z);
  return tables.value[static_cast<std::size_t>(tables.index(x.cell, y.cell, z.cell))];
}

// F1 and F2 over the 27 cells around p; each cell's feature point lies in the cell, moved
// from its centre by up to jitter / 2 per axis. With jitter <= 1 the nearest point is always
// among them; F2 can rarely lie further out (Worley 1996 searches the same neighbourhood).
float worley_point(const glm::dvec3& p, const WorleySetup& setup) noexcept {
  const NoiseTables& tables = noise_tables();
  const LatticeSplit s[3] = {split_lattice(p.x), split_lattice(p.y), split_lattice(p.z)};
  const float jitter = static_cast<float>(setup.jitter);
  float f1 = 1e30f, f2 = 1e30f;
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int d[3] = {dx, dy, dz};
        const int h =
            tables.index((s[0].cell + dx) & 255, (s[1].cell + dy) & 255, (s[2].cell + dz) & 255);
        float distance2 = 0.0f;
        for (int a = 0; a < 3; ++a) {
          const float u = tables.value[static_cast<std::size_t>(tables.perm[(h + 89 * a) & 255])];
          const float feature = 0.5f + jitter * (u - 0.5f);
          const float delta = (static_cast<float>(d[a]) + feature) - s[a].frac;
          distance2 += delta * delta;
        }
        if (distance2 < f1) {
          f2 = f1;
          f1 = distance2;
        } else if (distance2 < f2) {
          f2 = distance2;
        }
      }
    }
  }
  const float d1 = std::sqrt(f1), d2 = std::sqrt(f2);
  switch (setup.feature) {
    case WorleyFeature::f1:
      return d1;
    case WorleyFeature::f2:
      return d2;
    case WorleyFeature::f2_minus_f1:
      return d2 - d1;
  }
  return d1;
}

// Averaged over a fixed set of 4096 points spread through 16 cells per axis.
float worley_mean(const WorleySetup& setup) {
  double sum = 0.0;
  for (int k = 0; k < 16; ++k) {
    for (int j = 0; j < 16; ++j) {
      for (int i = 0; i < 16; ++i) {
        const glm::dvec3 p(i + 0.618034 * ((i * 7 + j * 3 + k) % 16) / 16.0,
                           j + 0.414214 * ((j * 5 + k * 11 + i) % 16) / 16.0,
                           k + 0.732051 * ((k * 13 + i * 5 + j) % 16) / 16.0);
        sum += worley_point(p, setup);
      }
    }
  }
  return static_cast<float>(sum / 4096.0);
}

void run_noise(const Program& program, const Instruction& instr, Batch& batch) {
  switch (instr.op) {
    case Op::noise3d:
    case Op::fractal3d:
    case Op::turbulence:
      return run_fractal(program, instr, batch);
    case Op::cellnoise3d:
      return run_cells(program, instr, batch, noise_tables().value_mean, cell_value);
    case Op::worleynoise3d:
      return run_cells(program, instr, batch, instr.worley.mean,
                       [&](const glm::dvec3& p) { return worley_point(p, instr.worley); });
    default:
      return;
  }
}

}  // namespace soltex::graph
