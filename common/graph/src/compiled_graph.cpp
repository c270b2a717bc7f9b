#include "soltex/graph/compiled_graph.h"

#include <algorithm>

#include "graph_batch.h"
#include "noise_kernels.h"
#include "soltex/common/texture_evaluator.h"

namespace soltex::graph {
namespace {

// Samples per batch: the registers of a batch stay in the cache (a 16^3 brick's 17^3
// samples are a few batches of whole rows).
constexpr std::size_t kBatchSamples = 2048;

struct Scratch {
  std::vector<double> storage;
  std::vector<double> widths;
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

void prepare(const Program& program, Batch& batch, std::size_t n, Scratch& s) {
  batch.size = n;
  batch.storage = &s.storage;
  batch.offsets.resize(program.registers.size());
  std::size_t offset = 0;
  for (std::size_t r = 0; r < program.registers.size(); ++r) {
    batch.offsets[r] = offset;
    offset += static_cast<std::size_t>(program.registers[r].components) * n;
  }
  if (s.storage.size() < offset) s.storage.resize(offset);
  for (std::size_t r = 0; r < program.registers.size(); ++r) {
    const Register& reg = program.registers[r];
    if (!reg.constant) continue;
    for (int c = 0; c < reg.components; ++c) {
      std::fill_n(batch.plane(static_cast<int>(r), c), n, reg.value[c]);
    }
  }
}

void run(const Program& program, Batch& batch) {
  for (const Instruction& instr : program.instructions) {
    if (instr.op >= Op::noise3d && instr.op <= Op::worleynoise3d) {
      run_noise(program, instr, batch);
    } else if (instr.op >= Op::ramp) {
      run_pattern(program, instr, batch);
    } else {
      run_arithmetic(program, instr, batch);
      if (instr.variance_out >= 0) {
        // A scaling by constants: its input's variance times the scale's square.
        const double* in = batch.plane(instr.variance_in, 0);
        double* out = batch.plane(instr.variance_out, 0);
        for (std::size_t i = 0; i < batch.size; ++i) {
          out[i] = finite_or_zero(in[i] * instr.variance_gain);
        }
      }
    }
  }
}

// Outputs are clamped to [0, 1] before they become channel samples.
void write_outputs(const Program& program, Batch& batch, const GraphPlanes& out,
                   std::size_t first) {
  const auto write = [&](int reg, int component, float* plane) {
    if (plane == nullptr || reg < 0) return;
    const double* v = batch.plane(reg, component);
    for (std::size_t i = 0; i < batch.size; ++i) {
      plane[first + i] = static_cast<float>(std::clamp(v[i], 0.0, 1.0));
    }
  };
  for (int c = 0; c < 3; ++c) write(program.colour, c, out.colour[c]);
  write(program.opacity, 0, out.opacity);
  write(program.specular, 0, out.specular);
}

}  // namespace

CompiledGraph::CompiledGraph(TextureGraph source, std::unique_ptr<Program> program,
                             std::vector<uint8_t> canonical)
    : source_(std::move(source)), program_(std::move(program)), canonical_(std::move(canonical)) {}

CompiledGraph::~CompiledGraph() = default;

double CompiledGraph::cost_per_sample() const {
  return program_->cost_per_sample;
}

bool CompiledGraph::has_colour() const {
  return program_->colour >= 0;
}
bool CompiledGraph::has_opacity() const {
  return program_->opacity >= 0;
}
bool CompiledGraph::has_specular() const {
  return program_->specular >= 0;
}

void CompiledGraph::append_canonical(std::vector<uint8_t>& bytes) const {
  bytes.insert(bytes.end(), canonical_.begin(), canonical_.end());
}

int CompiledGraph::evaluated_octaves(double filter_width) const {
  int octaves = 0;
  for (const Instruction& instr : program_->instructions) {
    if (instr.op != Op::noise3d && instr.op != Op::fractal3d && instr.op != Op::turbulence) {
      continue;
    }
    const int position = instr.in[instr.op == Op::noise3d ? 2 : 1];
    const double scale = program_->registers[static_cast<std::size_t>(position)].width_scale;
    const int comps = program_->registers[static_cast<std::size_t>(instr.out)].components;
    octaves += comps * graph_octave_plan(instr.noise, scale * filter_width).evaluated_octaves();
  }
  return octaves;
}

void CompiledGraph::evaluate_points(std::span<const glm::dvec3> points,
                                    std::span<const double> widths, const GraphPlanes& out) const {
  Scratch& s = scratch();
  Batch batch;
  batch.widths = widths.data();
  for (std::size_t first = 0; first < points.size(); first += kBatchSamples) {
    const std::size_t n = std::min(kBatchSamples, points.size() - first);
    prepare(*program_, batch, n, s);
    batch.widths = widths.data() + first;
    double *x = batch.plane(program_->position, 0), *y = batch.plane(program_->position, 1),
           *z = batch.plane(program_->position, 2);
    for (std::size_t i = 0; i < n; ++i) {
      x[i] = points[first + i].x;
      y[i] = points[first + i].y;
      z[i] = points[first + i].z;
    }
    run(*program_, batch);
    write_outputs(*program_, batch, out, first);
  }
}

void CompiledGraph::evaluate_grid(const Grid& grid, double filter_width,
                                  const GraphPlanes& out) const {
  Scratch& s = scratch();
  const auto nx = static_cast<std::size_t>(grid.count.x);
  const std::size_t rows_per_batch = std::max<std::size_t>(1, kBatchSamples / nx);
  const std::size_t rows = grid.size() / nx;
  s.widths.assign(rows_per_batch * nx, filter_width);
  Batch batch;
  batch.widths = s.widths.data();
  batch.uniform_width = true;
  batch.row_length = nx;
  for (std::size_t row = 0; row < rows; row += rows_per_batch) {
    const std::size_t batch_rows = std::min(rows_per_batch, rows - row);
    prepare(*program_, batch, batch_rows * nx, s);
    double *x = batch.plane(program_->position, 0), *y = batch.plane(program_->position, 1),
           *z = batch.plane(program_->position, 2);
    for (std::size_t r = 0; r < batch_rows; ++r) {
      const int j = static_cast<int>((row + r) % static_cast<std::size_t>(grid.count.y));
      const int k = static_cast<int>((row + r) / static_cast<std::size_t>(grid.count.y));
      for (std::size_t i = 0; i < nx; ++i) {
        const glm::dvec3 p = grid.point(static_cast<int>(i), j, k);
        x[r * nx + i] = p.x;
        y[r * nx + i] = p.y;
        z[r * nx + i] = p.z;
      }
    }
    run(*program_, batch);
    write_outputs(*program_, batch, out, row * nx);
  }
}

}  // namespace soltex::graph
