// Every attainable target, not only those above the build's baseline: the unit test runs each
// one against the scalar path, and a portable (non-native) build dispatches among them.
#ifndef HWY_COMPILE_ALL_ATTAINABLE
#define HWY_COMPILE_ALL_ATTAINABLE
#endif
// Highway 1.0.3 counts AVX3_DL attainable only when asked (its baseline test reads an
// undefined macro), so a -march=native build on such a CPU would otherwise fail to compile.
#ifndef HWY_WANT_AVX3_DL
#define HWY_WANT_AVX3_DL
#endif

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "noise_kernels.cpp"
#include "noise_kernels.h"

#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "fractal_point-inl.h"
#include "soltex/common/check.h"
#include "soltex/common/gradient_noise.h"
#include "soltex/common/lattice.h"
#include "soltex/common/noise_tables.h"

HWY_BEFORE_NAMESPACE();
namespace soltex::noise_kernels::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;

// table[x + h] for the faces x of one vector (table: NoiseTables::perm or ::value_at). Faces of
// neighbouring cells are consecutive lattice x values, so the lookups are mostly one contiguous
// load rather than a gather.
template <class D>
class FaceTable {
 public:
  using DI = hn::RebindToSigned<D>;
  using T = hn::TFromD<D>;

  FaceTable(D d, const T* HWY_RESTRICT table, const int32_t* HWY_RESTRICT face_x)
      : d_(d),
        table_(table),
        x0_(face_x[0]),
        x_(hn::LoadU(DI(), face_x)),
        // Iota(0) plus x0_, not Iota(x0_): with a run-time start Iota is built by scalar
        // stores read back as one vector, which waits for their forwarding.
        contiguous_(hn::AllTrue(DI(), hn::Eq(x_, hn::Add(hn::Iota(DI(), 0), hn::Set(DI(), x0_))))) {
  }

  HWY_INLINE hn::Vec<D> operator()(int32_t h) const {
    // face_x <= 256 and h <= 255 keep both forms inside the 512-entry tables.
    if (contiguous_) return hn::LoadU(d_, table_ + x0_ + h);
    return hn::GatherIndex(d_, table_, hn::Add(x_, hn::Set(DI(), h)));
  }

 private:
  D d_;
  const T* HWY_RESTRICT table_;
  int32_t x0_;
  hn::Vec<DI> x_;
  bool contiguous_;
};

// value_cell_edges' face, one face per lane.
template <class D>
void ValueFaces(D df, const NoiseTables& tables, const int32_t* HWY_RESTRICT face_x,
                std::size_t faces, const RowHashes& h, float fy, float fz,
                float* HWY_RESTRICT edge) {
  const auto vy = hn::Set(df, fy), vz = hn::Set(df, fz);
  for (std::size_t f = 0; f < faces; f += hn::Lanes(df)) {
    const FaceTable corner(df, tables.value_at.data(), face_x + f);
    const auto a = Lerp(corner(h.h00), corner(h.h10), vy);
    const auto b = Lerp(corner(h.h01), corner(h.h11), vy);
    hn::StoreU(Lerp(a, b, vz), df, edge + f);
  }
}

// Walks a rows request's rows in order: load(hashes) for the first row and for each row whose
// lattice cell in y or z differs from the row before's, then each_row(row, y split, z split).
// Consecutive rows in one cell (at the coarse octaves, all of a plane's rows) share what load
// made from the cell's corner hashes.
template <class Load, class EachRow>
HWY_INLINE void RowsByCell(const NoiseTables& tables, const RowsRequest& r, double frequency,
                           const Load& load, const EachRow& each_row) {
  int32_t cell_y = 0, cell_z = 0;
  for (std::size_t row = 0; row < r.rows; ++row) {
    const LatticeSplit sy = split_lattice_in_kernel(r.y[row] * frequency);
    const LatticeSplit sz = split_lattice_in_kernel(r.z[row] * frequency);
    if (row == 0 || sy.cell != cell_y || sz.cell != cell_z) {
      load(row_hashes(tables, sy.cell, sz.cell));
      cell_y = sy.cell;
      cell_z = sz.cell;
    }
    each_row(row, sy, sz);
  }
}

