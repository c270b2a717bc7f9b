// Graph textures at the edges of what they accept: constants near the ±1e15 bound, chains of
// warps, and positions a billion units from the origin. Every sample stays finite and in
// [0, 1], point and grid evaluation agree, and the noise lattice keeps its precision far out.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <string>
#include <vector>

#include "../unit/graph/graph_builders.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/graph/compiled_graph.h"

namespace soltex {
namespace {

using graph::testing::node;
using graph::testing::ref;

TextureEvaluator evaluator_of(const graph::TextureGraph& g) {
  TextureSpec spec;
  spec.graph = graph::compile(g);
  return TextureEvaluator(spec);
}

// Every sample of a grid at `origin`, at several widths: finite, in [0, 1] and equal to sample().
void expect_sane(const TextureEvaluator& t, glm::dvec3 origin) {
  Grid grid;
  grid.origin = origin;
  grid.step = glm::dvec3(1.0 / 128.0);
  grid.count = {9, 3, 3};
  std::vector<float> planes(grid.size() * 3);
  for (double width : {0.0, 1.0 / 128.0, 1e3}) {
    t.evaluate_grid(grid, width, planes);
    for (float v : planes) ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << v;
    const Texel texel = t.sample(grid.point(8, 2, 2), width);
    EXPECT_EQ(std::bit_cast<uint32_t>(texel.colour.r),
              std::bit_cast<uint32_t>(planes[grid.size() - 1]));
  }
}

graph::TextureGraph through_grey(std::vector<graph::Node> nodes, const std::string& last) {
  nodes.push_back(node("colour", "convert", {{"in", ref(last)}}, "color3"));
  return {std::move(nodes), {{Channel::colour, "colour"}}};
}

TEST(GraphExtremes, HugeAndTinyConstants) {
  for (double k : {1e15, -1e15, 1e-15, 3e-300}) {
    const auto g = through_grey(
        {node("p", "position"), node("s", "multiply", {{"in1", ref("p")}, {"in2", k}}),
         node("n", "fractal3d", {{"position", ref("s")}, {"octaves", 8.0}}),
         node("x", "extract", {{"in", ref("s")}}), node("w", "sin", {{"in", ref("x")}}),
         node("d", "divide", {{"in1", ref("w")}, {"in2", ref("n")}}),
         node("e", "power", {{"in1", ref("d")}, {"in2", k}}),
         node("m", "modulo", {{"in1", ref("e")}, {"in2", k}}),
         node("sum", "add", {{"in1", ref("m")}, {"in2", ref("n")}})},
        "sum");
    SCOPED_TRACE(k);
    const TextureEvaluator t = evaluator_of(g);
    expect_sane(t, glm::dvec3(0.1, -0.2, 0.3));
    expect_sane(t, glm::dvec3(1e9, -1e9, 1e9));
  }
}

// Ten warps deep: each adds a vector fractal of the previous position to it (68 octaves
// per sample, within the cost bound).
TEST(GraphExtremes, DeepWarps) {
  std::vector<graph::Node> nodes{node("w0", "multiply", {{"in1", ref("p")}, {"in2", 2.0}}),
                                 node("p", "position")};
  for (int i = 1; i <= 10; ++i) {
    const std::string prev = "w" + std::to_string(i - 1);
    nodes.push_back(node("n" + std::to_string(i), "fractal3d",
                         {{"position", ref(prev)}, {"octaves", 2.0}, {"amplitude", 0.8}},
                         "vector3"));
    nodes.push_back(node("w" + std::to_string(i), "add",
                         {{"in1", ref(prev)}, {"in2", ref("n" + std::to_string(i))}}));
  }
  nodes.push_back(node("cells", "worleynoise3d", {{"position", ref("w10")}}));
  const TextureEvaluator t = evaluator_of(through_grey(nodes, "cells"));
  expect_sane(t, glm::dvec3(0.5, 0.25, -0.75));
  expect_sane(t, glm::dvec3(-3e9, 2e9, 1e9));
}

// The lattices repeat every 256 cells: 256 · 2^22 (about 1.07e9) away, the pattern is the one
// at the origin to within the precision the offset leaves (2^-22 in position).
TEST(GraphExtremes, BillionUnitOffsetsKeepThePattern) {
  const double far = 256.0 * 4194304.0;
  const auto g = [&](double offset) {
    return through_grey(
        {node("p", "position"), node("q", "add", {{"in1", ref("p")}, {"in2", glm::dvec3(offset)}}),
         node("c", "worleynoise3d", {{"position", ref("q")}}),
         node("n", "fractal3d", {{"position", ref("q")}, {"octaves", 4.0}}),
         node("m", "mix", {{"fg", ref("c")}, {"bg", ref("n")}, {"mix", 0.5}})},
        "m");
  };
  const TextureEvaluator near = evaluator_of(g(0.0)), distant = evaluator_of(g(far));
  for (glm::dvec3 p : {glm::dvec3(0.3, 0.7, 0.1), glm::dvec3(12.34, -5.67, 8.9)}) {
    EXPECT_NEAR(near.sample(p).colour.r, distant.sample(p).colour.r, 1e-5f);
  }
  expect_sane(distant, glm::dvec3(far, far, -far));
}

}  // namespace
}  // namespace soltex
