#include <string>

#include "graph_checks.h"
#include "noise_kernels.h"
#include "soltex/common/spec_error.h"

// Turning a node's constant parameters into the settings its kernel reads.
namespace soltex::graph {
namespace {

double number(const Node& node, const NodeDef& def, const char* name) {
  const InputValue* value = find_input(node, name);
  if (value) return std::get<double>(*value);
  for (const InputDef& d : def.inputs) {
    if (std::string(d.name) == name) return d.fallback;
  }
  return 0.0;
}

int choice(const Node& node, const NodeDef& def, const char* name) {
  for (const InputDef& d : def.inputs) {
    if (std::string(d.name) == name) return choice_index(d, find_input(node, name));
  }
  return 0;
}

glm::dvec3 vector(const Node& node, const char* name, double fallback) {
  const InputValue* value = find_input(node, name);
  return value ? vector_of(*value) : glm::dvec3(fallback);
}

// Checks a built-in pattern's parameters with the pattern's own bounds, re-addressing the
// error to the node ("stripes.width" -> "graph.nodes[bands].width").
Pattern checked(const Node& node, Pattern pattern) {
  try {
    TextureSpec spec;
    spec.pattern = pattern;
    validated(spec);
  } catch (const SpecError& e) {
    const std::string& field = e.field();
    const std::size_t dot = field.find('.');
    throw SpecError(input_field(node, dot == std::string::npos ? field : field.substr(dot + 1)),
                    e.value(), e.bound());
  }
  return pattern;
}

Pattern builtin_pattern(const Node& node, const NodeDef& def) {
  const auto n = [&](const char* name) { return number(node, def, name); };
  const auto axis = [&] { return static_cast<Axis>(choice(node, def, "axis")); };
  switch (def.op) {
    case Op::stripes:
      return checked(node, StripesParams{n("width"), n("offset"), axis()});
    case Op::checker:
      return checked(node,
                     CheckerParams{vector(node, "size", 1.0), n("offset"), n("three_d") != 0.0});
    case Op::colour_cube:
      return checked(node, ColourCubeParams{n("period")});
    case Op::rings:
      return checked(node, RingsParams{n("thickness"), n("base"), n("amplitude")});
    case Op::wood:
      return checked(node, WoodParams{n("ring_spacing"), n("tilt_y"), n("tilt_z"), n("twist"),
                                      n("jitter"), n("jitter_scale"), n("grain_fraction")});
    case Op::marble: {
      MarbleParams m;
      m.frequency = n("frequency");
      m.amplitude = n("amplitude");
      m.ripple = static_cast<Ripple>(choice(node, def, "ripple"));
      m.axis = axis();
      return checked(node, m);
    }
    default:
      return StripesParams{};
  }
}

void check_ramp(const Node& node, const ColourRamp& ramp) {
  if (ramp.keys.empty()) {
    throw SpecError(input_field(node, "keys"), "0 keys", "a ramp needs at least one key");
  }
  try {
    TextureSpec spec;
    spec.ramp = ramp;
    validated(spec);
  } catch (const SpecError& e) {
    throw SpecError(input_field(node, e.field().substr(5)), e.value(), e.bound());  // "ramp."
  }
}

}  // namespace

void configure_instruction(const Node& node, const NodeDef& def, Instruction& instr) {
  switch (def.op) {
    case Op::noise3d:
    case Op::fractal3d:
    case Op::turbulence:
      instr.noise.basis =
          choice(node, def, "basis") == 0 ? NoiseBasis::gradient : NoiseBasis::value;
      instr.noise.absolute = def.op == Op::turbulence && instr.noise.basis == NoiseBasis::gradient;
      if (def.op != Op::noise3d) {
        instr.noise.octaves = static_cast<int>(number(node, def, "octaves"));
        instr.noise.lacunarity = number(node, def, "lacunarity");
        instr.noise.diminish = number(node, def, "diminish");
      }
      break;
    case Op::worleynoise3d:
      instr.worley.jitter = number(node, def, "jitter");
      instr.worley.feature = static_cast<WorleyFeature>(choice(node, def, "feature"));
      instr.worley.mean = worley_mean(instr.worley);
      break;
    case Op::extract:
      instr.index = static_cast<int>(number(node, def, "index"));
      break;
    case Op::ramp:
      instr.ramp.keys = std::get<RampKeys>(*find_input(node, "keys"));
      check_ramp(node, instr.ramp);
      break;
    case Op::stripes:
    case Op::checker:
    case Op::colour_cube:
    case Op::rings:
    case Op::wood:
    case Op::marble:
      instr.pattern = builtin_pattern(node, def);
      break;
    default:
      break;
  }
}

void check_parameters(const TextureGraph& graph) {
  for (const Node& node : graph.nodes) {
    const NodeDef& def = *find_node_def(node.category);
    if (def.op == Op::ramp || (def.op >= Op::stripes && def.op <= Op::marble)) {
      Instruction unused;
      configure_instruction(node, def, unused);
    }
  }
}

double node_cost(Op op, const Instruction& instr, ValueType type) {
  const double comps = components(type);
  switch (op) {
    case Op::noise3d:
      return comps;
    case Op::fractal3d:
    case Op::turbulence:
      return comps * instr.noise.octaves;
    case Op::worleynoise3d:
      return 8.0;
    case Op::cellnoise3d:
    case Op::wood:
      return 1.0;
    default:
      return 1.0 / 16.0;
  }
}

}  // namespace soltex::graph
