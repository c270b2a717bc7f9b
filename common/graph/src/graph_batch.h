#pragma once

#include <cstddef>
#include <vector>

#include "program.h"

// The samples one run of a program covers, and its registers' storage: every register holds
// `components` planes of `size` doubles.
namespace soltex::graph {

struct Batch {
  std::size_t size = 0;
  const double* widths = nullptr;  // per sample: the filter width in texture units
  bool uniform_width = false;      // every width equal (a grid at one level)
  // > 0 when the samples are whole grid rows of this length: along a row only x varies.
  std::size_t row_length = 0;
  std::vector<double>* storage = nullptr;
  std::vector<std::size_t> offsets;  // per register, into storage

  double* plane(int reg, int component) {
    return storage->data() + offsets[static_cast<std::size_t>(reg)] +
           static_cast<std::size_t>(component) * size;
  }
  // A float register's only plane for every component (a float broadcast to a vector).
  const double* operand(const Program& program, int reg, int component) {
    return plane(reg,
                 program.registers[static_cast<std::size_t>(reg)].components == 1 ? 0 : component);
  }
};

// Kernels: one call per instruction over the whole batch.
void run_arithmetic(const Program& program, const Instruction& instr, Batch& batch);
void run_noise(const Program& program, const Instruction& instr, Batch& batch);
void run_pattern(const Program& program, const Instruction& instr, Batch& batch);

// Non-finite results become 0 (docs/TEXTURES.md, "Node graphs"). A select, so loops vectorise.
inline double finite_or_zero(double v) {
  return v - v == 0.0 ? v : 0.0;
}

}  // namespace soltex::graph