// ValueFaces for every row of a rows request, for an octave whose faces fit one vector: the
// corners loaded once per cell (RowsByCell), each row's three lerps as ValueFaces makes them.
// Row r's faces go to face_a + r * faces, in ascending rows (each store may run past its
// row's faces into the next row's, which that row's store then overwrites).
template <class D>
void ValueFacesRows(D df, const NoiseTables& tables, const OctaveColumnsView& c, double frequency,
                    const RowsRequest& r, float* HWY_RESTRICT face_a) {
  const FaceTable corner(df, tables.value_at.data(), c.face_x);
  hn::Vec<D> c00 = hn::Zero(df), c10 = c00, c01 = c00, c11 = c00;
  RowsByCell(
      tables, r, frequency,
      [&](const RowHashes& h) {
        c00 = corner(h.h00);
        c10 = corner(h.h10);
        c01 = corner(h.h01);
        c11 = corner(h.h11);
      },
      [&](std::size_t row, const LatticeSplit& sy, const LatticeSplit& sz) {
        const auto vy = hn::Set(df, sy.frac), vz = hn::Set(df, sz.frac);
        hn::StoreU(Lerp(Lerp(c00, c10, vy), Lerp(c01, c11, vy), vz), df, face_a + row * c.faces);
      });
}

// gradient_cell_edges' face, one face per lane.
template <class D>
void GradientFaces(D df, const NoiseTables& tables, const int32_t* HWY_RESTRICT face_x,
                   std::size_t faces, const GradientRow& row, float* HWY_RESTRICT slope,
                   float* HWY_RESTRICT offset) {
  const hn::RebindToSigned<D> di;
  const GradientRowVec<D> r{hn::Set(df, row.fy), hn::Set(df, row.fy - 1.0f),
                            hn::Set(df, row.fz), hn::Set(df, row.fz - 1.0f),
                            hn::Set(df, row.v),  hn::Set(df, row.w)};
  for (std::size_t f = 0; f < faces; f += hn::Lanes(df)) {
    const FaceTable perm(di, tables.perm.data(), face_x + f);
    hn::Vec<D> face_slope, face_offset;
    GradientFace(df, r, perm(row.hashes.h00), perm(row.hashes.h10), perm(row.hashes.h01),
                 perm(row.hashes.h11), face_slope, face_offset);
    hn::StoreU(face_slope, df, slope + f);
    hn::StoreU(face_offset, df, offset + f);
  }
}

// GradientFaces for every row of a rows request, for an octave whose faces fit one vector:
// the corners' hashes loaded once per cell (RowsByCell); each row's slopes and offsets at
// r * faces.
template <class D>
void GradientFacesRows(D df, const NoiseTables& tables, const OctaveColumnsView& c,
                       double frequency, const RowsRequest& r, float* HWY_RESTRICT slope,
                       float* HWY_RESTRICT offset) {
  const hn::RebindToSigned<D> di;
  const FaceTable perm(di, tables.perm.data(), c.face_x);
  hn::Vec<decltype(di)> p00 = hn::Zero(di), p10 = p00, p01 = p00, p11 = p00;
  RowsByCell(
      tables, r, frequency,
      [&](const RowHashes& h) {
        p00 = perm(h.h00);
        p10 = perm(h.h10);
        p01 = perm(h.h01);
        p11 = perm(h.h11);
      },
      [&](std::size_t row, const LatticeSplit& sy, const LatticeSplit& sz) {
        // gradient_row()'s fractions and fades, as GradientFaces takes them.
        const GradientRowVec<D> v{hn::Set(df, sy.frac),       hn::Set(df, sy.frac - 1.0f),
                                  hn::Set(df, sz.frac),       hn::Set(df, sz.frac - 1.0f),
                                  hn::Set(df, fade(sy.frac)), hn::Set(df, fade(sz.frac))};
        hn::Vec<D> face_slope, face_offset;
        GradientFace(df, v, p00, p10, p01, p11, face_slope, face_offset);
        hn::StoreU(face_slope, df, slope + row * c.faces);
        hn::StoreU(face_offset, df, offset + row * c.faces);
      });
}

