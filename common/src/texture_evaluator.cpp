#include "soltex/common/texture_evaluator.h"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "pattern_fields.h"
#include "pattern_kernels.h"

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

// The ramp the colour planes apply. A field of two values (stripes, checkers, wood's grain,
// rings) averaged over a box is the share of the box at the second value, so the box's colour
// is the blend of the two values' colours: the spec's ramp with those two as its only keys.
// (A ramp with keys between them would colour an edge's average as if the field passed
// through them.) Other fields keep the spec's ramp, averaged over their spread.
ColourRamp applied_ramp(const TextureSpec& spec) {
  const auto two_valued = [&](float low, float high) {
    if (high < low) std::swap(low, high);
    return ColourRamp{{{low, spec.ramp.at(low)}, {high, spec.ramp.at(high)}}};
  };
  if (std::holds_alternative<StripesParams>(spec.pattern) ||
      std::holds_alternative<CheckerParams>(spec.pattern) ||
      std::holds_alternative<WoodParams>(spec.pattern)) {
    return two_valued(0.0f, 1.0f);
  }
  if (const auto* rings = std::get_if<RingsParams>(&spec.pattern)) {
    const double inner = std::clamp(rings->base, 0.0, 1.0);
    const double outer = std::clamp(rings->base + rings->amplitude, 0.0, 1.0);
    return two_valued(static_cast<float>(inner), static_cast<float>(outer));
  }
  return spec.ramp;
}

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
      colour_ramp_(spec_.graph ? ColourRamp{} : applied_ramp(spec_)),
      wood_tilt_z_(wood_tilt_z(spec_.pattern)) {
  FractalParams storage;
  if (const FractalParams* fractal = fractal_of(spec_.pattern, storage)) {
    fractal_ = *fractal;
    has_fractal_ = true;
  }
  point_plan_ = plan_for(0.0);
}

OctavePlan TextureEvaluator::plan_for(double filter_width) const {
  return has_fractal_ ? plan_octaves(fractal_, filter_width) : OctavePlan{};
}

pattern_kernels::PatternSource TextureEvaluator::pattern_source() const {
  return {&spec_,       &colour_ramp_,  has_fractal_ ? &fractal_ : nullptr,
          &point_plan_, wood_tilt_z_.x, wood_tilt_z_.y};
}

int TextureEvaluator::evaluated_octaves(double filter_width) const {
  if (spec_.graph) return spec_.graph->evaluated_octaves(filter_width);
  return plan_for(filter_width).evaluated_octaves();
}

Texel TextureEvaluator::sample(const glm::dvec3& p, double filter_width) const {
  return sample(p, SampleFootprint::isotropic(filter_width));
}

Texel TextureEvaluator::sample(const glm::dvec3& p, const SampleFootprint& footprint) const {
  if (!spec_.graph) return pattern_kernels::sample_point(pattern_source(), p, footprint);
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
  pattern_kernels::sample_points(pattern_source(), points, footprints, out);
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
  // Hard edges are averaged over the sample spacing on every axis, as sample() does.
  const glm::dvec3 box = SampleFootprint::isotropic(filter_width).box;
  pattern_kernels::evaluate_grid(pattern_source(), grid, plan, box, out);
}

}  // namespace soltex
