#pragma once

#include <memory>
#include <string>

#include "soltex/graph/compiled_graph.h"

// MaterialX documents (https://materialx.org) as graph textures. A nodegraph of standard nodes
// (the MaterialX Standard Nodes specification) that soltex also has becomes a TextureGraph
// whose colour output is the named output; any other node is refused with its name, its
// category and its line in the document.
namespace soltex::materialx {

struct MaterialxSource {
  std::string text;      // the document
  std::string document;  // its name in messages, e.g. "scenes/granite.mtlx"
  std::string nodegraph;
  std::string output;
};

// Reads the nodegraph into a graph (not yet validated). Throws MaterialxError.
graph::TextureGraph read_nodegraph(const MaterialxSource& source);

// Reads and compiles; a SpecError from compile() is re-thrown as MaterialxError with the
// document's line of the node it names.
std::shared_ptr<const graph::CompiledGraph> compile_nodegraph(const MaterialxSource& source);

// A document that cannot be read as a texture: "granite.mtlx:14: node "blur" (blur): ...".
class MaterialxError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Every MaterialX category the reader accepts.
bool is_supported_category(const std::string& category);

}  // namespace soltex::materialx
