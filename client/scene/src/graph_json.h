#pragma once

#include <nlohmann/json.hpp>

#include "json_reader.h"
#include "soltex/graph/texture_graph.h"

// Graph textures in scene JSON (docs/SCENES.md, "Node graphs"):
//   {"nodes": [{"name": "p4", "category": "multiply", "inputs": {"in1": {"node": "p"}, "in2": 4}},
//              ...],
//    "outputs": {"colour": "veins"}}
// An input is a number, a boolean, a [x, y, z] vector, a choice ("gradient"), {"node": name}
// for another node's output, or a ramp node's keys [{"position": 0, "colour": [r, g, b]}, ...].
namespace soltex {

// Reads the graph as written; compile() validates it.
graph::TextureGraph graph_from_json(const JsonValue& value);
nlohmann::json graph_to_json(const graph::TextureGraph& graph);

}  // namespace soltex
