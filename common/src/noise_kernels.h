#pragma once

#include <cstddef>
#include <cstdint>

#include "soltex/common/fractal.h"

// The vector kernels behind FractalRows::sum, compiled for every x86 target Highway knows
// (SSSE3, SSE4, AVX2, AVX-512) plus its scalar fallback, and chosen at run time once per row.
//
// One octave of one row works in two passes:
//   faces:  the y-z interpolated noise on every distinct lattice x-face the row's points touch
//           (one face per vector lane, the lattice hashes fetched by gather);
//   points: one point per lane, gathering its cell's two faces and finishing along x.
// A point in the cell whose left face is face f has its right face at f + 1: the face list is
// built that way, so a point needs one index, and adjacent cells share the face between them.
// fractal_rows() runs a grid plane's rows together: their faces one row after another (rows
// in one lattice cell in y and z load their corners once), then one points pass over all of
// them, so a row of 17 points does not leave most of a second vector empty.
// Every target executes the scalar path's operations in the scalar path's order, so all give
// the bits fractal_sum gives.
// How a single-point entry point calls its kernel, in a file compiled under
// hwy/foreach_target.h: where the build's own target is already the best one the file compiles
// (a -march=native build), directly, with nothing to choose; otherwise (the generic build)
// through run-time dispatch, one indirect call per point.
#define SOLTEX_POINT_DISPATCH(FUNC)                                                \
  ((HWY_STATIC_TARGET == (HWY_TARGETS & -HWY_TARGETS)) ? HWY_STATIC_DISPATCH(FUNC) \
                                                       : HWY_DYNAMIC_DISPATCH(FUNC))

namespace soltex::noise_kernels {

// Every per-point and per-face array is padded to a multiple of this many entries (the widest
// vector, 16 floats), the padding holding valid indices, so kernels never need a tail loop.
inline constexpr std::size_t kPad = 16;

inline constexpr std::size_t padded(std::size_t n) {
  return (n + kPad - 1) / kPad * kPad;
}

// One evaluated octave's x columns (see FractalRows).
struct OctaveColumnsView {
  const float* frac;       // per point: x fraction
  const int32_t* face_lo;  // per point: index of its cell's left face
  const int32_t* face_x;   // per face: lattice x in [0, 256]
  std::size_t faces;       // unpadded face count
};

struct RowRequest {
  const OctavePlan* plan;
  const OctaveColumnsView* octaves;  // plan->count entries; faded-out octaves are not read
  std::size_t size;                  // points in the row
  double y, z;
  float* out;  // size entries
};

// out[i] = fractal_sum(plan, (x[i], y, z)) bit for bit.
void fractal_row(const RowRequest& request);

// Rows that share their x columns, their points end to end in the lanes: the octave views'
// frac and face_lo hold rows * size points, row r's reading faces r * faces on (face_x is one
// row's).
struct RowsRequest {
  const OctavePlan* plan;
  const OctaveColumnsView* octaves;
  std::size_t size;  // points per row
  std::size_t rows;
  const double* y;  // rows entries
  const double* z;  // rows entries
  float* out;       // rows * size entries
};

// out[r * size + i] = fractal_sum(plan, (x[i], y[r], z[r])) bit for bit.
void fractal_rows(const RowsRequest& request);

// fractal_sum(plan, p) at one point, through run-time dispatch: one indirect call per point,
// next to the 50-100 ns of a few octaves (measured in docs/PERFORMANCE.md, "Generic and native
// builds"), so that a generic build runs the gradient basis one octave per vector lane and the
// value basis with its target's rounding instructions, as a -march=native build does.
float fractal_sum_point(const OctavePlan& plan, const glm::dvec3& p);

// The gradient basis alone through run-time dispatch, so that tests can run it on every target.
float gradient_fractal_sum_dispatched(const OctavePlan& plan, const glm::dvec3& p);

// The Highway targets compiled into the kernels (a HWY_TARGETS-style bit mask), for tests that
// run each of them.
int64_t compiled_targets();

// The target fractal_row dispatches to now (one HWY_* bit).
int64_t dispatched_target();

}  // namespace soltex::noise_kernels
