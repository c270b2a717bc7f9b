#include "soltex/common/texture_evaluator.h"

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "checker_kernel.h"
#include "pattern_fields.h"
#include "soltex/common/overloaded.h"

namespace soltex {
namespace {

// The fractal a pattern uses, if any.
const FractalParams* fractal_of(const Pattern& pattern, FractalParams& storage) {
  if (const auto* noise = std::get_if<NoiseParams>(&pattern)) {
    storage = fields::single_octave(*noise);
    return &storage;
  }
  if (const auto* turbulence = std::get_if<TurbulenceParams>(&pattern)) {
    return &turbulence->fractal;
  }
  if (const auto* marble = std::get_if<MarbleParams>(&pattern)) return &marble->turbulence;
  return nullptr;
}

// cos and sin of wood's tilt about z, fixed per texture.
glm::dvec2 wood_tilt_z(const Pattern& pattern) {
  if (const auto* wood = std::get_if<WoodParams>(&pattern)) {
    return {std::cos(wood->tilt_z), std::sin(wood->tilt_z)};
  }
  return {1.0, 0.0};
}

inline float cube_field(const glm::vec3& c) {
  return (c.r + c.g + c.b) * (1.0f / 3.0f);
}

struct RowScratch {
  std::vector<double> x;
  std::vector<float> field;
  std::vector<glm::vec3> colour;
};

// Graphs: the field a Texel carries is the graph's opacity output, else its specular output.
void sample_graph(const GraphField& graph, std::span<const glm::dvec3> points,
                  std::span<const SampleFootprint> footprints, std::span<Texel> out) {
  const std::size_t n = points.size();
  thread_local std::vector<double> widths;
  thread_local std::vector<float> planes;
  widths.resize(n);
  planes.assign(4 * n, 0.0f);
  for (std::size_t i = 0; i < n; ++i) widths[i] = footprints[i].width;
  GraphPlanes to;
  if (graph.has_colour()) {
    for (int c = 0; c < 3; ++c) to.colour[c] = planes.data() + static_cast<std::size_t>(c) * n;
  }
  float* field = planes.data() + 3 * n;
  if (graph.has_opacity()) {
    to.opacity = field;
  } else if (graph.has_specular()) {
    to.specular = field;
  }
  graph.evaluate_points(points, widths, to);
  for (std::size_t i = 0; i < n; ++i) {
    out[i].colour = {planes[i], planes[n + i], planes[2 * n + i]};
    out[i].field = field[i];
  }
}

// Graphs write their channels straight into the grid's planes; scalar channels then go
// through the spec's ranges, as a pattern's field does.
void evaluate_graph_grid(const GraphField& graph, const TextureSpec& spec, const Grid& grid,
                         double filter_width, std::span<float> out) {
  const std::size_t n = grid.size();
  GraphPlanes to;
  float* plane = out.data();
  if (spec.channels.colour) {
    for (int c = 0; c < 3; ++c, plane += n) to.colour[c] = plane;
  }
  float* opacity = spec.channels.opacity ? plane : nullptr;
  if (opacity) plane += n;
  float* specular = spec.channels.specular ? plane : nullptr;
  to.opacity = opacity;
  to.specular = specular;
  graph.evaluate_grid(grid, filter_width, to);
  for (const auto& [values, range] :
       {std::pair{opacity, &spec.opacity}, {specular, &spec.specular}}) {
    if (values == nullptr) continue;
    for (std::size_t i = 0; i < n; ++i) {
      values[i] = range->low + (range->high - range->low) * values[i];
    }
  }
}

}  // namespace

TextureEvaluator::TextureEvaluator(const TextureSpec& spec)
    : spec_(validated(spec)),
      point_plan_(plan_for(0.0)),
      wood_tilt_z_(wood_tilt_z(spec_.pattern)) {}

OctavePlan TextureEvaluator::plan_for(double filter_width) const {
  FractalParams storage;
  const FractalParams* fractal = fractal_of(spec_.pattern, storage);
  return fractal ? plan_octaves(*fractal, filter_width) : OctavePlan{};
}

int TextureEvaluator::evaluated_octaves(double filter_width) const {
  if (spec_.graph) return spec_.graph->evaluated_octaves(filter_width);
  return plan_for(filter_width).evaluated_octaves();
}

Texel TextureEvaluator::sample(const glm::dvec3& p, double filter_width) const {
  return sample(p, SampleFootprint::isotropic(filter_width));
}

Texel TextureEvaluator::sample(const glm::dvec3& p, const SampleFootprint& footprint) const {
  Texel texel;
  sample({&p, 1}, {&footprint, 1}, {&texel, 1});
  return texel;
}

void TextureEvaluator::sample(std::span<const glm::dvec3> points,
                              std::span<const SampleFootprint> footprints,
                              std::span<Texel> out) const {
  const std::size_t n = points.size();
  if (footprints.size() != n || out.size() < n) {
    throw std::invalid_argument("TextureEvaluator::sample: " + std::to_string(n) + " points, " +
                                std::to_string(footprints.size()) + " footprints, " +
                                std::to_string(out.size()) + " texels");
  }
  if (spec_.graph) {
    sample_graph(*spec_.graph, points, footprints, out);
    return;
  }
  const auto each = [&](auto&& field) {
    for (std::size_t i = 0; i < n; ++i) out[i].field = field(points[i], footprints[i].box);
  };
  // Noise: a plan per point of its own width, made where it is used. (Keeping one plan across
  // a run of equal widths was slower: pixels' widths all differ, and a plan copied in just
  // before it is read stalls the loads that read it.)
  const auto each_fractal = [&](auto&& field) {
    for (std::size_t i = 0; i < n; ++i) {
      const double w = footprints[i].width;
      if (w > 0.0) {
        const OctavePlan plan = plan_for(w);
        out[i].field = field(plan, points[i], footprints[i].box);
      } else {
        out[i].field = field(point_plan_, points[i], footprints[i].box);
      }
    }
  };
  const fields::WoodFrame frame{wood_tilt_z_.x, wood_tilt_z_.y};
  std::visit(
      Overloaded{
          [&](const StripesParams& s) {
            each([&](const glm::dvec3& p, const glm::dvec3& box) {
              return fields::stripes(s, p, box);
            });
          },
          [&](const CheckerParams& c) { checker_fields(c, points, footprints, out); },
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
          [&](const NoiseParams&) {
            each_fractal([&](const OctavePlan& plan, const glm::dvec3& p, const glm::dvec3&) {
              return fields::normalise_fractal(plan, fractal_sum(plan, p));
            });
          },
          [&](const TurbulenceParams&) {
            each_fractal([&](const OctavePlan& plan, const glm::dvec3& p, const glm::dvec3&) {
              return fields::normalise_fractal(plan, fractal_sum(plan, p));
            });
          },
          [&](const MarbleParams& m) {
            each_fractal([&](const OctavePlan& plan, const glm::dvec3& p, const glm::dvec3& box) {
              return fields::marble(m, fields::ripple(m, p), fractal_sum(plan, p),
                                    fields::ripple_width(m, p, box));
            });
          },
      },
      spec_.pattern);
  if (!std::holds_alternative<ColourCubeParams>(spec_.pattern)) {
    for (std::size_t i = 0; i < n; ++i) out[i].colour = spec_.ramp.at(out[i].field);
  }
}

void TextureEvaluator::evaluate_grid(const Grid& grid, double filter_width,
                                     std::span<float> out) const {
  const std::size_t n = grid.size();
  const int channels = spec_.channels.sample_count();
  if (grid.count.x <= 0 || grid.count.y <= 0 || grid.count.z <= 0) {
    throw std::invalid_argument("evaluate_grid: grid.count must be positive on every axis");
  }
  if (out.size() < n * static_cast<std::size_t>(channels)) {
    throw std::invalid_argument("evaluate_grid: output holds " + std::to_string(out.size()) +
                                " floats, the grid needs " +
                                std::to_string(n * static_cast<std::size_t>(channels)));
  }
  if (spec_.graph) {
    evaluate_graph_grid(*spec_.graph, spec_, grid, filter_width, out);
    return;
  }
  const OctavePlan local_plan = filter_width > 0.0 ? plan_for(filter_width) : OctavePlan{};
  const OctavePlan& plan = filter_width > 0.0 ? local_plan : point_plan_;
  const fields::WoodFrame frame{wood_tilt_z_.x, wood_tilt_z_.y};
  // Hard edges are averaged over the sample spacing on every axis, as sample() does.
  const glm::dvec3 box = SampleFootprint::isotropic(filter_width).box;
  const bool is_cube = std::holds_alternative<ColourCubeParams>(spec_.pattern);

  thread_local RowScratch scratch;
  const auto nx = static_cast<std::size_t>(grid.count.x);
  scratch.x.resize(nx);
  scratch.field.resize(nx);
  scratch.colour.resize(nx);
  // The x coordinates are the same in every row.
  for (std::size_t i = 0; i < nx; ++i) scratch.x[i] = grid.point(static_cast<int>(i), 0, 0).x;
  const std::span<const double> xs(scratch.x.data(), nx);
  float* field = scratch.field.data();
  glm::vec3* colour = scratch.colour.data();

  std::optional<FractalRows> fractal_rows;
  if (plan.count > 0) fractal_rows.emplace(plan, xs);

  const auto row_field = [&](double y, double z) {
    const auto each_point = [&](auto&& fn) {
      for (std::size_t i = 0; i < nx; ++i) field[i] = fn(glm::dvec3(xs[i], y, z));
    };
    std::visit(Overloaded{
                   [&](const StripesParams& s) {
                     each_point([&](const glm::dvec3& p) { return fields::stripes(s, p, box); });
                   },
                   [&](const CheckerParams& c) {
                     each_point([&](const glm::dvec3& p) { return fields::checker(c, p, box); });
                   },
                   [&](const ColourCubeParams& c) {
                     for (std::size_t i = 0; i < nx; ++i) {
                       colour[i] = fields::colour_cube(c, glm::dvec3(xs[i], y, z), box);
                       field[i] = cube_field(colour[i]);
                     }
                   },
                   [&](const RingsParams& r) {
                     each_point([&](const glm::dvec3& p) { return fields::rings(r, p, box); });
                   },
                   [&](const WoodParams& w) {
                     const fields::WoodRotation rotation = fields::wood_rotation(w, y);
                     each_point([&](const glm::dvec3& p) {
                       return fields::wood(w, frame, rotation, p, box);
                     });
                   },
                   [&](const NoiseParams&) {
                     fractal_rows->sum(y, z, {field, nx});
                     for (std::size_t i = 0; i < nx; ++i) {
                       field[i] = fields::normalise_fractal(plan, field[i]);
                     }
                   },
                   [&](const TurbulenceParams&) {
                     fractal_rows->sum(y, z, {field, nx});
                     for (std::size_t i = 0; i < nx; ++i) {
                       field[i] = fields::normalise_fractal(plan, field[i]);
                     }
                   },
                   [&](const MarbleParams& m) {
                     fractal_rows->sum(y, z, {field, nx});
                     for (std::size_t i = 0; i < nx; ++i) {
                       field[i] =
                           fields::marble(m, fields::ripple(m, glm::dvec3(xs[i], y, z)), field[i],
                                          fields::ripple_width(m, glm::dvec3(xs[i], y, z), box));
                     }
                   },
               },
               spec_.pattern);
  };

  const ChannelSet& wanted = spec_.channels;
  std::size_t row_start = 0;
  for (int k = 0; k < grid.count.z; ++k) {
    for (int j = 0; j < grid.count.y; ++j, row_start += nx) {
      const glm::dvec3 row_origin = grid.point(0, j, k);
      row_field(row_origin.y, row_origin.z);
      float* plane = out.data() + row_start;
      if (wanted.colour) {
        for (std::size_t i = 0; i < nx; ++i) {
          const glm::vec3 c = is_cube ? colour[i] : spec_.ramp.at(field[i]);
          plane[i] = c.r;
          plane[n + i] = c.g;
          plane[2 * n + i] = c.b;
        }
        plane += 3 * n;
      }
      for (const auto* range : {wanted.opacity ? &spec_.opacity : nullptr,
                                wanted.specular ? &spec_.specular : nullptr}) {
        if (range == nullptr) continue;
        for (std::size_t i = 0; i < nx; ++i) {
          plane[i] = range->low + (range->high - range->low) * field[i];
        }
        plane += n;
      }
    }
  }
}

}  // namespace soltex
