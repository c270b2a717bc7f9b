// Runtime dispatch of the built-in patterns' batch evaluation (pattern_kernels.h). Highway
// compiles this file once per target (hwy/foreach_target.h re-includes it); HWY_EXPORT builds
// the table of per-target functions and HWY_DYNAMIC_DISPATCH calls the best one for the CPU.
//
// Every header the kernels use comes before foreach_target.h, so its inline functions are
// compiled for the default target where they are emitted out of line, and for each target only
// where a kernel inlines them.

// As in noise_kernels.cpp: every attainable target, and AVX3_DL accepted as a baseline.
#ifndef HWY_COMPILE_ALL_ATTAINABLE
#define HWY_COMPILE_ALL_ATTAINABLE
#endif
#ifndef HWY_WANT_AVX3_DL
#define HWY_WANT_AVX3_DL
#endif

#include "pattern_kernels.h"

#include <algorithm>
#include <cstddef>
#include <optional>
#include <variant>
#include <vector>

#include "checker_kernel.h"
#include "pattern_fields.h"
#include "soltex/common/check.h"
#include "soltex/common/overloaded.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "pattern_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "fractal_point-inl.h"
#include "grid_row_lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace soltex::pattern_kernels::HWY_NAMESPACE {

inline float cube_field(const glm::vec3& c) {
  return (c.r + c.g + c.b) * (1.0f / 3.0f);
}

// Flattened: the field functions are inline code from headers compiled for the default target;
// only inlined here are they compiled for this one.
HWY_FLATTEN void SamplePointsKernel(const PatternSource& source, std::span<const glm::dvec3> points,
                                    std::span<const SampleFootprint> footprints,
                                    std::span<Texel> out) {
  const std::size_t n = points.size();
  const TextureSpec& spec = *source.spec;
  const ColourRamp& ramp = *source.ramp;
  // A field of two values (stripes, checkers, rings, wood): the ramp's colour of the box average
  // is the blend of the two values' colours, which source.ramp holds as its keys.
  const auto each = [&](auto&& field) {
    for (std::size_t i = 0; i < n; ++i) {
      out[i].field = field(points[i], footprints[i].box);
      out[i].colour = ramp.at(out[i].field);
    }
  };
  // Noise: a plan per point of its own width, made where it is used. (Keeping one plan across
  // a run of equal widths was slower: pixels' widths all differ, and a plan copied in just
  // before it is read stalls the loads that read it.)
  const auto each_fractal = [&](auto&& texel) {
    for (std::size_t i = 0; i < n; ++i) {
      const double w = footprints[i].width;
      if (w > 0.0) {
        const OctavePlan plan = plan_octaves(*source.fractal, w);
        texel(plan, points[i], footprints[i].box, out[i]);
      } else {
        texel(*source.point_plan, points[i], footprints[i].box, out[i]);
      }
    }
  };
  const auto fractal_texel = [&](const OctavePlan& plan, const glm::dvec3& p, const glm::dvec3&,
                                 Texel& texel) {
    texel.field =
        fields::normalise_fractal(plan, noise_kernels::HWY_NAMESPACE::FractalSumAt(plan, p));
    texel.colour = ramp.average(texel.field, fields::fractal_spread(plan));
  };
  const fields::WoodFrame frame{source.wood_cos_tilt_z, source.wood_sin_tilt_z};
  std::visit(
      Overloaded{
          [&](const StripesParams& s) {
            each([&](const glm::dvec3& p, const glm::dvec3& box) {
              return fields::stripes(s, p, box);
            });
          },
          // Its own kernel: the filter's branches as selects across the points.
          [&](const CheckerParams& c) {
            checker_fields(c, points, footprints, out);
            for (std::size_t i = 0; i < n; ++i) out[i].colour = ramp.at(out[i].field);
          },
          [&](const ColourCubeParams& c) {
            for (std::size_t i = 0; i < n; ++i) {
              out[i].colour = fields::colour_cube(c, points[i], footprints[i].box);
              out[i].field = cube_field(out[i].colour);
            }
          },
          [&](const RingsParams& r) {
            each([&](const glm::dvec3& p, const glm::dvec3& box) {
              return fields::rings(r, p, box);
            });
          },
          [&](const WoodParams& w) {
            each([&](const glm::dvec3& p, const glm::dvec3& box) {
              return fields::wood(w, frame, fields::wood_rotation(w, p.y), p, box);
            });
          },
          [&](const NoiseParams&) { each_fractal(fractal_texel); },
          [&](const TurbulenceParams&) { each_fractal(fractal_texel); },
          [&](const MarbleParams& m) {
            each_fractal([&](const OctavePlan& plan, const glm::dvec3& p, const glm::dvec3& box,
                             Texel& texel) {
              const double ripple_width = fields::ripple_width(m, p, box);
              const double sine = fields::marble_sine(
                  m, fields::ripple(m, p), noise_kernels::HWY_NAMESPACE::FractalSumAt(plan, p));
              texel.field = fields::marble_of_sine(sine, fields::marble_fade(ripple_width));
              texel.colour = ramp.average(
                  texel.field, fields::marble_spread(fields::marble_spread_terms(
                                                         m, ripple_width, plan.unresolved_variance),
                                                     sine));
            });
          },
      },
      spec.pattern);
}

