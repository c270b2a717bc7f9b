#pragma once

#include "soltex/graph/texture_graph.h"
#include "soltex/v1/texture.pb.h"

// Graph textures to and from their protocol messages, field for field.
namespace soltex {

// Reads the message as written; compile() then validates it. Throws SpecError for a value
// the C++ form cannot hold (an unset input, an unknown channel).
graph::TextureGraph graph_from_proto(const v1::Graph& m);
v1::Graph graph_to_proto(const graph::TextureGraph& graph);

}  // namespace soltex
