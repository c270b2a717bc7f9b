#pragma once

#include <memory>
#include <vector>

#include "soltex/common/graph_field.h"
#include "soltex/graph/texture_graph.h"

// A validated graph, ready to evaluate: compile() checks every node against the node
// catalogue and the bounds of GraphLimits, infers the types, orders the nodes canonically and
// lowers them to array kernels. The result is what TextureSpec::graph holds.
namespace soltex::graph {

struct Program;

class CompiledGraph final : public GraphField {
 public:
  CompiledGraph(TextureGraph source, std::unique_ptr<Program> program,
                std::vector<uint8_t> canonical);
  ~CompiledGraph() override;

  // The graph as written (for writing it back out as JSON or proto).
  const TextureGraph& source() const { return source_; }
  const Program& program() const { return *program_; }
  double cost_per_sample() const;

  bool has_colour() const override;
  bool has_opacity() const override;
  bool has_specular() const override;
  void append_canonical(std::vector<uint8_t>& bytes) const override;
  int evaluated_octaves(double filter_width) const override;
  void evaluate_points(std::span<const glm::dvec3> points, std::span<const double> widths,
                       const GraphPlanes& out) const override;
  void evaluate_grid(const Grid& grid, double filter_width, const GraphPlanes& out) const override;

 private:
  TextureGraph source_;
  std::unique_ptr<Program> program_;
  std::vector<uint8_t> canonical_;
};

// Validates and compiles; throws SpecError naming the node, the input and what is wrong,
// e.g. `graph.nodes[warp].in2 = node "grain" (float): must be vector3 like in1`.
std::shared_ptr<const CompiledGraph> compile(TextureGraph graph);

// The source graph of a spec's graph (TextureSpec::graph, made by compile()).
const TextureGraph& source_of(const GraphField& field);

}  // namespace soltex::graph
