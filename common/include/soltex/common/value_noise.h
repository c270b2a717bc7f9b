#pragma once

#include <glm/vec3.hpp>

#include "soltex/common/lattice.h"
#include "soltex/common/noise_tables.h"

// Lattice value noise (the lecture's latticeNoise + trilinear interpolation), in [0, 1],
// period 256 cells along each axis.
//
// The trilinear interpolation runs along y and z first, then x. That order is the definition:
// a row of samples along x inside one cell then shares the two y-z interpolated edge values,
// and the single-point and batch paths execute the same operations, so they agree bit for bit.
namespace soltex {

// The values on the two x-faces of a cell, interpolated in y and z.
struct ValueCellEdges {
  float e0;
  float e1;
};

inline ValueCellEdges value_cell_edges(const NoiseTables& tables, int ix, const LatticeSplit& y,
                                       const LatticeSplit& z) noexcept {
  const auto corner = [&](int dx, int dy, int dz) {
    return tables.value[tables.index(ix + dx, y.cell + dy, z.cell + dz)];
  };
  const auto bilerp = [&](int dx) {
    const float a = corner(dx, 0, 0) + y.frac * (corner(dx, 1, 0) - corner(dx, 0, 0));
    const float b = corner(dx, 0, 1) + y.frac * (corner(dx, 1, 1) - corner(dx, 0, 1));
    return a + z.frac * (b - a);
  };
  return {bilerp(0), bilerp(1)};
}

inline float value_cell_finish(const ValueCellEdges& edges, float fx) noexcept {
  return edges.e0 + fx * (edges.e1 - edges.e0);
}

// Value noise at `t`, given in lattice units (already scaled by the frequency).
inline float value_noise(const NoiseTables& tables, const glm::dvec3& t) noexcept {
  const LatticeSplit x = split_lattice(t.x);
  const LatticeSplit y = split_lattice(t.y);
  const LatticeSplit z = split_lattice(t.z);
  return value_cell_finish(value_cell_edges(tables, x.cell, y, z), x.frac);
}

inline float value_noise(const glm::dvec3& t) noexcept {
  return value_noise(noise_tables(), t);
}

}  // namespace soltex
