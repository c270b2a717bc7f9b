// Runtime dispatch of the evaluated pixels' inputs (evaluated_inputs.h). Highway compiles this
// file once per target (hwy/foreach_target.h re-includes it) and HWY_DYNAMIC_DISPATCH calls the
// widest one the CPU supports, once per batch. Plain per-lane double arithmetic with selects
// for the branches of TextureSurface::normal(), inset() and surface_footprint(), so that the
// compiler runs it in vector lanes; no contraction (-ffp-contract=off holds for every target).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "evaluated_inputs.cpp"
#include "evaluated_inputs.h"

#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <cmath>
#include <limits>

#include "texture_surface.h"

HWY_BEFORE_NAMESPACE();
namespace soltex::render::HWY_NAMESPACE {

void evaluated_inputs_target(const glm::dmat3& m, EvaluatedLanes& e, std::size_t count) {
  alignas(64) EvaluatedLanes::Lanes<double> px, py, pz, width, bx, by, bz;
  constexpr double kMax = std::numeric_limits<double>::max();
  for (std::size_t l = 0; l < count; ++l) {
    const double wx = e.normal_x[l], wy = e.normal_y[l], wz = e.normal_z[l];
    // TextureSurface::normal(): glm's mat3 * vec3, normalised, zero staying zero.
    const double nx = (m[0][0] * wx + m[1][0] * wy) + m[2][0] * wz;
    const double ny = (m[0][1] * wx + m[1][1] * wy) + m[2][1] * wz;
    const double nz = (m[0][2] * wx + m[1][2] * wy) + m[2][2] * wz;
    const double length = std::sqrt(nx * nx + ny * ny + nz * nz);
    const bool has_length = length > 0.0;
    const double ux = has_length ? nx / length : 0.0;
    const double uy = has_length ? ny / length : 0.0;
    const double uz = has_length ? nz / length : 0.0;
    const double footprint = e.footprint[l];
    // inset(): p - n * distance where the distance is finite.
    const double distance = kEvaluatedInset * footprint;
    const bool finite = std::fabs(distance) <= kMax;
    px[l] = finite ? e.position_x[l] - ux * distance : e.position_x[l];
    py[l] = finite ? e.position_y[l] - uy * distance : e.position_y[l];
    pz[l] = finite ? e.position_z[l] - uz * distance : e.position_z[l];
    // surface_footprint(): the disc's extent on each axis plus the inset depth's, or a point
    // where the footprint is not positive (SampleFootprint::isotropic of it: 0).
    const bool positive = footprint > 0.0;
    const double depth = 2.0 * kEvaluatedInset * footprint;
    const auto extent = [&](double c) {
      const double across = 1.0 - c * c;
      return footprint * std::sqrt(across > 0.0 ? across : 0.0) + depth * std::fabs(c);
    };
    width[l] = positive ? footprint : 0.0;
    bx[l] = positive ? extent(ux) : 0.0;
    by[l] = positive ? extent(uy) : 0.0;
    bz[l] = positive ? extent(uz) : 0.0;
  }
  for (std::size_t l = 0; l < count; ++l) {
    e.points[l] = glm::dvec3(px[l], py[l], pz[l]);
    e.footprints[l] = SampleFootprint{width[l], glm::dvec3(bx[l], by[l], bz[l])};
  }
}

}  // namespace soltex::render::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex::render {

HWY_EXPORT(evaluated_inputs_target);

void evaluated_inputs(const glm::dmat3& normal_from_world, EvaluatedLanes& lanes,
                      std::size_t count) {
  HWY_DYNAMIC_DISPATCH(evaluated_inputs_target)(normal_from_world, lanes, count);
}

}  // namespace soltex::render
#endif
