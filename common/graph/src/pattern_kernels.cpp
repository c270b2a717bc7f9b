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
    double *r = batch.plane(instr.out, 0), *g = batch.plane(instr.out, 1),
           *b = batch.plane(instr.out, 2);
    for (std::size_t i = 0; i < batch.size; ++i) {
      const glm::vec3 colour = instr.ramp.at(static_cast<float>(t[i]));
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
                   each([&](const glm::dvec3& p, const glm::dvec3& box, std::size_t i) {
                     return fields::marble(m, fields::ripple(m, p),
                                           static_cast<float>(turbulence[i]),
                                           fields::ripple_width(m, p, box));
                   });
                 },
                 [&](const auto&) {},
             },
             instr.pattern);
}

}  // namespace soltex::graph
