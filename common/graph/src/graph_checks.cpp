#include "graph_checks.h"

#include <cmath>
#include <functional>
#include <optional>
#include <string_view>

#include "soltex/common/quoted_text.h"
#include "soltex/common/spec_error.h"
#include "soltex/common/utf8.h"
#include "soltex/graph/graph_limits.h"

namespace soltex::graph {
namespace {

std::string describe(const InputValue& value) {
  if (const auto* d = std::get_if<double>(&value)) return spec_number_text(*d);
  if (const auto* v = std::get_if<glm::dvec3>(&value)) {
    return "[" + spec_number_text(v->x) + ", " + spec_number_text(v->y) + ", " +
           spec_number_text(v->z) + "]";
  }
  if (const auto* r = std::get_if<NodeRef>(&value)) return "node " + quoted_text(r->node);
  if (const auto* s = std::get_if<std::string>(&value)) return quoted_text(*s);
  return std::to_string(std::get<RampKeys>(value).size()) + " ramp keys";
}

std::string input_names(const NodeDef& def) {
  if (def.inputs.empty()) return "it takes no inputs";
  std::string names = "it takes ";
  for (std::size_t i = 0; i < def.inputs.size(); ++i) {
    names += (i ? ", " : "") + std::string(def.inputs[i].name);
  }
  return names;
}

void check_constant(const Node& node, const InputDef& def, const InputValue& value) {
  const std::string field = input_field(node, def.name);
  const auto finite = [&](double v) {
    if (!std::isfinite(v) || std::fabs(v) > GraphLimits::kMaxConstant) {
      throw SpecError(field, describe(value),
                      "must be finite and in [-1e15, 1e15] (GraphLimits::kMaxConstant)");
    }
  };
  const bool number = std::holds_alternative<double>(value);
  const bool vector = std::holds_alternative<glm::dvec3>(value);
  switch (def.slot) {
    case Slot::number:
    case Slot::integer:
    case Slot::boolean: {
      if (!number) throw SpecError(field, describe(value), "must be a number");
      const double v = std::get<double>(value);
      finite(v);
      const double lo = def.slot == Slot::boolean ? 0.0 : def.lo;
      const double hi = def.slot == Slot::boolean ? 1.0 : def.hi;
      if (v < lo || v > hi) {
        throw SpecError(field, describe(value),
                        "must be in [" + spec_number_text(lo) + ", " + spec_number_text(hi) + "]");
      }
      if (def.slot != Slot::number && v != std::floor(v)) {
        throw SpecError(field, describe(value),
                        def.slot == Slot::boolean ? "must be true or false" : "must be an integer");
      }
      return;
    }
    case Slot::vector_param:
      if (!number && !vector) throw SpecError(field, describe(value), "must be a vector");
      for (int c = 0; c < 3; ++c) finite(vector_of(value)[c]);
      return;
    case Slot::choice: {
      const auto* text = std::get_if<std::string>(&value);
      const std::string choices = def.choices;
      if (text == nullptr || choice_index(def, &value) < 0) {
        throw SpecError(field, describe(value), "must be one of " + choices);
      }
      return;
    }
    case Slot::keys:
      if (!std::holds_alternative<RampKeys>(value)) {
        throw SpecError(field, describe(value), "must be a list of ramp keys");
      }
      return;
    default:
      if (!number && !vector) {
        throw SpecError(field, describe(value), "must be a number, a vector or a node");
      }
      if (def.slot == Slot::float_ && vector) {
        throw SpecError(field, describe(value), "must be a float");
      }
      for (int c = 0; c < 3; ++c) finite(vector_of(value)[c]);
      return;
  }
}

void check_node(const Node& node, const NodeIndex& index) {
  const NodeDef* def = find_node_def(node.category);
  if (def == nullptr) {
    throw SpecError(node_field(node, "category"), quoted_text(node.category),
                    "is not a known node category (docs/SCENES.md lists them)");
  }
  for (std::size_t i = 0; i < node.inputs.size(); ++i) {
    const NodeInput& input = node.inputs[i];
    const InputDef* input_def = nullptr;
    for (const InputDef& d : def->inputs) {
      if (input.name == d.name) input_def = &d;
    }
    if (input_def == nullptr) {
      throw SpecError(input_field(node, input.name), describe(input.value),
                      "is not an input of " + node.category + ": " + input_names(*def));
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (node.inputs[j].name == input.name) {
        throw SpecError(input_field(node, input.name), describe(input.value), "is given twice");
      }
    }
    if (const auto* ref = std::get_if<NodeRef>(&input.value)) {
      if (!connectable(input_def->slot)) {
        throw SpecError(input_field(node, input.name), describe(input.value),
                        "must be a constant: it is a parameter of " + node.category);
      }
      if (!index.contains(ref->node)) {
        throw SpecError(input_field(node, input.name), describe(input.value),
                        "names no node of the graph");
      }
    } else {
      check_constant(node, *input_def, input.value);
    }
  }
  for (const InputDef& d : def->inputs) {
    if (std::isnan(d.fallback) && find_input(node, d.name) == nullptr) {
      throw SpecError(input_field(node, d.name), "absent",
                      "is required by " + node.category + ": " + input_names(*def));
    }
  }
}

std::optional<ValueType> parse_type(const std::string& name) {
  for (ValueType t : {ValueType::float_, ValueType::vector3, ValueType::color3}) {
    if (name == type_name(t)) return t;
  }
  return std::nullopt;
}

class TypeInference {
 public:
  TypeInference(const TextureGraph& graph, const NodeIndex& index)
      : graph_(graph), index_(index), state_(graph.nodes.size(), 0), types_(graph.nodes.size()) {}