// Runs a face pass on vectors no wider than the face count needs: a row's coarse octaves touch
// only a few faces, and a gather costs per lane.
template <class Pass>
HWY_INLINE void WithFaceWidth(std::size_t faces, const Pass& pass) {
  if (faces <= hn::Lanes(hn::CappedTag<float, 4>())) {
    pass(hn::CappedTag<float, 4>());
  } else if (faces <= hn::Lanes(hn::CappedTag<float, 8>())) {
    pass(hn::CappedTag<float, 8>());
  } else {
    pass(DF());
  }
}

// The faces a vector of points needs, face[lo] (left) and face[lo + 1] (right). Points in
// ascending x reach fewer faces than a vector has lanes: then two loads and in-register lane
// lookups replace the gathers.
class FaceFetch {
 public:
  explicit FaceFetch(const int32_t* HWY_RESTRICT face_lo)
      : lo_(hn::LoadU(DI(), face_lo)),
        base_(face_lo[0]),
        rel_(hn::Sub(lo_, hn::Set(DI(), base_))),
        local_(hn::AllTrue(
            DI(), hn::And(hn::Gt(rel_, hn::Set(DI(), -1)), hn::Lt(rel_, hn::Set(DI(), kLanes))))) {}

  HWY_INLINE VF left(const float* HWY_RESTRICT face) const { return get(face); }
  HWY_INLINE VF right(const float* HWY_RESTRICT face) const { return get(face + 1); }

 private:
  HWY_INLINE VF get(const float* HWY_RESTRICT face) const {
    if (local_) {
      return hn::TableLookupLanes(hn::LoadU(DF(), face + base_), hn::IndicesFromVec(DF(), rel_));
    }
    return hn::GatherIndex(DF(), face, lo_);
  }

  static constexpr int32_t kLanes = static_cast<int32_t>(hn::MaxLanes(DF()));

  VI lo_;
  int32_t base_;
  VI rel_;  // lo - base: lane indices when local_
  bool local_;
};

template <bool kAbsolute>
void ValuePoints(const OctaveColumnsView& c, std::size_t n, const float* HWY_RESTRICT edge,
                 float weight, float mean, float* HWY_RESTRICT acc) {
  const DF df;
  const VF w = hn::Set(df, weight), m = hn::Set(df, mean);
  for (std::size_t i = 0; i < n; i += hn::Lanes(df)) {
    const FaceFetch face(c.face_lo + i);
    VF noise = Lerp(face.left(edge), face.right(edge), hn::LoadU(df, c.frac + i));
    if constexpr (kAbsolute) noise = hn::Abs(noise);
    const VF term = hn::Add(hn::Mul(w, noise), m);
    hn::StoreU(hn::Add(hn::LoadU(df, acc + i), term), df, acc + i);
  }
}

template <bool kAbsolute>
void GradientPoints(const OctaveColumnsView& c, std::size_t n, const float* HWY_RESTRICT slope,
                    const float* HWY_RESTRICT offset, float weight, float mean,
                    float* HWY_RESTRICT acc) {
  const DF df;
  const VF w = hn::Set(df, weight), m = hn::Set(df, mean), one = hn::Set(df, 1.0f);
  for (std::size_t i = 0; i < n; i += hn::Lanes(df)) {
    const FaceFetch face(c.face_lo + i);
    const VF fx = hn::LoadU(df, c.frac + i);
    // gradient_cell_finish
    const VF a0 = hn::Add(face.left(offset), hn::Mul(face.left(slope), fx));
    const VF a1 = hn::Add(face.right(offset), hn::Mul(face.right(slope), hn::Sub(fx, one)));
    VF noise = Lerp(a0, a1, Fade(df, fx));
    if constexpr (kAbsolute) noise = hn::Abs(noise);
    const VF term = hn::Add(hn::Mul(w, noise), m);
    hn::StoreU(hn::Add(hn::LoadU(df, acc + i), term), df, acc + i);
  }
}

