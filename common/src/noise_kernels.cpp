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

// Mul then Add, never fused: the build forbids contraction so that every target and the
// scalar path round alike.
template <class V>
HWY_INLINE V Lerp(V a, V b, V t) {
  return hn::Add(a, hn::Mul(t, hn::Sub(b, a)));
}

// fade(t) = t * t * t * (t * (t * 6 - 15) + 10), in gradient_noise.h's order.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V Fade(D df, V t) {
  const V poly = hn::Add(hn::Mul(t, hn::Sub(hn::Mul(t, hn::Set(df, 6.0f)), hn::Set(df, 15.0f))),
                         hn::Set(df, 10.0f));
  return hn::Mul(hn::Mul(hn::Mul(t, t), t), poly);
}

// detail::gradient_component for a vector of hashes already shifted left by one (2 * h).
template <class D>
HWY_INLINE hn::Vec<D> GradientComponent(D df, uint32_t packed,
                                        hn::Vec<hn::RebindToSigned<D>> twice_h) {
  const hn::RebindToSigned<D> di;
  const hn::RebindToUnsigned<D> du;
  const auto bits =
      hn::And(hn::Shr(hn::Set(du, packed), hn::BitCast(du, twice_h)), hn::Set(du, 3u));
  return hn::ConvertTo(df, hn::Sub(hn::BitCast(di, bits), hn::Set(di, 1)));
}

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
        contiguous_(hn::AllTrue(DI(), hn::Eq(x_, hn::Iota(DI(), x0_)))) {}

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

// The y-z quantities of gradient_row, per lane.
template <class D>
struct GradientRowVec {
  hn::Vec<D> fy0, fy1, fz0, fz1;  // fractions and fractions - 1
  hn::Vec<D> v, w;                // fade(fy), fade(fz)
};

