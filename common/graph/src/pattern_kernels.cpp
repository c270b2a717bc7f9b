#include <cmath>

#include "graph_batch.h"
#include "pattern_fields.h"
#include "soltex/common/overloaded.h"

// The built-in patterns as nodes: the same field functions the patterns use, with hard edges
// averaged over a box as wide as the filter width at the node's position.
namespace soltex::graph {

void run_pattern(const Program& program, const Instruction& instr, Batch& batch) {
  if (instr.op == Op::ramp) {
    const double* t = batch.plane(instr.in[0], 0);
    const int variance_reg = program.registers[static_cast<std::size_t>(instr.in[0])].variance;
    const double* variance = variance_reg >= 0 ? batch.plane(variance_reg, 0) : nullptr;
    double *r = batch.plane(instr.out, 0), *g = batch.plane(instr.out, 1),
           *b = batch.plane(instr.out, 2);
    for (std::size_t i = 0; i < batch.size; ++i) {
      const float spread = variance ? fields::even_spread(variance[i]) : 0.0f;
      const glm::vec3 colour = instr.ramp.average(static_cast<float>(t[i]), spread);
      r[i] = colour.r;
      g[i] = colour.g;
      b[i] = colour.b;
    }
    return;
  }
  const int position_reg = instr.in[0];
  const double scale = program.registers[static_cast<std::size_t>(position_reg)].width_scale;
  const double *px = batch.plane(position_reg, 0), *py = batch.plane(position_reg, 1),
               *pz = batch.plane(position_reg, 2);
  const std::size_t n = batch.size;
  double* out = batch.plane(instr.out, 0);
  const auto each = [&](auto&& field) {
    for (std::size_t i = 0; i < n; ++i) {
      const double w = scale * batch.widths[i];
      const glm::dvec3 box(w > 0.0 ? w : 0.0);
      out[i] = static_cast<double>(field(glm::dvec3(px[i], py[i], pz[i]), box, i));
    }
  };
  std::visit(Overloaded{
                 [&](const StripesParams& s) {
                   each([&](const glm::dvec3& p, const glm::dvec3& box, std::size_t) {
                     return fields::stripes(s, p, box);
                   });
                 },
                 [&](const CheckerParams& c) {
                   each([&](const glm::dvec3& p, const glm::dvec3& box, std::size_t) {
                     return fields::checker(c, p, box);
                   });
                 },
                 [&](const ColourCubeParams& c) {
                   double* g = batch.plane(instr.out, 1);
                   double* b = batch.plane(instr.out, 2);
                   for (std::size_t i = 0; i < n; ++i) {
                     const double w = scale * batch.widths[i];
                     const glm::vec3 colour = fields::colour_cube(
                         c, glm::dvec3(px[i], py[i], pz[i]), glm::dvec3(w > 0.0 ? w : 0.0));
                     out[i] = colour.r;
                     g[i] = colour.g;
                     b[i] = colour.b;
                   }
                 },
                 [&](const RingsParams& r) {
                   each([&](const glm::dvec3& p, const glm::dvec3& box, std::size_t) {
                     return fields::rings(r, p, box);
                   });
                 },
                 [&](const WoodParams& w) {
                   const fields::WoodFrame frame{std::cos(w.tilt_z), std::sin(w.tilt_z)};
                   each([&](const glm::dvec3& p, const glm::dvec3& box, std::size_t) {
                     return fields::wood(w, frame, fields::wood_rotation(w, p.y), p, box);
                   });
                 },
                 [&](const MarbleParams& m) {
                   const double* turbulence = batch.plane(instr.in[1], 0);
                   const int turbulence_variance_reg =
                       program.registers[static_cast<std::size_t>(instr.in[1])].variance;
                   const double* turbulence_variance = turbulence_variance_reg >= 0
                                                           ? batch.plane(turbulence_variance_reg, 0)
                                                           : nullptr;
                   double* variance =
                       instr.variance_out >= 0 ? batch.plane(instr.variance_out, 0) : nullptr;
                   each([&](const glm::dvec3& p, const glm::dvec3& box, std::size_t i) {
                     const double width = fields::ripple_width(m, p, box);
                     const double sine = fields::marble_sine(m, fields::ripple(m, p),
                                                             static_cast<float>(turbulence[i]));
                     if (variance != nullptr) {
                       variance[i] = fields::marble_variance(
                           fields::marble_spread_terms(
                               m, width, turbulence_variance ? turbulence_variance[i] : 0.0),
                           sine);
                     }
                     return fields::marble_of_sine(sine, fields::marble_fade(width));
                   });
                 },
                 [&](const auto&) {},
             },
             instr.pattern);
}

}  // namespace soltex::graph
