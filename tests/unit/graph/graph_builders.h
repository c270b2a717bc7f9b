#pragma once

#include <string>
#include <utility>
#include <vector>

#include "soltex/graph/texture_graph.h"

// Short ways to write graphs in tests.
namespace soltex::graph::testing {

inline NodeRef ref(std::string name) {
  return NodeRef{std::move(name)};
}

inline Node node(std::string name, std::string category, std::vector<NodeInput> inputs = {},
                 std::string type = "") {
  return Node{std::move(name), std::move(category), std::move(type), std::move(inputs)};
}

// The built-in marble (MarbleParams{} with its default ramp) as a graph: value fBm of six
// octaves at scale 4 feeding the marble node, through the marble ramp.
inline TextureGraph builtin_marble_graph(const ColourRamp& ramp = default_ramp(MarbleParams{})) {
  return TextureGraph{
      {node("p", "position"), node("p4", "multiply", {{"in1", ref("p")}, {"in2", 4.0}}),
       node("turb", "fractal3d",
            {{"position", ref("p4")}, {"octaves", 6.0}, {"basis", std::string("value")}}),
       node("veins", "marble", {{"turbulence", ref("turb")}}),
       node("colour", "ramp", {{"in", ref("veins")}, {"keys", ramp.keys}})},
      {{Channel::colour, "colour"}}};
}

// Veined marble: fBm warped by a vector fBm, through a ramp.
inline TextureGraph warped_graph() {
  return TextureGraph{
      {node("p", "position"), node("p3", "multiply", {{"in1", ref("p")}, {"in2", 3.0}}),
       node("warp", "fractal3d", {{"position", ref("p3")}, {"octaves", 4.0}, {"amplitude", 0.4}},
            "vector3"),
       node("q", "add", {{"in1", ref("p3")}, {"in2", ref("warp")}}),
       node("f", "fractal3d", {{"position", ref("q")}, {"octaves", 5.0}}),
       node("t", "remap", {{"in", ref("f")}, {"inlow", -0.8}, {"inhigh", 0.8}}),
       node("c", "ramp",
            {{"in", ref("t")},
             {"keys", RampKeys{{0.0f, {0.1f, 0.1f, 0.12f}}, {1.0f, {0.95f, 0.93f, 0.9f}}}}})},
      {{Channel::colour, "c"}}};
}

}  // namespace soltex::graph::testing