  std::vector<ValueType> run() {
    for (std::size_t i = 0; i < graph_.nodes.size(); ++i) type_of(i);
    return types_;
  }

 private:
  // The type of an input's value: a node's output, or a constant's shape.
  ValueType value_type(const InputValue& value, std::size_t from, const std::string& input) {
    if (const auto* ref = std::get_if<NodeRef>(&value)) {
      const std::size_t target = index_.at(ref->node);
      if (state_[target] == 1) {
        throw SpecError(input_field(graph_.nodes[from], input), describe(value),
                        "closes a cycle: a node may not depend on itself");
      }
      return type_of(target);
    }
    return std::holds_alternative<glm::dvec3>(value) ? ValueType::vector3 : ValueType::float_;
  }

  ValueType declared_or(const Node& node, const NodeDef& def, ValueType fallback) {
    if (node.type.empty()) return fallback;
    const auto t = parse_type(node.type);
    if (!t || std::find(def.allowed.begin(), def.allowed.end(), *t) == def.allowed.end()) {
      std::string allowed;
      for (ValueType a : def.allowed)
        allowed += (allowed.empty() ? "" : ", ") + std::string(type_name(a));
      throw SpecError(node_field(node, "type"), quoted_text(node.type),
                      "must be one of " + allowed + " for " + node.category);
    }
    return *t;
  }

  ValueType type_of(std::size_t i) {
    if (state_[i] == 2) return types_[i];
    state_[i] = 1;
    const Node& node = graph_.nodes[i];
    const NodeDef& def = *find_node_def(node.category);
    std::vector<std::pair<const InputDef*, ValueType>> got;
    for (const NodeInput& input : node.inputs) {
      for (const InputDef& d : def.inputs) {
        if (input.name == d.name && connectable(d.slot)) {
          got.emplace_back(&d, value_type(input.value, i, input.name));
        }
      }
    }
    ValueType type = def.fallback_type;
    if (def.rule == TypeRule::declared || def.rule == TypeRule::fixed) {
      type = declared_or(node, def, def.fallback_type);
    } else if (!node.type.empty()) {
      type = declared_or(node, def, def.fallback_type);
    } else {
      type = inferred_working_type(node, got, type);
    }
    for (const NodeInput& input : node.inputs) {
      for (const auto& [d, t] : got) {
        if (input.name == d->name) check_input_type(node, def, *d, input.value, t, type);
      }
    }
    check_vectors_alike(node, got);
    state_[i] = 2;
    types_[i] = type;
    return type;
  }