// Per grid: the x coordinates (the same in every row), the field and its spread within a
// sample's box (ColourRamp::average) at every point, so that the ramp runs over the whole grid
// at once (a row of 17 would leave a scalar tail per row), and what a separable pattern's
// points share along x (the checker's x factors, the colour cube's red); per row, the colour
// cube's colours.
struct RowScratch {
  std::vector<double> x;
  std::vector<float> field;
  std::vector<float> spread;
  std::vector<glm::vec3> colour;
  std::vector<double> checker_x;
  std::vector<float> cube_red;
  std::vector<double> wood;                          // WoodRow's scratch, 3 per point of a row
  std::vector<fields::WoodRotation> wood_rotations;  // per y index: wood's rotation about y
  std::vector<double> plane_y, plane_z;              // a plane's rows' y and z, for sum_rows
};

// One row's field (and the colour cube's colours, and marble's spreads) at (xs[i], y, z).
struct RowFields {
  const Pattern& pattern;
  const OctavePlan& plan;
  const fields::WoodFrame frame;
  const glm::dvec3& box;
  const std::optional<FractalRows>& fractal_rows;
  std::span<const double> xs;
  glm::vec3* colour;
  const double* checker_x;  // fields::checker_factor along x at xs, for a checker
  const float* cube_red;    // fields::colour_cube_channel along x at xs, for a colour cube
  double* wood_scratch;     // 3 * xs.size() doubles, for wood
  const fields::WoodRotation* wood_rotations;   // by the row's y index, for wood
  const fields::MarbleAxisFilter* marble_axis;  // for marble rippling along an axis

  // The row at y index j, (xs[i], y, z), into the row's `field` and (for marble) `spread`.
  void operator()(int j, double y, double z, float* field, float* spread) const {
    const std::size_t nx = xs.size();
    const auto each_point = [&](auto&& fn) {
      for (std::size_t i = 0; i < nx; ++i) field[i] = fn(glm::dvec3(xs[i], y, z));
    };
    // The fractal patterns' `field` holds the row's sums already: EvaluateGridKernel sums a
    // plane's rows at once (FractalRows::sum_rows).
    const auto fractal_field = [&] {
      for (std::size_t i = 0; i < nx; ++i) field[i] = fields::normalise_fractal(plan, field[i]);
    };
    std::visit(Overloaded{
                   [&](const StripesParams& s) {
                     each_point([&](const glm::dvec3& p) { return fields::stripes(s, p, box); });
                   },
                   [&](const CheckerParams& c) {
                     const double fy = fields::checker_factor(c, 1, y, box.y);
                     const double fz = c.three_d ? fields::checker_factor(c, 2, z, box.z) : 1.0;
                     for (std::size_t i = 0; i < nx; ++i) {
                       field[i] = fields::checker_of_factors(c, checker_x[i], fy, fz);
                     }
                   },
                   [&](const ColourCubeParams& c) {
                     const float green = fields::colour_cube_channel(c, y, box.y);
                     const float blue = fields::colour_cube_channel(c, z, box.z);
                     for (std::size_t i = 0; i < nx; ++i) {
                       colour[i] = glm::vec3(cube_red[i], green, blue);
                       field[i] = cube_field(colour[i]);
                     }
                   },
                   [&](const RingsParams& r) {
                     each_point([&](const glm::dvec3& p) { return fields::rings(r, p, box); });
                   },
                   [&](const WoodParams& w) {
                     WoodRow(w, frame, wood_rotations[j], xs.data(), y, z, box, wood_scratch, field,
                             nx);
                   },
                   [&](const NoiseParams&) { fractal_field(); },
                   [&](const TurbulenceParams&) { fractal_field(); },
                   [&](const MarbleParams& m) {
                     if (m.ripple == Ripple::axis) {
                       MarbleAxisRow(m, *marble_axis, xs.data(), y, z, field, spread, nx);
                       return;
                     }
                     for (std::size_t i = 0; i < nx; ++i) {
                       const glm::dvec3 p(xs[i], y, z);
                       const double width = fields::ripple_width(m, p, box);
                       const double sine = fields::marble_sine(m, fields::ripple(m, p), field[i]);
                       field[i] = fields::marble_of_sine(sine, fields::marble_fade(width));
                       spread[i] = fields::marble_spread(
                           fields::marble_spread_terms(m, width, plan.unresolved_variance), sine);
                     }
                   },
               },
               pattern);
  }
};