// gradient_cell_edges' face from its four corner hashes perm[x + h<dy><dz>] (unmasked):
// value(fx) = offset + slope * (fx - dx).
template <class D, class VI = hn::Vec<hn::RebindToSigned<D>>>
HWY_INLINE void GradientFace(D df, const GradientRowVec<D>& row, VI p00, VI p10, VI p01, VI p11,
                             hn::Vec<D>& slope, hn::Vec<D>& offset) {
  const hn::RebindToSigned<D> di;
  using V = hn::Vec<D>;
  // (hash & 15) * 2: the shift GradientComponent needs.
  const auto twice = [&](VI hash) {
    const VI masked = hn::And(hash, hn::Set(di, 15));
    return hn::Add(masked, masked);
  };
  const VI h00 = twice(p00), h10 = twice(p10), h01 = twice(p01), h11 = twice(p11);
  const auto gx = [&](VI h2) { return GradientComponent(df, detail::kPackedX, h2); };
  const auto dot = [&](VI h2, V fy, V fz) {
    return hn::Add(hn::Mul(GradientComponent(df, detail::kPackedY, h2), fy),
                   hn::Mul(GradientComponent(df, detail::kPackedZ, h2), fz));
  };
  const V s0 = Lerp(gx(h00), gx(h10), row.v);
  const V s1 = Lerp(gx(h01), gx(h11), row.v);
  const V o0 = Lerp(dot(h00, row.fy0, row.fz0), dot(h10, row.fy1, row.fz0), row.v);
  const V o1 = Lerp(dot(h01, row.fy0, row.fz1), dot(h11, row.fy1, row.fz1), row.v);
  slope = Lerp(s0, s1, row.w);
  offset = Lerp(o0, o1, row.w);
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

// One evaluated octave along the row, added into acc (padded length).
void AddOctave(const OctavePlan& plan, const Octave& octave, const OctaveColumnsView& c,
               std::size_t n, double y, double z, float* HWY_RESTRICT acc,
               float* HWY_RESTRICT face_a, float* HWY_RESTRICT face_b) {
  const NoiseTables& tables = noise_tables();
  const LatticeSplit sy = split_lattice(y * octave.frequency);
  const LatticeSplit sz = split_lattice(z * octave.frequency);
  const float weight = octave.noise_weight, mean = octave.mean_term;
  if (plan.basis == NoiseBasis::value) {
    const RowHashes hashes = row_hashes(tables, sy.cell, sz.cell);
    WithFaceWidth(c.faces, [&](auto d) {
      ValueFaces(d, tables, c.face_x, c.faces, hashes, sy.frac, sz.frac, face_a);
    });
    if (plan.absolute) {
      ValuePoints<true>(c, n, face_a, weight, mean, acc);
    } else {
      ValuePoints<false>(c, n, face_a, weight, mean, acc);
    }
    return;
  }
  const GradientRow row = gradient_row(tables, sy, sz);
  WithFaceWidth(c.faces,
                [&](auto d) { GradientFaces(d, tables, c.face_x, c.faces, row, face_a, face_b); });
  if (plan.absolute) {
    GradientPoints<true>(c, n, face_a, face_b, weight, mean, acc);
  } else {
    GradientPoints<false>(c, n, face_a, face_b, weight, mean, acc);
  }
}

// acc holds padded(size) entries, face_a and face_b padded(faces) + kPad for the widest octave.
void FractalRowKernel(const RowRequest& r, float* HWY_RESTRICT acc, float* HWY_RESTRICT face_a,
                      float* HWY_RESTRICT face_b) {
  const DF df;
  const std::size_t n = padded(r.size);
  std::fill(acc, acc + n, 0.0f);
  for (int k = 0; k < r.plan->count; ++k) {
    const Octave& octave = r.plan->octaves[k];
    if (octave.noise_weight == 0.0f) {
      const VF mean = hn::Set(df, octave.mean_term);
      for (std::size_t i = 0; i < n; i += hn::Lanes(df)) {
        hn::StoreU(hn::Add(hn::LoadU(df, acc + i), mean), df, acc + i);
      }
      continue;
    }
    AddOctave(*r.plan, octave, r.octaves[k], n, r.y, r.z, acc, face_a, face_b);
  }
  std::copy(acc, acc + r.size, r.out);
}

// ---- One point, one octave per lane ------------------------------------------------------
//
// fractal_sum's octaves are independent noise evaluations at one point: lanes of doubles carry
// the octaves' lattice coordinates, and lanes of floats (as many) their noise.

template <class D64>
struct SplitVec {
  hn::Vec<hn::Rebind<int32_t, D64>> cell;
  hn::Vec<hn::Rebind<float, D64>> frac;
};

// split_lattice per lane: the same cell and fraction. floor(t) mod 256 comes from
// whole - 256 * floor(whole / 256), exact in double, so no 64-bit integer conversion is needed.
template <class D64>
HWY_INLINE SplitVec<D64> SplitLattice(D64 dd, hn::Vec<D64> t) {
  t = hn::IfThenElseZero(hn::Lt(hn::Abs(t), hn::Set(dd, 0x1p62)), t);
  const auto whole = hn::Floor(t);
  const auto high = hn::Floor(hn::Mul(whole, hn::Set(dd, 1.0 / 256.0)));
  const auto wrapped = hn::Sub(whole, hn::Mul(hn::Set(dd, 256.0), high));
  return {hn::DemoteTo(hn::Rebind<int32_t, D64>(), wrapped),
          hn::DemoteTo(hn::Rebind<float, D64>(), hn::Sub(t, whole))};
}

// Gradient noise at lattice points (tx, ty, tz), one per lane: gradient_noise's operations.
template <class D64>
HWY_INLINE hn::Vec<hn::Rebind<float, D64>> GradientNoise(D64 dd, hn::Vec<D64> tx, hn::Vec<D64> ty,
                                                         hn::Vec<D64> tz) {
  using DF32 = hn::Rebind<float, D64>;
  using DI32 = hn::Rebind<int32_t, D64>;
  using VI = hn::Vec<DI32>;
  const DF32 df;
  const DI32 di;
  const int32_t* HWY_RESTRICT perm = noise_tables().perm.data();
  const SplitVec<D64> x = SplitLattice(dd, tx), y = SplitLattice(dd, ty), z = SplitLattice(dd, tz);
  const auto p = [&](VI cell, VI h) { return hn::GatherIndex(di, perm, hn::Add(cell, h)); };
  const VI one = hn::Set(di, 1);
  // row_hashes
  const VI pz0 = hn::GatherIndex(di, perm, z.cell), pz1 = p(z.cell, one);
  const VI y1 = hn::Add(y.cell, one);
  const VI h00 = p(y.cell, pz0), h10 = p(y1, pz0), h01 = p(y.cell, pz1), h11 = p(y1, pz1);
  const auto one_f = hn::Set(df, 1.0f);
  const GradientRowVec<DF32> row{y.frac,           hn::Sub(y.frac, one_f),
                                 z.frac,           hn::Sub(z.frac, one_f),
                                 Fade(df, y.frac), Fade(df, z.frac)};
  const VI x1 = hn::Add(x.cell, one);
  hn::Vec<DF32> slope0, offset0, slope1, offset1;
  GradientFace(df, row, p(x.cell, h00), p(x.cell, h10), p(x.cell, h01), p(x.cell, h11), slope0,
               offset0);
  GradientFace(df, row, p(x1, h00), p(x1, h10), p(x1, h01), p(x1, h11), slope1, offset1);
  // gradient_cell_finish
  const auto a0 = hn::Add(offset0, hn::Mul(slope0, x.frac));
  const auto a1 = hn::Add(offset1, hn::Mul(slope1, hn::Sub(x.frac, one_f)));
  return Lerp(a0, a1, Fade(df, x.frac));
}

// fractal_sum in the gradient basis: the octave terms in lanes, then summed in octave order as
// the definition does.
float GradientFractalSumKernel(const OctavePlan& plan, const glm::dvec3& point) {
  using D64 = hn::ScalableTag<double>;
  const D64 dd;
  const hn::Rebind<float, D64> df;
  static_assert(OctavePlan::kLaneRoom >= SpecLimits::kMaxOctaveCount + kPad);
  HWY_ALIGN float term[OctavePlan::kLaneRoom];
  const std::size_t count = static_cast<std::size_t>(plan.count);
  for (std::size_t k = 0; k < count; k += hn::Lanes(dd)) {
    const auto f = hn::Load(dd, plan.lane_frequency.data() + k);
    auto noise = GradientNoise(dd, hn::Mul(hn::Set(dd, point.x), f),
                               hn::Mul(hn::Set(dd, point.y), f), hn::Mul(hn::Set(dd, point.z), f));
    if (plan.absolute) noise = hn::Abs(noise);
    const auto w = hn::Load(df, plan.lane_noise_weight.data() + k);
    const auto m = hn::Load(df, plan.lane_mean_term.data() + k);
    // octave_term; a faded-out octave adds its mean alone, as fractal_sum's definition says.
    const auto t = hn::IfThenElse(hn::Eq(w, hn::Zero(df)), m, hn::Add(hn::Mul(w, noise), m));
    hn::Store(t, df, term + k);
  }
  float sum = 0.0f;
  for (std::size_t k = 0; k < count; ++k) sum += term[k];
  return sum;
}

int64_t TargetOfKernel() {
  return HWY_TARGET;
}

}  // namespace soltex::noise_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex::noise_kernels {

HWY_EXPORT(FractalRowKernel);
HWY_EXPORT(TargetOfKernel);
HWY_EXPORT(GradientFractalSumKernel);

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

int64_t compiled_targets() {
  return HWY_TARGETS;
}

float gradient_fractal_sum(const OctavePlan& plan, const glm::dvec3& p) {
  SOLTEX_DCHECK(plan.basis == NoiseBasis::gradient);
  return HWY_STATIC_DISPATCH(GradientFractalSumKernel)(plan, p);
}

float gradient_fractal_sum_dispatched(const OctavePlan& plan, const glm::dvec3& p) {
  return HWY_DYNAMIC_DISPATCH(GradientFractalSumKernel)(plan, p);
}

int64_t dispatched_target() {
  return HWY_DYNAMIC_DISPATCH(TargetOfKernel)();
}

}  // namespace soltex::noise_kernels
#endif  // HWY_ONCE