  // The first non-float type a working input brings, a node's output before a constant's
  // shape: [x, y, z] is vector3 or color3 alike, so it decides only where no node does,
  // whatever the order of the inputs.
  static ValueType inferred_working_type(
      const Node& node, const std::vector<std::pair<const InputDef*, ValueType>>& got,
      ValueType fallback) {
    std::optional<ValueType> from_constant;
    for (const auto& [d, t] : got) {
      if ((d->slot != Slot::working && d->slot != Slot::working_or_float) ||
          t == ValueType::float_) {
        continue;
      }
      const InputValue* value = find_input(node, d->name);
      if (value != nullptr && std::holds_alternative<NodeRef>(*value)) return t;
      if (!from_constant) from_constant = t;
    }
    return from_constant.value_or(fallback);
  }

  // A node taking two vectors of either kind (dotproduct) takes two of one kind: vector3 and
  // color3 do not mix. A constant [x, y, z] is either, as elsewhere.
  static void check_vectors_alike(const Node& node,
                                  const std::vector<std::pair<const InputDef*, ValueType>>& got) {
    const std::pair<const InputDef*, ValueType>* first = nullptr;
    for (const auto& entry : got) {
      const InputValue* value = find_input(node, entry.first->name);
      if (entry.first->slot != Slot::any_vector || value == nullptr ||
          !std::holds_alternative<NodeRef>(*value)) {
        continue;
      }
      if (first == nullptr) {
        first = &entry;
      } else if (entry.second != first->second) {
        throw SpecError(input_field(node, entry.first->name),
                        describe(*value) + " (" + type_name(entry.second) + ")",
                        std::string("must be ") + type_name(first->second) + " like " +
                            first->first->name + ": vector3 and color3 do not mix");
      }
    }
  }

  void check_input_type(const Node& node, const NodeDef& def, const InputDef& d,
                        const InputValue& value, ValueType got, ValueType output) {
    const bool is_ref = std::holds_alternative<NodeRef>(value);
    const ValueType working = working_type_of(def, output);
    std::string need;
    switch (d.slot) {
      case Slot::working:
        if (got == working || (!is_ref && got == ValueType::float_) ||
            (!is_ref && working != ValueType::float_)) {
          return;
        }
        need = std::string("must be ") + type_name(working) + " like the node's output";
        break;
      case Slot::working_or_float:
        if (got == working || got == ValueType::float_ ||
            (!is_ref && working != ValueType::float_)) {
          return;
        }
        need = working == ValueType::float_ ? std::string("must be float like the node's output")
                                            : std::string("must be float or ") + type_name(working);
        break;
      case Slot::float_:
        if (got == ValueType::float_) return;
        need = "must be float";
        break;
      case Slot::position:
        if (got == ValueType::vector3) return;
        need = "must be a vector3 position";
        break;
      case Slot::any_vector:
        if (got != ValueType::float_) return;
        need = "must be vector3 or color3";
        break;
      case Slot::any:
        if (got == ValueType::float_ || output != ValueType::float_) return;
        need = "converts to float only from float: use extract for a component";
        break;
      default:
        return;
    }
    // A constant [x, y, z] has no kind of its own (vector3 or color3 alike): its shape is
    // what the slot refuses.
    const std::string kind = !is_ref && std::holds_alternative<glm::dvec3>(value)
                                 ? std::string("three components")
                                 : std::string(type_name(got));
    throw SpecError(input_field(node, d.name), describe(value) + " (" + kind + ")", need);
  }

