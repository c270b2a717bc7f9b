#pragma once

#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "node_catalogue.h"
#include "program.h"
#include "soltex/graph/texture_graph.h"

// The checks compile() makes before it lowers a graph, and the helpers that read a node's
// inputs. Every failure throws SpecError with the field "graph.nodes[<name>].<input>".
namespace soltex::graph {

using NodeIndex = std::unordered_map<std::string, std::size_t>;

// Names, counts, categories, inputs present / known / of the right kind, constants finite and
// in range, outputs naming nodes. Returns the index of node names.
NodeIndex check_structure(const TextureGraph& graph);

// Each node's output type, refusing cycles and mismatched connections.
std::vector<ValueType> infer_types(const TextureGraph& graph, const NodeIndex& index);

// Colour outputs are color3, opacity and specular float.
void check_outputs(const TextureGraph& graph, const NodeIndex& index,
                   const std::vector<ValueType>& types);

// "graph.nodes[<node>].<field>", the node's name escaped and cut as quoted_text() does: it is
// the client's, and may be long or hold control characters.
std::string node_field(const Node& node, std::string_view field);
// "graph.nodes[<node>].<input>", the input's name shown the same way.
std::string input_field(const Node& node, const std::string& input);

const InputValue* find_input(const Node& node, const std::string& name);
glm::dvec3 vector_of(const InputValue& value);
int choice_index(const InputDef& def, const InputValue* value);

// The type T of the node's `working` inputs, given its output type.
ValueType working_type_of(const NodeDef& def, ValueType output);

// Fills an instruction's noise, Worley, ramp, pattern and index settings from the node's
// constant parameters (built-in pattern parameters are checked as the patterns' own).
void configure_instruction(const Node& node, const NodeDef& def, Instruction& instr);

// Checks the parameters of every node, used or not, that configure_instruction() checks.
void check_parameters(const TextureGraph& graph);

// Estimated cost per sample in noise octaves (GraphLimits::kMaxCostPerSample).
double node_cost(Op op, const Instruction& instr, ValueType type);

}  // namespace soltex::graph