// The x tables of the separable patterns (RowScratch::checker_x, cube_red), once per grid, and
// wood's scratch.
void fill_separable_x(const Pattern& pattern, std::span<const double> xs, const glm::dvec3& box,
                      RowScratch& scratch) {
  if (const auto* c = std::get_if<CheckerParams>(&pattern)) {
    scratch.checker_x.resize(xs.size());
    for (std::size_t i = 0; i < xs.size(); ++i) {
      scratch.checker_x[i] = fields::checker_factor(*c, 0, xs[i], box.x);
    }
  } else if (const auto* cube = std::get_if<ColourCubeParams>(&pattern)) {
    scratch.cube_red.resize(xs.size());
    for (std::size_t i = 0; i < xs.size(); ++i) {
      scratch.cube_red[i] = fields::colour_cube_channel(*cube, xs[i], box.x);
    }
  } else if (std::holds_alternative<WoodParams>(pattern)) {
    scratch.wood.resize(3 * xs.size());
  }
}

// A grid's planes from its fields (and their spreads, or nullptr where there are none): the
// colours through the ramp (the colour cube writes its own), then the scalar channels' ranges.
void WritePlanes(const PatternSource& source, const float* field, const float* spread,
                 std::size_t n, std::span<float> out) {
  const TextureSpec& spec = *source.spec;
  const ChannelSet& wanted = spec.channels;
  float* plane = out.data();
  if (wanted.colour) {
    const ColourRamp& ramp = *source.ramp;
    SOLTEX_DCHECK(!ramp.keys.empty());  // validated() fills an empty ramp with the default
    if (std::holds_alternative<ColourCubeParams>(spec.pattern)) {
      // written row by row
    } else if (spread != nullptr) {
      RampAveragePlanes(ramp, RampSteps(ramp), field, spread, n, plane, plane + n, plane + 2 * n);
    } else {
      RampPlanes(ramp, field, n, plane, plane + n, plane + 2 * n);
    }
    plane += 3 * n;
  }
  for (const auto* range :
       {wanted.opacity ? &spec.opacity : nullptr, wanted.specular ? &spec.specular : nullptr}) {
    if (range == nullptr) continue;
    for (std::size_t i = 0; i < n; ++i) {
      plane[i] = range->low + (range->high - range->low) * field[i];
    }
    plane += n;
  }
}

