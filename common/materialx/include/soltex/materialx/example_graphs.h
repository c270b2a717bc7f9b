#pragma once

#include <memory>
#include <string>
#include <vector>

#include "soltex/graph/compiled_graph.h"

// The example graph textures of deploy/scenes/graphs, built into the program from their
// MaterialX documents (so a viewer or the gallery needs no files to show them).
namespace soltex::materialx {

struct ExampleGraph {
  std::string name;  // the document's name without .mtlx: "granite", "veined-marble", ...
  std::shared_ptr<const graph::CompiledGraph> graph;
};

// Compiled once, in the order granite, veined-marble, cells, stripes-and-cells.
const std::vector<ExampleGraph>& example_graphs();

}  // namespace soltex::materialx
