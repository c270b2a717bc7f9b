#include "graph_json.h"

#include <limits>

#include "soltex/common/overloaded.h"
#include "soltex/graph/graph_limits.h"

namespace soltex {
namespace {

using nlohmann::json;

constexpr double kAny = std::numeric_limits<double>::max();

graph::RampKeys read_keys(const JsonValue& value) {
  graph::RampKeys keys;
  for (const JsonValue& element :
       value.elements(static_cast<std::size_t>(SpecLimits::kMaxRampKeys))) {
    JsonObject key(element);
    keys.push_back(
        {static_cast<float>(key.get("position").number(-kAny, kAny)), key.get("colour").colour()});
    key.reject_unknown_keys();
  }
  return keys;
}

// Numbers may be anything finite here: compile() applies the bounds and names them.
// `boolean`: the input takes true or false (graph::takes_boolean).
graph::InputValue read_input(const JsonValue& value, bool boolean) {
  const json& j = value.json();
  if (j.is_boolean()) {
    value.expect(boolean,
                 "a number, a vector, a choice, {\"node\": ...} or ramp keys (true and "
                 "false are for true/false inputs)");
    return value.boolean() ? 1.0 : 0.0;
  }
  // A true/false input takes true or false, as the built-in patterns' do: 1 or "yes" would be
  // words the format does not have for it.
  if (boolean) return value.boolean() ? 1.0 : 0.0;
  if (j.is_number()) return value.number(-kAny, kAny);
  if (j.is_string()) return value.string();
  if (j.is_object()) {
    JsonObject object(value);
    graph::NodeRef ref{object.get("node").string()};
    object.reject_unknown_keys();
    return ref;
  }
  if (j.is_array() && !j.empty() && j.front().is_object()) return read_keys(value);
  // Neither a vector nor keys: say what an empty list might have meant.
  if (j.is_array() && j.empty()) {
    value.fail(
        "an empty list: expected ramp keys ([{\"position\": .., \"colour\": ..}, ...]) "
        "or a [x, y, z] vector");
  }
  value.expect(j.is_array(),
               "a number, a boolean, a [x, y, z] vector, a choice, {\"node\": ...} "
               "or ramp keys");
  return value.vec3(-kAny, kAny);
}

graph::Node read_node(const JsonValue& value) {
  JsonObject object(value);
  graph::Node node;
  node.name = object.get("name").string();
  node.category = object.get("category").string();
  if (const auto type = object.find("type")) node.type = type->string();
  if (const auto inputs = object.find("inputs")) {
    inputs->expect(inputs->json().is_object(), "an object of inputs");
    for (const auto& [name, input] : inputs->json().items()) {
      node.inputs.push_back(
          {name, read_input(inputs->child(name), graph::takes_boolean(node.category, name))});
    }
  }
  object.reject_unknown_keys();
  return node;
}

json input_to_json(const graph::InputValue& value) {
  return std::visit(
      Overloaded{
          [](double v) -> json { return v; },
          [](const glm::dvec3& v) -> json {
            return json::array({v.x, v.y, v.z});
          },
          [](const graph::NodeRef& r) -> json {
            return {{"node", r.node}};
          },
          [](const std::string& s) -> json { return s; },
          [](const graph::RampKeys& keys) -> json {
            json out = json::array();
            for (const RampKey& key : keys) {
              out.push_back({{"position", key.position},
                             {"colour", json::array({key.colour.r, key.colour.g, key.colour.b})}});
            }
            return out;
          },
      },
      value);
}

}  // namespace

graph::TextureGraph graph_from_json(const JsonValue& value) {
  JsonObject object(value);
  graph::TextureGraph g;
  for (const JsonValue& node :
       object.get("nodes").elements(static_cast<std::size_t>(graph::GraphLimits::kMaxNodes))) {
    g.nodes.push_back(read_node(node));
  }
  JsonObject outputs(object.get("outputs"));
  for (const auto& [name, channel] : {std::pair{"colour", Channel::colour},
                                      {"opacity", Channel::opacity},
                                      {"specular", Channel::specular}}) {
    if (const auto node = outputs.find(name)) g.outputs.push_back({channel, node->string()});
  }
  outputs.reject_unknown_keys();
  object.reject_unknown_keys();
  return g;
}

json graph_to_json(const graph::TextureGraph& graph) {
  json nodes = json::array();
  for (const graph::Node& node : graph.nodes) {
    json inputs = json::object();
    for (const graph::NodeInput& input : node.inputs)
      inputs[input.name] = input_to_json(input.value);
    json n = {{"name", node.name}, {"category", node.category}, {"inputs", inputs}};
    if (!node.type.empty()) n["type"] = node.type;
    nodes.push_back(std::move(n));
  }
  json outputs = json::object();
  for (const graph::GraphOutput& out : graph.outputs) {
    outputs[graph::channel_name(out.channel)] = out.node;
  }
  return {{"nodes", nodes}, {"outputs", outputs}};
}

}  // namespace soltex
