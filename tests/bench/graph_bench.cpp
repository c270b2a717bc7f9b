// Graph textures against the built-in patterns they can express: one B = 16 brick ((B + 1)^3
// samples, RGB) per iteration, single thread, band-limited, at the finest and a coarse level.
// Built-in and graph rows alternate in one run so they see the same machine.
#include <benchmark/benchmark.h>

#include <numbers>
#include <vector>

#include "../unit/graph/graph_builders.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/graph/compiled_graph.h"

namespace {

using namespace soltex;
using graph::NodeRef;
using graph::testing::node;
using graph::testing::ref;

// Marble from arithmetic nodes instead of the marble node: 0.5 + 0.5 sin(2 pi fract(2x) + 4 f).
graph::TextureGraph arithmetic_marble_graph() {
  graph::TextureGraph g = graph::testing::builtin_marble_graph();
  g.nodes.erase(g.nodes.begin() + 3, g.nodes.end());  // p, p4, turb
  const auto add = [&](graph::Node n) { g.nodes.push_back(std::move(n)); };
  add(node("x", "extract", {{"in", ref("p")}}));
  add(node("x2", "multiply", {{"in1", ref("x")}, {"in2", 2.0}}));
  add(node("f", "fract", {{"in", ref("x2")}}));
  add(node("phase", "multiply", {{"in1", ref("f")}, {"in2", 2.0 * std::numbers::pi}}));
  add(node("bend", "multiply", {{"in1", ref("turb")}, {"in2", 4.0}}));
  add(node("angle", "add", {{"in1", ref("phase")}, {"in2", ref("bend")}}));
  add(node("wave", "sin", {{"in", ref("angle")}}));
  add(node("t", "remap", {{"in", ref("wave")}, {"inlow", -1.0}, {"inhigh", 1.0}}));
  add(node("colour", "ramp", {{"in", ref("t")}, {"keys", default_ramp(MarbleParams{}).keys}}));
  return g;
}

graph::TextureGraph worley_graph(const char* feature) {
  return {{node("p", "position"), node("p8", "multiply", {{"in1", ref("p")}, {"in2", 8.0}}),
           node("w", "worleynoise3d", {{"position", ref("p8")}, {"feature", std::string(feature)}}),
           node("c", "ramp",
                {{"in", ref("w")},
                 {"keys", graph::RampKeys{{0.0f, glm::vec3(0.0f)}, {1.0f, glm::vec3(1.0f)}}}})},
          {{Channel::colour, "c"}}};
}

TextureSpec spec_by_index(int index) {
  TextureSpec spec;
  switch (index) {
    case 0:
      spec.pattern = MarbleParams{};
      break;
    case 1:
      spec.graph = graph::compile(graph::testing::builtin_marble_graph());
      break;
    case 2:
      spec.graph = graph::compile(arithmetic_marble_graph());
      break;
    case 3:
      spec.graph = graph::compile(graph::testing::warped_graph());
      break;
    case 4:
      spec.graph = graph::compile(worley_graph("f1"));
      break;
    default:
      spec.graph = graph::compile(worley_graph("f2_minus_f1"));
      break;
  }
  return spec;
}

const char* kLabels[] = {"builtin marble",
                         "graph marble (marble node)",
                         "graph marble (arithmetic nodes)",
                         "graph warped fBm",
                         "graph worley F1",
                         "graph worley F2-F1"};

void BM_GraphBrick(benchmark::State& state) {
  const TextureSpec spec = spec_by_index(static_cast<int>(state.range(0)));
  const TextureEvaluator texture(spec);
  Volume volume;
  volume.min = glm::dvec3(-1.0);
  volume.max = glm::dvec3(1.0);
  volume.finest_level_log2 = 8;
  const BrickLayout layout(volume, 16);
  const int level = static_cast<int>(state.range(1));
  std::vector<float> out(static_cast<std::size_t>(layout.samples_per_brick()) * 3);
  const int bricks = layout.bricks_per_axis(level);
  int next = 0;
  for (auto _ : state) {
    const int b = next++ % (bricks * bricks * bricks);
    evaluate_brick(texture, layout, level,
                   {b % bricks, (b / bricks) % bricks, b / (bricks * bricks)}, MipSettings{}, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetLabel(std::string(kLabels[state.range(0)]) + " level " + std::to_string(level));
  state.SetItemsProcessed(state.iterations() * layout.samples_per_brick());  // samples/s
}

void GraphArguments(benchmark::internal::Benchmark* b) {
  for (int level : {0, 3}) {
    for (int spec = 0; spec < 6; ++spec) b->Args({spec, level});
  }
}

BENCHMARK(BM_GraphBrick)->Apply(GraphArguments)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
