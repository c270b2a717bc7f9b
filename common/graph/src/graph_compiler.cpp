#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "graph_checks.h"
#include "noise_kernels.h"
#include "program.h"
#include "soltex/common/check.h"
#include "soltex/common/spec_error.h"
#include "soltex/graph/compiled_graph.h"
#include "soltex/graph/graph_limits.h"

namespace soltex::graph {
namespace {

// The canonical form: instructions in the order the outputs reach them (inputs in catalogue
// order), registers by number. Node names appear nowhere, so renaming or reordering nodes
// leaves it unchanged.
class CanonicalWriter {
 public:
  void u8(uint8_t v) { bytes_.push_back(v); }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void f64(double v) {
    const uint64_t bits = std::bit_cast<uint64_t>(v == 0.0 ? 0.0 : v);
    for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<uint8_t>(bits >> (8 * i)));
  }
  std::vector<uint8_t> take() { return std::move(bytes_); }

 private:
  std::vector<uint8_t> bytes_;
};

// A scalar instruction that scales and shifts one input by constants: that input and the
// scale. Its output varies within a sample's box as the input does, times the scale.
struct Affine {
  int input;
  double gain;
};

std::optional<Affine> affine_of(const Instruction& instr, const std::vector<Register>& regs) {
  if (regs[static_cast<std::size_t>(instr.out)].components != 1) return std::nullopt;
  const auto constant = [&](int k) { return regs[static_cast<std::size_t>(instr.in[k])].constant; };
  const auto value = [&](int k) { return regs[static_cast<std::size_t>(instr.in[k])].value.x; };
  switch (instr.op) {
    case Op::add:
    case Op::subtract:
    case Op::multiply:
      if (constant(0) == constant(1)) return std::nullopt;
      if (instr.op != Op::multiply) return Affine{constant(0) ? instr.in[1] : instr.in[0], 1.0};
      return Affine{constant(0) ? instr.in[1] : instr.in[0], constant(0) ? value(0) : value(1)};
    case Op::divide:
      if (constant(0) || !constant(1)) return std::nullopt;
      return Affine{instr.in[0], value(1) != 0.0 ? 1.0 / value(1) : 0.0};  // x / 0 is 0
    case Op::remap: {
      if (constant(0) || !(constant(1) && constant(2) && constant(3) && constant(4))) {
        return std::nullopt;
      }
      const double span = value(2) - value(1);
      return Affine{instr.in[0], span != 0.0 ? (value(4) - value(3)) / span : 0.0};
    }
    default:
      return std::nullopt;
  }
}

// Per-component texture-space axes a value depends on (bit 0 x, 1 y, 2 z).
using Deps = std::array<uint8_t, 3>;

class Lowering {
 public:
  Lowering(const TextureGraph& graph, const NodeIndex& index, const std::vector<ValueType>& types)
      : graph_(graph), index_(index), types_(types), node_register_(graph.nodes.size(), -1) {}

  std::unique_ptr<Program> run() {
    program_ = std::make_unique<Program>();
    program_->position = new_register(3, false, glm::dvec3(0.0), 1.0, {1, 2, 4});
    writer_.u8(0x47);  // 'G'
    for (Channel channel : {Channel::colour, Channel::opacity, Channel::specular}) {
      int reg = -1;
      for (const GraphOutput& out : graph_.outputs) {
        if (out.channel == channel) reg = lower(index_.at(out.node));
      }
      writer_.u32(static_cast<uint32_t>(reg + 1));
      (channel == Channel::colour    ? program_->colour
       : channel == Channel::opacity ? program_->opacity
                                     : program_->specular) = reg;
    }
    add_variances();
    return std::move(program_);
  }
  std::vector<uint8_t> canonical() { return writer_.take(); }

 private:
  int new_register(int components, bool constant, glm::dvec3 value, double width_scale, Deps deps) {
    Register r;
    r.components = components;
    r.constant = constant;
    r.value = value;
    r.width_scale = width_scale;
    deps_.push_back(deps);
    r.separable = (deps[0] & ~1) == 0 && (deps[1] & ~2) == 0 && (deps[2] & ~4) == 0;
    program_->registers.push_back(r);
    return static_cast<int>(program_->registers.size()) - 1;
  }

  int constant_register(const InputValue& value, int comps) {
    glm::dvec3 v(0.0);
    if (const auto* d = std::get_if<double>(&value)) v = glm::dvec3(*d);
    if (const auto* vec = std::get_if<glm::dvec3>(&value)) v = *vec;
    writer_.u8(0x43);  // 'C'
    writer_.u8(static_cast<uint8_t>(comps));
    for (int c = 0; c < comps; ++c) writer_.f64(v[c]);
    return new_register(comps, true, v, 0.0, {0, 0, 0});
  }

