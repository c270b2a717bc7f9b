#pragma once

#include <glm/vec3.hpp>

#include "soltex/common/lattice.h"
#include "soltex/common/noise_tables.h"

// Lattice value noise (the lecture's latticeNoise + trilinear interpolation), in [0, 1],
// period 256 cells along each axis.
//
// The trilinear interpolation runs along y and z first, then x. That order is the definition:
// a row of samples along x shares the y-z hashes and fractions, a run of samples inside one
// cell shares the two y-z interpolated face values, and the single-point and batch paths
// execute the same operations, so they agree bit for bit.
namespace soltex {

// The values on the two x-faces of a cell, interpolated in y and z.
struct ValueCellEdges {
  float e0;
  float e1;
};

// `v` is NoiseTables::value_at (the value at each permutation entry); passed as a pointer so
// that a vectorised caller can declare it free of aliasing with its outputs.
inline ValueCellEdges value_cell_edges(const float* v, int ix, const RowHashes& h, float fy,
                                       float fz) noexcept {
  const auto face = [&](int x) {
    const float c00 = v[x + h.h00], c10 = v[x + h.h10];
    const float c01 = v[x + h.h01], c11 = v[x + h.h11];
    const float a = c00 + fy * (c10 - c00);
    const float b = c01 + fy * (c11 - c01);
    return a + fz * (b - a);
  };
  return {face(ix), face(ix + 1)};
}

inline float value_cell_finish(float e0, float e1, float fx) noexcept {
  return e0 + fx * (e1 - e0);
}

// Value noise at the point the three axes' splits describe.
inline float value_noise_at(const NoiseTables& tables, const LatticeSplit& x, const LatticeSplit& y,
                            const LatticeSplit& z) noexcept {
  const ValueCellEdges edges = value_cell_edges(tables.value_at.data(), x.cell,
                                                row_hashes(tables, y.cell, z.cell), y.frac, z.frac);
  return value_cell_finish(edges.e0, edges.e1, x.frac);
}

// Value noise at `t`, given in lattice units (already scaled by the frequency).
inline float value_noise(const NoiseTables& tables, const glm::dvec3& t) noexcept {
  return value_noise_at(tables, split_lattice(t.x), split_lattice(t.y), split_lattice(t.z));
}

// The same for code inlined into the runtime-dispatched kernels (split_lattice_in_kernel).
inline float value_noise_in_kernel(const NoiseTables& tables, const glm::dvec3& t) noexcept {
  return value_noise_at(tables, split_lattice_in_kernel(t.x), split_lattice_in_kernel(t.y),
                        split_lattice_in_kernel(t.z));
}

inline float value_noise(const glm::dvec3& t) noexcept {
  return value_noise(noise_tables(), t);
}

}  // namespace soltex