// One octave's y-z noise on one row's faces: value noise into face_a, or gradient noise's
// slope and offset into face_a and face_b.
void OctaveFaces(const OctavePlan& plan, const Octave& octave, const OctaveColumnsView& c, double y,
                 double z, float* HWY_RESTRICT face_a, float* HWY_RESTRICT face_b) {
  const NoiseTables& tables = noise_tables();
  const LatticeSplit sy = split_lattice_in_kernel(y * octave.frequency);
  const LatticeSplit sz = split_lattice_in_kernel(z * octave.frequency);
  if (plan.basis == NoiseBasis::value) {
    const RowHashes hashes = row_hashes(tables, sy.cell, sz.cell);
    WithFaceWidth(c.faces, [&](auto d) {
      ValueFaces(d, tables, c.face_x, c.faces, hashes, sy.frac, sz.frac, face_a);
    });
    return;
  }
  const GradientRow row = gradient_row(tables, sy, sz);
  WithFaceWidth(c.faces,
                [&](auto d) { GradientFaces(d, tables, c.face_x, c.faces, row, face_a, face_b); });
}

// One octave finished at n points (padded length) from their faces, added into acc.
void OctavePoints(const OctavePlan& plan, const Octave& octave, const OctaveColumnsView& c,
                  std::size_t n, const float* HWY_RESTRICT face_a, const float* HWY_RESTRICT face_b,
                  float* HWY_RESTRICT acc) {
  const float weight = octave.noise_weight, mean = octave.mean_term;
  if (plan.basis == NoiseBasis::value) {
    if (plan.absolute) {
      ValuePoints<true>(c, n, face_a, weight, mean, acc);
    } else {
      ValuePoints<false>(c, n, face_a, weight, mean, acc);
    }
  } else if (plan.absolute) {
    GradientPoints<true>(c, n, face_a, face_b, weight, mean, acc);
  } else {
    GradientPoints<false>(c, n, face_a, face_b, weight, mean, acc);
  }
}

// A faded octave's mean, added at n points (padded length).
void AddMean(float mean_term, std::size_t n, float* HWY_RESTRICT acc) {
  const DF df;
  const VF mean = hn::Set(df, mean_term);
  for (std::size_t i = 0; i < n; i += hn::Lanes(df)) {
    hn::StoreU(hn::Add(hn::LoadU(df, acc + i), mean), df, acc + i);
  }
}

// acc holds padded(size) entries, face_a and face_b padded(faces) + kPad for the widest octave.
void FractalRowKernel(const RowRequest& r, float* HWY_RESTRICT acc, float* HWY_RESTRICT face_a,
                      float* HWY_RESTRICT face_b) {
  const std::size_t n = padded(r.size);
  std::fill(acc, acc + n, 0.0f);
  for (int k = 0; k < r.plan->count; ++k) {
    const Octave& octave = r.plan->octaves[k];
    if (octave.noise_weight == 0.0f) {
      AddMean(octave.mean_term, n, acc);
      continue;
    }
    OctaveFaces(*r.plan, octave, r.octaves[k], r.y, r.z, face_a, face_b);
    OctavePoints(*r.plan, octave, r.octaves[k], n, face_a, face_b, acc);
  }
  std::copy(acc, acc + r.size, r.out);
}