  // A variance register for each scalar noise and marble node, and each scaling or shift of
  // one by constants, whose value a ramp reads (or, for a noise node, a marble node that a ramp
  // reads), numbered after every other register, so the canonical form (which names
  // registers) does not depend on them.
  void add_variances() {
    std::vector<Instruction>& instructions = program_->instructions;
    const std::vector<Register>& regs = program_->registers;
    std::vector<bool> wanted(regs.size(), false);
    for (const Instruction& instr : instructions) {
      if (instr.op == Op::ramp) wanted[static_cast<std::size_t>(instr.in[0])] = true;
    }
    // Instructions come after their inputs: from the last, a wanted marble wants its
    // turbulence, and a wanted scaling its input.
    for (auto it = instructions.rbegin(); it != instructions.rend(); ++it) {
      if (!wanted[static_cast<std::size_t>(it->out)]) continue;
      if (it->op == Op::marble) wanted[static_cast<std::size_t>(it->in[1])] = true;
      if (const std::optional<Affine> affine = affine_of(*it, regs)) {
        wanted[static_cast<std::size_t>(affine->input)] = true;
      }
    }
    for (Instruction& instr : instructions) {
      if (!wanted[static_cast<std::size_t>(instr.out)]) continue;
      const bool noise =
          instr.op == Op::noise3d || instr.op == Op::fractal3d || instr.op == Op::turbulence;
      const std::optional<Affine> affine = affine_of(instr, program_->registers);
      if (affine) {
        const int input_variance = program_->registers[affine->input].variance;
        if (input_variance < 0) continue;
        instr.variance_in = input_variance;
        instr.variance_gain = affine->gain * affine->gain;
      } else if (!(noise && program_->registers[instr.out].components == 1) &&
                 instr.op != Op::marble) {
        continue;
      }
      instr.variance_out = new_register(1, false, glm::dvec3(0.0), 0.0, deps_[instr.out]);
      program_->registers[instr.out].variance = instr.variance_out;
    }
  }

  int lower(std::size_t node_index);
  int lower_operand(const Node& node, const InputDef& def, ValueType working, Instruction& instr);
  void set_parameters(const Node& node, const NodeDef& def, Instruction& instr);
  Register result_register(const Node& node, const NodeDef& def, const Instruction& instr,
                           ValueType type, Deps& deps) const;