  const TextureGraph& graph_;
  const NodeIndex& index_;
  std::vector<int> state_;  // 0 unvisited, 1 on the current path, 2 done
  std::vector<ValueType> types_;
};

}  // namespace

std::string node_field(const Node& node, std::string_view field) {
  return "graph.nodes[" + escaped_text(node.name) + "]." + std::string(field);
}

std::string input_field(const Node& node, const std::string& input) {
  return node_field(node, escaped_text(input));
}

const InputValue* find_input(const Node& node, const std::string& name) {
  for (const NodeInput& input : node.inputs) {
    if (input.name == name) return &input.value;
  }
  return nullptr;
}

glm::dvec3 vector_of(const InputValue& value) {
  if (const auto* d = std::get_if<double>(&value)) return glm::dvec3(*d);
  return std::get<glm::dvec3>(value);
}

int choice_index(const InputDef& def, const InputValue* value) {
  if (value == nullptr) return 0;
  const auto* text = std::get_if<std::string>(value);
  if (text == nullptr) return -1;
  const std::string choices = def.choices;
  std::size_t start = 0;
  for (int i = 0;; ++i) {
    const std::size_t end = choices.find('|', start);
    if (choices.substr(start, end - start) == *text) return i;
    if (end == std::string::npos) return -1;
    start = end + 1;
  }
}

ValueType working_type_of(const NodeDef& def, ValueType output) {
  if (def.op == Op::noise3d || def.op == Op::fractal3d || def.op == Op::turbulence) {
    return output;
  }
  return def.rule == TypeRule::working ? output : ValueType::float_;
}

NodeIndex check_structure(const TextureGraph& graph) {
  const std::size_t n = graph.nodes.size();
  if (n == 0 || n > static_cast<std::size_t>(GraphLimits::kMaxNodes)) {
    throw SpecError("graph.nodes", std::to_string(n) + " nodes",
                    "must be 1 to " + std::to_string(GraphLimits::kMaxNodes));
  }
  NodeIndex index;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string& name = graph.nodes[i].name;
    // UTF-8 as protobuf requires of a string field: a name that is not would fail only when sent.
    if (name.empty() || name.size() > static_cast<std::size_t>(GraphLimits::kMaxNameLength) ||
        !is_utf8(name)) {
      throw SpecError(
          "graph.nodes[" + std::to_string(i) + "].name", quoted_text(name),
          "must be 1 to " + std::to_string(GraphLimits::kMaxNameLength) + " bytes of UTF-8");
    }
    if (!index.emplace(name, i).second) {
      throw SpecError(node_field(graph.nodes[i], "name"), quoted_text(name),
                      "names two nodes: node names must be unique");
    }
  }
  for (const Node& node : graph.nodes) check_node(node, index);
  if (graph.outputs.empty()) {
    throw SpecError("graph.outputs", "none",
                    "the graph needs an output (colour, opacity or specular)");
  }
  for (std::size_t i = 0; i < graph.outputs.size(); ++i) {
    const GraphOutput& out = graph.outputs[i];
    const std::string field = std::string("graph.outputs.") + channel_name(out.channel);
    for (std::size_t j = 0; j < i; ++j) {
      if (graph.outputs[j].channel == out.channel) {
        throw SpecError(field, quoted_text(out.node), "is given twice");
      }
    }
    if (!index.contains(out.node)) {
      throw SpecError(field, quoted_text(out.node), "names no node of the graph");
    }
  }
  return index;
}

std::vector<ValueType> infer_types(const TextureGraph& graph, const NodeIndex& index) {
  return TypeInference(graph, index).run();
}

void check_outputs(const TextureGraph& graph, const NodeIndex& index,
                   const std::vector<ValueType>& types) {
  for (const GraphOutput& out : graph.outputs) {
    const ValueType got = types[index.at(out.node)];
    const ValueType need = out.channel == Channel::colour ? ValueType::color3 : ValueType::float_;
    if (got != need) {
      throw SpecError(std::string("graph.outputs.") + channel_name(out.channel),
                      "node " + quoted_text(out.node) + " (" + type_name(got) + ")",
                      std::string("must be ") + type_name(need));
    }
  }
}

const char* channel_name(Channel channel) {
  switch (channel) {
    case Channel::colour:
      return "colour";
    case Channel::opacity:
      return "opacity";
    case Channel::specular:
      return "specular";
  }
  return "unknown";
}

}  // namespace soltex::graph