// As FractalRowKernel for r.rows rows at once: each row's faces at r * faces, then every
// row's points in one pass. face_a and face_b hold rows * faces + kPad for the widest octave.
void FractalRowsKernel(const RowsRequest& r, float* HWY_RESTRICT acc, float* HWY_RESTRICT face_a,
                       float* HWY_RESTRICT face_b) {
  const std::size_t n = padded(r.size * r.rows);
  std::fill(acc, acc + n, 0.0f);
  for (int k = 0; k < r.plan->count; ++k) {
    const Octave& octave = r.plan->octaves[k];
    if (octave.noise_weight == 0.0f) {
      AddMean(octave.mean_term, n, acc);
      continue;
    }
    const OctaveColumnsView& c = r.octaves[k];
    bool shared_corners = false;
    WithFaceWidth(c.faces, [&](auto d) {
      if (c.faces > hn::Lanes(d)) return;  // several face vectors: row by row below
      if (r.plan->basis == NoiseBasis::value) {
        ValueFacesRows(d, noise_tables(), c, octave.frequency, r, face_a);
      } else {
        GradientFacesRows(d, noise_tables(), c, octave.frequency, r, face_a, face_b);
      }
      shared_corners = true;
    });
    // Ascending rows: a row's faces pass may write past its faces into the next row's,
    // which that row's pass then overwrites.
    for (std::size_t row = 0; row < r.rows && !shared_corners; ++row) {
      OctaveFaces(*r.plan, octave, c, r.y[row], r.z[row], face_a + row * c.faces,
                  face_b + row * c.faces);
    }
    OctavePoints(*r.plan, octave, c, n, face_a, face_b, acc);
  }
  std::copy(acc, acc + r.size * r.rows, r.out);
}

float GradientFractalSumKernel(const OctavePlan& plan, const glm::dvec3& point) {
  return GradientFractalSum(plan, point);
}

float FractalSumKernel(const OctavePlan& plan, const glm::dvec3& point) {
  return FractalSumAt(plan, point);
}

int64_t TargetOfKernel() {
  return HWY_TARGET;
}

}  // namespace soltex::noise_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex::noise_kernels {

HWY_EXPORT(FractalRowKernel);
HWY_EXPORT(FractalRowsKernel);
HWY_EXPORT(TargetOfKernel);
HWY_EXPORT(GradientFractalSumKernel);
HWY_EXPORT(FractalSumKernel);

namespace {
// Row scratch, reused across calls on the same thread.
struct RowScratch {
  std::vector<float> acc, face_a, face_b;
};
}  // namespace

void fractal_row(const RowRequest& request) {
  if (request.size == 0) return;
  std::size_t faces = 0;
  for (int k = 0; k < request.plan->count; ++k) {
    if (request.plan->octaves[k].noise_weight != 0.0f) {
      faces = std::max(faces, request.octaves[k].faces);
    }
  }
  thread_local RowScratch scratch;
  const std::size_t points = padded(request.size), face_room = padded(faces) + kPad;
  if (scratch.acc.size() < points) scratch.acc.resize(points);
  if (scratch.face_a.size() < face_room) {
    scratch.face_a.resize(face_room);
    scratch.face_b.resize(face_room);
  }
  HWY_DYNAMIC_DISPATCH(FractalRowKernel)
  (request, scratch.acc.data(), scratch.face_a.data(), scratch.face_b.data());
}

void fractal_rows(const RowsRequest& request) {
  if (request.size == 0 || request.rows == 0) return;
  std::size_t faces = 0;
  for (int k = 0; k < request.plan->count; ++k) {
    if (request.plan->octaves[k].noise_weight != 0.0f) {
      faces = std::max(faces, request.octaves[k].faces);
    }
  }
  thread_local RowScratch scratch;
  const std::size_t points = padded(request.size * request.rows);
  const std::size_t face_room = request.rows * faces + padded(faces) + kPad;
  if (scratch.acc.size() < points) scratch.acc.resize(points);
  if (scratch.face_a.size() < face_room) {
    scratch.face_a.resize(face_room);
    scratch.face_b.resize(face_room);
  }
  HWY_DYNAMIC_DISPATCH(FractalRowsKernel)
  (request, scratch.acc.data(), scratch.face_a.data(), scratch.face_b.data());
}

int64_t compiled_targets() {
  return HWY_TARGETS;
}

float fractal_sum_point(const OctavePlan& plan, const glm::dvec3& p) {
  return SOLTEX_POINT_DISPATCH(FractalSumKernel)(plan, p);
}

float gradient_fractal_sum_dispatched(const OctavePlan& plan, const glm::dvec3& p) {
  return HWY_DYNAMIC_DISPATCH(GradientFractalSumKernel)(plan, p);
}

int64_t dispatched_target() {
  return HWY_DYNAMIC_DISPATCH(TargetOfKernel)();
}

}  // namespace soltex::noise_kernels
#endif  // HWY_ONCE