  const TextureGraph& graph_;
  const NodeIndex& index_;
  const std::vector<ValueType>& types_;
  std::vector<int> node_register_;
  std::vector<Deps> deps_;
  std::unique_ptr<Program> program_;
  CanonicalWriter writer_;
};

// A constant operand's width: its slot's, or for a slot of any type the constant's own shape.
// Only a slot of the working type takes the working type's (a number broadcast to it).
int constant_components(Slot slot, ValueType working, const InputValue& constant) {
  switch (slot) {
    case Slot::float_:
      return 1;
    case Slot::position:
    case Slot::any_vector:
      return 3;
    case Slot::any:
      return std::holds_alternative<glm::dvec3>(constant) ? 3 : 1;
    default:
      return components(working);
  }
}

int Lowering::lower_operand(const Node& node, const InputDef& def, ValueType working,
                            Instruction& instr) {
  const InputValue* value = find_input(node, def.name);
  int reg;
  if (value != nullptr && std::holds_alternative<NodeRef>(*value)) {
    reg = lower(index_.at(std::get<NodeRef>(*value).node));
    writer_.u8(0x52);  // 'R'
    writer_.u32(static_cast<uint32_t>(reg));
  } else if (value == nullptr && def.slot == Slot::position) {
    reg = program_->position;
    writer_.u8(0x50);  // 'P'
  } else {
    const InputValue constant = value ? *value : InputValue(def.fallback);
    reg = constant_register(constant, constant_components(def.slot, working, constant));
  }
  instr.in[static_cast<std::size_t>(instr.operand_count++)] = reg;
  return reg;
}

int Lowering::lower(std::size_t node_index) {
  if (node_register_[node_index] >= 0) return node_register_[node_index];
  const Node& node = graph_.nodes[node_index];
  const NodeDef& def = *find_node_def(node.category);
  if (def.op == Op::position) {
    writer_.u8(0x50);  // 'P'
    node_register_[node_index] = program_->position;
    return program_->position;
  }
  const ValueType type = types_[node_index];
  const ValueType working = working_type_of(def, type);
  Instruction instr;
  instr.op = def.op;
  for (const InputDef& input : def.inputs) {
    if (connectable(input.slot)) lower_operand(node, input, working, instr);
  }
  set_parameters(node, def, instr);
  Deps deps{0, 0, 0};
  Register out = result_register(node, def, instr, type, deps);
  instr.out = new_register(out.components, false, glm::dvec3(0.0), out.width_scale, deps);
  writer_.u8(0x4e);  // 'N'
  writer_.u8(static_cast<uint8_t>(def.op));
  writer_.u8(static_cast<uint8_t>(type));
  program_->cost_per_sample += node_cost(def.op, instr, type);
  program_->instructions.push_back(std::move(instr));
  node_register_[node_index] = program_->instructions.back().out;
  return node_register_[node_index];
}

// Constant parameters, written into the canonical form with their defaults filled in.
void Lowering::set_parameters(const Node& node, const NodeDef& def, Instruction& instr) {
  for (const InputDef& input : def.inputs) {
    if (connectable(input.slot)) continue;
    const InputValue* value = find_input(node, input.name);
    if (input.slot == Slot::keys) {
      // The count first, so that where the keys end is part of what the id hashes.
      const RampKeys& keys = std::get<RampKeys>(*value);
      writer_.u32(static_cast<uint32_t>(keys.size()));
      for (const RampKey& key : keys) {
        for (float f : {key.position, key.colour.r, key.colour.g, key.colour.b}) writer_.f64(f);
      }
    } else if (input.slot == Slot::choice) {
      const int choice = choice_index(input, value);
      writer_.u8(static_cast<uint8_t>(choice));
    } else if (input.slot == Slot::vector_param) {
      const glm::dvec3 v = value ? vector_of(*value) : glm::dvec3(input.fallback);
      writer_.f64(v.x);
      writer_.f64(v.y);
      writer_.f64(v.z);
    } else {
      writer_.f64(value ? std::get<double>(*value) : input.fallback);
    }
  }
  configure_instruction(node, def, instr);
}

double max_abs(const Register& r) {
  return std::max({std::fabs(r.value.x), std::fabs(r.value.y), std::fabs(r.value.z)});
}

double min_abs(const Register& r) {
  double m = std::fabs(r.value.x);
  for (int c = 1; c < r.components; ++c) m = std::min(m, std::fabs(r.value[c]));
  return m;
}

// The output register's shape, width scale and dependencies (docs/TEXTURES.md, "Node graphs":
// exact through scaling and translation by constants, estimates elsewhere).
Register Lowering::result_register(const Node&, const NodeDef& def, const Instruction& instr,
                                   ValueType type, Deps& deps) const {
  const auto& regs = program_->registers;
  Register out;
  out.components = components(type);
  double sum = 0.0;
  for (int k = 0; k < instr.operand_count; ++k) sum += regs[instr.in[k]].width_scale;
  out.width_scale = sum;
  SOLTEX_DCHECK(instr.operand_count > 0);
  const Register& a = regs[static_cast<std::size_t>(instr.in[0])];
  const auto elementwise = [&] {
    for (int c = 0; c < out.components; ++c) {
      for (int k = 0; k < instr.operand_count; ++k) {
        const Register& r = regs[instr.in[k]];
        deps[c] |= deps_[instr.in[k]][r.components == 1 ? 0 : c];
      }
    }
  };
  const auto everything = [&] {
    uint8_t all = 0;
    for (int k = 0; k < instr.operand_count; ++k) {
      for (uint8_t d : deps_[instr.in[k]]) all |= d;
    }
    deps = {all, all, all};
  };
  switch (def.op) {
    case Op::position:
    case Op::constant:
      elementwise();
      break;
    case Op::multiply:
    case Op::divide: {
      elementwise();
      const Register& b = regs[instr.in[1]];
      if (b.constant) {
        out.width_scale = def.op == Op::multiply ? a.width_scale * max_abs(b)
                          : min_abs(b) > 0.0     ? a.width_scale / min_abs(b)
                                                 : a.width_scale;
      } else if (a.constant && def.op == Op::multiply) {
        out.width_scale = b.width_scale * max_abs(a);
      }
      break;
    }
    case Op::remap: {
      elementwise();
      const Register &lo = regs[instr.in[1]], &hi = regs[instr.in[2]];
      const Register &olo = regs[instr.in[3]], &ohi = regs[instr.in[4]];
      if (lo.constant && hi.constant && olo.constant && ohi.constant) {
        double gain = 0.0;
        for (int c = 0; c < 3; ++c) {
          const double span = std::fabs(hi.value[c] - lo.value[c]);
          gain = std::max(gain, span > 0.0 ? std::fabs(ohi.value[c] - olo.value[c]) / span : 0.0);
        }
        out.width_scale = a.width_scale * gain;
      }
      break;
    }
    case Op::extract:
      deps = {deps_[instr.in[0]][static_cast<std::size_t>(instr.index)], 0, 0};
      break;
    case Op::combine3:
      deps = {deps_[instr.in[0]][0], deps_[instr.in[1]][0], deps_[instr.in[2]][0]};
      out.width_scale = std::max({regs[instr.in[0]].width_scale, regs[instr.in[1]].width_scale,
                                  regs[instr.in[2]].width_scale});
      break;
    case Op::convert:
      elementwise();
      break;
    case Op::dotproduct:
    case Op::magnitude:
      everything();
      break;
    case Op::noise3d:
    case Op::fractal3d:
    case Op::turbulence: {
      everything();
      // The lowest octave's mean slope: a warp by this value widens features by about this
      // much (an estimate, not a bound; docs/TEXTURES.md).
      const Register& amplitude = regs[instr.in[0]];
      const Register& position = regs[instr.in[def.op == Op::noise3d ? 2 : 1]];
      out.width_scale =
          position.width_scale * (amplitude.constant ? max_abs(amplitude) : 1.0) * kNoiseMeanSlope;
      break;
    }
    default:
      if (def.op >= Op::cellnoise3d) {
        everything();
      } else {
        elementwise();
      }
      break;
  }
  return out;
}

// Nodes on the longest chain from an output back to the position or a constant: instructions
// come after their inputs, so one pass finds it.
int longest_chain(const Program& program) {
  std::vector<int> chain(program.registers.size(), 0);
  int longest = 0;
  for (const Instruction& instr : program.instructions) {
    int deepest = 0;
    for (int k = 0; k < instr.operand_count; ++k) {
      deepest = std::max(deepest, chain[static_cast<std::size_t>(instr.in[k])]);
    }
    chain[static_cast<std::size_t>(instr.out)] = deepest + 1;
    longest = std::max(longest, deepest + 1);
  }
  return longest;
}

// Nodes on the longest chain from an output back along its inputs, every node counted (the
// position and constants too), as the user wrote the graph: lowering may fold or share nodes,
// which the bound on what a user writes must not depend on. The graph is acyclic by now.
int longest_node_chain(const TextureGraph& graph, const NodeIndex& index) {
  std::vector<int> depth(graph.nodes.size(), 0);    // 0: not yet known
  std::vector<std::pair<std::size_t, bool>> stack;  // node, inputs pushed
  int longest = 0;
  for (const GraphOutput& output : graph.outputs) {
    stack.emplace_back(index.at(output.node), false);
    while (!stack.empty()) {
      const auto [at, expanded] = stack.back();
      stack.pop_back();
      if (depth[at] != 0) continue;
      const Node& node = graph.nodes[at];
      int deepest = 0;
      bool ready = true;
      for (const NodeInput& input : node.inputs) {
        const auto* ref = std::get_if<NodeRef>(&input.value);
        if (ref == nullptr) continue;
        const std::size_t from = index.at(ref->node);
        if (depth[from] == 0) {
          SOLTEX_DCHECK(!expanded);  // acyclic: its inputs are known once pushed
          if (ready) stack.emplace_back(at, true);
          ready = false;
          stack.emplace_back(from, false);
        }
        deepest = std::max(deepest, depth[from]);
      }
      if (ready) depth[at] = deepest + 1;
    }
    longest = std::max(longest, depth[index.at(output.node)]);
  }
  return longest;
}

}  // namespace