HWY_FLATTEN void EvaluateGridKernel(const PatternSource& source, const Grid& grid,
                                    const OctavePlan& plan, const glm::dvec3& box,
                                    std::span<float> out) {
  const TextureSpec& spec = *source.spec;
  const std::size_t n = grid.size();
  const bool is_cube = std::holds_alternative<ColourCubeParams>(spec.pattern);
  thread_local RowScratch scratch;
  const auto nx = static_cast<std::size_t>(grid.count.x);
  scratch.x.resize(nx);
  scratch.field.resize(n);
  scratch.spread.resize(n);
  scratch.colour.resize(nx);
  for (std::size_t i = 0; i < nx; ++i) scratch.x[i] = grid.point(static_cast<int>(i), 0, 0).x;
  const std::span<const double> xs(scratch.x.data(), nx);
  fill_separable_x(spec.pattern, xs, box, scratch);
  // Wood's rotation about y depends on y alone: once per y index, not once per row.
  if (const auto* w = std::get_if<WoodParams>(&spec.pattern)) {
    scratch.wood_rotations.resize(static_cast<std::size_t>(grid.count.y));
    for (int j = 0; j < grid.count.y; ++j) {
      scratch.wood_rotations[static_cast<std::size_t>(j)] =
          fields::wood_rotation(*w, grid.point(0, j, 0).y);
    }
  }
  float* field = scratch.field.data();
  glm::vec3* colour = scratch.colour.data();
  fields::MarbleAxisFilter marble_axis{};
  if (const auto* m = std::get_if<MarbleParams>(&spec.pattern)) {
    marble_axis = fields::marble_axis_filter(*m, box, plan.unresolved_variance);
  }
  // The fractal patterns sum a plane's rows in one call (FractalRows::sum_rows).
  const bool fractal_pattern =
      plan.count > 0 && (std::holds_alternative<NoiseParams>(spec.pattern) ||
                         std::holds_alternative<TurbulenceParams>(spec.pattern) ||
                         std::holds_alternative<MarbleParams>(spec.pattern));
  std::optional<FractalRows> fractal_rows;
  if (fractal_pattern) fractal_rows.emplace(plan, xs, static_cast<std::size_t>(grid.count.y));
  const RowFields row_field{spec.pattern,
                            plan,
                            {source.wood_cos_tilt_z, source.wood_sin_tilt_z},
                            box,
                            fractal_rows,
                            xs,
                            colour,
                            scratch.checker_x.data(),
                            scratch.cube_red.data(),
                            scratch.wood.data(),
                            scratch.wood_rotations.data(),
                            &marble_axis};

  const ChannelSet& wanted = spec.channels;
  // A fractal's spread is the grid's (one plan); marble's is each point's; the other fields
  // have two values, which the ramp's keys already blend.
  const bool is_marble = std::holds_alternative<MarbleParams>(spec.pattern);
  const float fractal_spread = is_marble ? 0.0f : fields::fractal_spread(plan);
  if (fractal_spread > 0.0f) std::fill_n(scratch.spread.begin(), n, fractal_spread);
  const bool has_spread = is_marble || fractal_spread > 0.0f;
  std::size_t row_start = 0;
  const auto ny = static_cast<std::size_t>(grid.count.y);
  scratch.plane_y.resize(ny);
  scratch.plane_z.resize(ny);
  for (int k = 0; k < grid.count.z; ++k) {
    if (fractal_pattern) {
      for (std::size_t j = 0; j < ny; ++j) {
        const glm::dvec3 row_origin = grid.point(0, static_cast<int>(j), k);
        scratch.plane_y[j] = row_origin.y;
        scratch.plane_z[j] = row_origin.z;
      }
      fractal_rows->sum_rows(scratch.plane_y, scratch.plane_z, {field + row_start, ny * nx});
    }
    for (int j = 0; j < grid.count.y; ++j, row_start += nx) {
      const glm::dvec3 row_origin = grid.point(0, j, k);
      row_field(j, row_origin.y, row_origin.z, field + row_start,
                scratch.spread.data() + row_start);
      if (is_cube && wanted.colour) {
        for (std::size_t i = 0; i < nx; ++i) {
          out[row_start + i] = colour[i].r;
          out[n + row_start + i] = colour[i].g;
          out[2 * n + row_start + i] = colour[i].b;
        }
      }
    }
  }
  WritePlanes(source, field, has_spread ? scratch.spread.data() : nullptr, n, out);
}

int64_t TargetOfKernel() {
  return HWY_TARGET;
}

}  // namespace soltex::pattern_kernels::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace soltex::pattern_kernels {

HWY_EXPORT(SamplePointsKernel);
HWY_EXPORT(EvaluateGridKernel);
HWY_EXPORT(TargetOfKernel);

void sample_points(const PatternSource& source, std::span<const glm::dvec3> points,
                   std::span<const SampleFootprint> footprints, std::span<Texel> out) {
  HWY_DYNAMIC_DISPATCH(SamplePointsKernel)(source, points, footprints, out);
}

Texel sample_point(const PatternSource& source, const glm::dvec3& p,
                   const SampleFootprint& footprint) {
  Texel texel;
  SOLTEX_POINT_DISPATCH(SamplePointsKernel)(source, {&p, 1}, {&footprint, 1}, {&texel, 1});
  return texel;
}

void evaluate_grid(const PatternSource& source, const Grid& grid, const OctavePlan& plan,
                   const glm::dvec3& box, std::span<float> out) {
  HWY_DYNAMIC_DISPATCH(EvaluateGridKernel)(source, grid, plan, box, out);
}

int64_t compiled_targets() {
  return HWY_TARGETS;
}

int64_t dispatched_target() {
  return HWY_DYNAMIC_DISPATCH(TargetOfKernel)();
}

}  // namespace soltex::pattern_kernels
#endif  // HWY_ONCE
