#pragma once

#include <glm/vec3.hpp>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "soltex/common/texture_spec.h"

// A texture as a graph of nodes, as a user writes it (scene JSON, proto, MaterialX): nodes
// with a name, a category (the node's kind, MaterialX's word) and inputs that are constants or
// other nodes' outputs, and one output node per channel. compile() (compiled_graph.h)
// validates it and turns it into something that evaluates; docs/SCENES.md lists the nodes.
namespace soltex::graph {

// An input connected to another node's output.
struct NodeRef {
  std::string node;
  bool operator==(const NodeRef&) const = default;
};

// A ramp node's keys.
using RampKeys = std::vector<RampKey>;

// Numbers are doubles (integers and booleans too: 3, 0 / 1); vectors and colours are
// three-component; text names a choice ("gradient", "x", "f2_minus_f1").
using InputValue = std::variant<double, glm::dvec3, NodeRef, std::string, RampKeys>;

struct NodeInput {
  std::string name;
  InputValue value;
};

struct Node {
  std::string name;
  std::string category;  // "add", "fractal3d", ...
  std::string type;      // output type: "float", "vector3", "color3"; empty: inferred
  std::vector<NodeInput> inputs;
};

struct GraphOutput {
  Channel channel = Channel::colour;
  std::string node;
};

struct TextureGraph {
  std::vector<Node> nodes;
  std::vector<GraphOutput> outputs;
};

const char* channel_name(Channel channel);

// Whether input `input` of a `category` node is a true/false constant. Readers of formats with
// booleans of their own (JSON, MaterialX) accept one only there: elsewhere a boolean read as
// 0 or 1 would be a number the user never wrote. False for unknown nodes and inputs.
bool takes_boolean(std::string_view category, std::string_view input);

}  // namespace soltex::graph