std::shared_ptr<const CompiledGraph> compile(TextureGraph graph) {
  const NodeIndex index = check_structure(graph);
  const std::vector<ValueType> types = infer_types(graph, index);
  check_parameters(graph);
  check_outputs(graph, index, types);
  if (const int chain = longest_node_chain(graph, index); chain > GraphLimits::kMaxDepth) {
    throw SpecError(
        "graph.nodes", "a chain of " + std::to_string(chain) + " nodes",
        "at most " + std::to_string(GraphLimits::kMaxDepth) + " nodes on a chain from an output");
  }
  Lowering lowering(graph, index, types);
  std::unique_ptr<Program> program = lowering.run();
  program->depth = longest_chain(*program);
  if (program->cost_per_sample > GraphLimits::kMaxCostPerSample) {
    char value[64];
    std::snprintf(value, sizeof value, "estimated cost %.4g octaves per sample",
                  program->cost_per_sample);
    char bound[96];
    std::snprintf(bound, sizeof bound, "at most %.4g (noise octaves per sample)",
                  GraphLimits::kMaxCostPerSample);
    throw SpecError("graph.nodes", value, bound);
  }
  std::vector<uint8_t> canonical = lowering.canonical();
  return std::make_shared<CompiledGraph>(std::move(graph), std::move(program),
                                         std::move(canonical));
}

const TextureGraph& source_of(const GraphField& field) {
  return static_cast<const CompiledGraph&>(field).source();
}

}  // namespace soltex::graph
