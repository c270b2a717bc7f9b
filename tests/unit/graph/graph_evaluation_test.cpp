#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "graph_builders.h"
#include "soltex/common/brick_evaluator.h"
#include "soltex/common/brick_layout.h"
#include "soltex/common/texture_evaluator.h"
#include "soltex/common/texture_id.h"
#include "soltex/graph/compiled_graph.h"

namespace soltex::graph {
namespace {

using testing::node;
using testing::ref;

TextureSpec spec_of(const TextureGraph& graph, ChannelSet channels = {}) {
  TextureSpec spec;
  spec.graph = compile(graph);
  spec.channels = channels;
  return spec;
}

Grid test_grid(glm::dvec3 origin = glm::dvec3(-0.3, 0.2, 0.7)) {
  Grid grid;
  grid.origin = origin;
  grid.step = glm::dvec3(1.0 / 64.0, 1.0 / 48.0, 1.0 / 40.0);
  grid.count = {17, 9, 5};
  grid.first = {3, -2, 5};
  return grid;
}

bool same_bits(float a, float b) {
  return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b);
}

// The grid path (array kernels over rows, row-shared fractal work) and the point path give the
// same bits at every sample, at several filter widths.
void expect_point_equals_grid(const TextureGraph& graph,
                              glm::dvec3 origin = glm::dvec3(-0.3, 0.2, 0.7)) {
  const TextureEvaluator texture(spec_of(graph));
  const Grid grid = test_grid(origin);
  std::vector<float> planes(grid.size() * 3);
  for (double width : {0.0, 1.0 / 64.0, 0.3}) {
    texture.evaluate_grid(grid, width, planes);
    std::size_t i = 0, mismatches = 0;
    for (int k = 0; k < grid.count.z; ++k) {
      for (int j = 0; j < grid.count.y; ++j) {
        for (int x = 0; x < grid.count.x; ++x, ++i) {
          const Texel t = texture.sample(grid.point(x, j, k), width);
          for (int c = 0; c < 3; ++c) {
            mismatches += same_bits(t.colour[c], planes[c * grid.size() + i]) ? 0 : 1;
          }
        }
      }
    }
    EXPECT_EQ(mismatches, 0u) << "width " << width;
  }
}

TEST(GraphEvaluation, PointAndGridAgreeBitForBit) {
  expect_point_equals_grid(testing::builtin_marble_graph());
  expect_point_equals_grid(testing::warped_graph());
  expect_point_equals_grid(testing::warped_graph(), glm::dvec3(1e9, -1e9, 3e8));
}

TEST(GraphEvaluation, PointAndGridAgreeForEveryNoiseAndPattern) {
  const RampKeys bw{{0.0f, glm::vec3(0.0f)}, {1.0f, glm::vec3(1.0f)}};
  for (const char* category : {"noise3d", "turbulence", "cellnoise3d", "worleynoise3d", "stripes",
                               "checker", "rings", "wood"}) {
    TextureGraph g{
        {node("p", "position"), node("p5", "multiply", {{"in1", ref("p")}, {"in2", 5.0}}),
         node("f", category, {{"position", ref("p5")}}),
         node("c", "ramp", {{"in", ref("f")}, {"keys", bw}})},
        {{Channel::colour, "c"}}};
    SCOPED_TRACE(category);
    expect_point_equals_grid(g);
  }
  expect_point_equals_grid(
      TextureGraph{{node("c", "colour_cube", {{"period", 0.4}})}, {{Channel::colour, "c"}}});
}

// Scaling the position by a constant carries the filter width exactly: the graph form of the
// built-in marble (position * 4 into a fractal at scale 1) is the built-in marble, bit for bit,
// at every level of a brick layout.
// With its default ramp, and with one whose averaged colours sum to the edge of [0, 1] (the
// graph clamps its outputs there, so the built-in must not leave it by an ulp).
TEST(GraphEvaluation, GraphMarbleEqualsBuiltinMarble) {
  const ColourRamp to_one{{{0.0f, glm::vec3(0.452404827f)},
                           {0.2f, glm::vec3(0.982142389f)},
                           {0.4f, glm::vec3(0.450086743f)},
                           {0.6f, glm::vec3(1.0f)}}};
  for (const ColourRamp& ramp : {default_ramp(MarbleParams{}), to_one}) {
    TextureSpec builtin;
    builtin.pattern = MarbleParams{};
    builtin.ramp = ramp;
    const TextureEvaluator a(builtin);
    const TextureEvaluator b(spec_of(testing::builtin_marble_graph(ramp)));
    const BrickLayout layout(Volume{}, 16);
    std::vector<float> pa(layout.samples_per_brick() * 3), pb(pa.size());
    for (int level : {0, 1, 2, 3, 4}) {
      evaluate_brick(a, layout, level, {0, 0, 0}, MipSettings{}, pa);
      evaluate_brick(b, layout, level, {0, 0, 0}, MipSettings{}, pb);
      EXPECT_EQ(std::memcmp(pa.data(), pb.data(), pa.size() * sizeof(float)), 0) << level;
      EXPECT_EQ(a.evaluated_octaves(layout.filter_width(level)),
                b.evaluated_octaves(layout.filter_width(level)));
    }
  }
}

// Value fBm at amplitude 0.25 (fields in [0, 0.5]) through a ramp that is far from linear: the
// ramp reads it doubled by a `multiply`, doubled by a `remap` (both carry the fractal's
// spread, scaled), or through `absval` as well (which carries none).
enum class Path { multiply, remap, abs };

TextureGraph faded_noise_ramp(Path path) {
  std::vector<Node> nodes{node("p", "position"),
                          node("p8", "multiply", {{"in1", ref("p")}, {"in2", 8.0}}),
                          node("f", "fractal3d",
                               {{"position", ref("p8")},
                                {"octaves", 6.0},
                                {"amplitude", 0.25},
                                {"basis", std::string("value")}})};
  if (path == Path::remap) {
    nodes.push_back(node("t", "remap", {{"in", ref("f")}, {"inhigh", 0.5}}));
  } else {
    nodes.push_back(node("t", "multiply", {{"in1", ref("f")}, {"in2", 2.0}}));
  }
  std::string last = "t";
  if (path == Path::abs) {
    nodes.push_back(node("a", "absval", {{"in", ref("t")}}));
    last = "a";
  }
  nodes.push_back(node(
      "c", "ramp",
      {{"in", ref(last)},
       {"keys",
        RampKeys{{0.3f, glm::vec3(0.0f)}, {0.45f, glm::vec3(1.0f)}, {0.6f, glm::vec3(0.2f)}}}}));
  return TextureGraph{nodes, {{Channel::colour, "c"}}};
}

// Over boxes where every octave is faded: the sample's colour against the mean of the point
// colours in its box, the mean absolute error of the red channel.
double faded_colour_error(const TextureEvaluator& texture) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  const double width = 0.5;
  double error = 0.0;
  for (int b = 0; b < 8; ++b) {
    const glm::dvec3 centre(u(rng) * 8.0, u(rng) * 8.0, u(rng) * 8.0);
    constexpr int kPoints = 3000;
    double mean = 0.0;
    for (int i = 0; i < kPoints; ++i) {
      mean += texture.sample(centre + width * glm::dvec3(u(rng), u(rng), u(rng))).colour.r;
    }
    error += std::fabs(mean / kPoints - texture.sample(centre, width).colour.r);
  }
  return error / 8;
}

// A ramp reading a fractal node, directly or scaled and shifted by constants, averages its
// colours over the faded octaves' spread, as the built-in turbulence does, instead of
// colouring the box's mean field.
TEST(GraphEvaluation, ARampOfFadedNoiseTakesTheMeanOfItsColours) {
  const double scaled =
      faded_colour_error(TextureEvaluator(spec_of(faded_noise_ramp(Path::multiply))));
  const double remapped =
      faded_colour_error(TextureEvaluator(spec_of(faded_noise_ramp(Path::remap))));
  const double of_mean = faded_colour_error(TextureEvaluator(spec_of(faded_noise_ramp(Path::abs))));
  // The even spread is a model of the faded octaves' distribution: within 0.08 on this steep
  // ramp, where the ramp of the mean field is off by several times that.
  EXPECT_LT(scaled, 0.08);
  EXPECT_LT(remapped, 0.08);
  EXPECT_GT(of_mean, 3.0 * scaled);
}

TEST(GraphEvaluation, CoarseWidthsFadeOctaves) {
  const TextureEvaluator t(spec_of(testing::builtin_marble_graph()));
  EXPECT_EQ(t.evaluated_octaves(0.0), 6);
  EXPECT_LT(t.evaluated_octaves(1.0 / 32.0), 6);
  EXPECT_EQ(t.evaluated_octaves(1.0), 0);
  // A warp widens the filter: the warped fractal keeps fewer octaves than the same graph with
  // a warp of amplitude 0.
  TextureGraph unwarped = testing::warped_graph();
  unwarped.nodes[2].inputs[2].value = 0.0;
  const double width = 1.0 / 128.0;
  EXPECT_LT(compile(testing::warped_graph())->evaluated_octaves(width),
            compile(unwarped)->evaluated_octaves(width));
}

// Every operation has a defined, finite result: 1 / 0, pow(-2, 0.5), sqrt(-1), 5 mod 0 are 0.
TEST(GraphEvaluation, DefinedResultsForSingularInputs) {
  const auto value_of = [](Node n) {
    n.name = "v";
    TextureGraph g{{n, node("c", "convert", {{"in", ref("v")}}, "color3")},
                   {{Channel::colour, "c"}}};
    return TextureEvaluator(spec_of(g)).sample(glm::dvec3(0.1, 0.2, 0.3)).colour.r;
  };
  EXPECT_EQ(value_of(node("", "divide", {{"in1", 1.0}, {"in2", 0.0}})), 0.0f);
  EXPECT_EQ(value_of(node("", "power", {{"in1", -2.0}, {"in2", 0.5}})), 0.0f);
  EXPECT_EQ(value_of(node("", "sqrt", {{"in", -1.0}})), 0.0f);
  EXPECT_EQ(value_of(node("", "modulo", {{"in1", 5.0}, {"in2", 0.0}})), 0.0f);
  EXPECT_EQ(value_of(node("", "multiply", {{"in1", 1e15}, {"in2", 1e15}})), 1.0f);  // clamped
  EXPECT_FLOAT_EQ(value_of(node("", "modulo", {{"in1", -0.25}, {"in2", 1.0}})), 0.75f);
  EXPECT_FLOAT_EQ(value_of(node("", "smoothstep", {{"in", 0.5}, {"low", 0.0}, {"high", 1.0}})),
                  0.5f);
  EXPECT_EQ(value_of(node("", "smoothstep", {{"in", 0.5}, {"low", 1.0}, {"high", 1.0}})), 0.0f);
  EXPECT_FLOAT_EQ(
      value_of(
          node("", "remap",
               {{"in", 0.5}, {"inlow", 0.0}, {"inhigh", 2.0}, {"outlow", 0.2}, {"outhigh", 0.6}})),
      0.3f);
  EXPECT_FLOAT_EQ(value_of(node("", "mix", {{"fg", 1.0}, {"bg", 0.0}, {"mix", 0.25}})), 0.25f);
}

TEST(GraphEvaluation, VectorNodes) {
  TextureGraph g{
      {node("p", "position"),
       node("d", "dotproduct", {{"in1", ref("p")}, {"in2", glm::dvec3(1, 0, 0)}}),
       node("y", "extract", {{"in", ref("p")}, {"index", 1.0}}),
       node("m", "magnitude", {{"in", ref("p")}}),
       node("c", "combine3", {{"in1", ref("d")}, {"in2", ref("y")}, {"in3", ref("m")}}, "color3")},
      {{Channel::colour, "c"}}};
  const glm::vec3 c = TextureEvaluator(spec_of(g)).sample(glm::dvec3(0.3, 0.4, 0.0)).colour;
  EXPECT_FLOAT_EQ(c.r, 0.3f);
  EXPECT_FLOAT_EQ(c.g, 0.4f);
  EXPECT_FLOAT_EQ(c.b, 0.5f);
}

// A constant vector given to an input of any type or a position keeps all three components
// whatever the node's own type, and each component is part of the texture's id.
TEST(GraphEvaluation, ConstantVectorsKeepEveryComponent) {
  const glm::dvec3 v(0.2, 0.4, 0.6);
  const auto colour_of = [](const TextureGraph& g) {
    return TextureEvaluator(spec_of(g)).sample(glm::dvec3(0.3, -0.1, 0.9)).colour;
  };
  const glm::vec3 converted =
      colour_of({{node("c", "convert", {{"in", v}}, "color3")}, {{Channel::colour, "c"}}});
  EXPECT_FLOAT_EQ(converted.g, 0.4f);
  EXPECT_FLOAT_EQ(converted.b, 0.6f);
  const glm::vec3 extracted = colour_of({{node("z", "extract", {{"in", v}, {"index", 2.0}}),
                                          node("c", "convert", {{"in", ref("z")}}, "color3")},
                                         {{Channel::colour, "c"}}});
  EXPECT_FLOAT_EQ(extracted.r, 0.6f);
  const glm::vec3 dot = colour_of(
      {{node("d", "dotproduct", {{"in1", glm::dvec3(1.0)}, {"in2", glm::dvec3(0.5, 0.0, 0.25)}}),
        node("c", "convert", {{"in", ref("d")}}, "color3")},
       {{Channel::colour, "c"}}});
  EXPECT_FLOAT_EQ(dot.r, 0.75f);
  // Noise at a constant position is one value everywhere.
  TextureGraph noise{
      {node("n", "noise3d", {{"position", v}}), node("c", "convert", {{"in", ref("n")}}, "color3")},
      {{Channel::colour, "c"}}};
  const TextureEvaluator constant_noise(spec_of(noise));
  EXPECT_EQ(constant_noise.sample(glm::dvec3(0.0)).colour,
            constant_noise.sample(glm::dvec3(3.7, -1.2, 8.5)).colour);
  const Volume volume;
  TextureGraph other_noise = noise;
  other_noise.nodes[0].inputs[0].value = glm::dvec3(0.2, 9.0, 0.1);
  EXPECT_NE(texture_id(spec_of(noise), volume, 16, MipSettings{}),
            texture_id(spec_of(other_noise), volume, 16, MipSettings{}));
}

TEST(GraphEvaluation, WorleyFeaturesAreOrdered) {
  const auto at = [](const char* feature, glm::dvec3 p) {
    TextureGraph g{{node("w", "worleynoise3d", {{"feature", std::string(feature)}}),
                    node("c", "convert", {{"in", ref("w")}}, "color3")},
                   {{Channel::colour, "c"}}};
    return TextureEvaluator(spec_of(g)).sample(p).colour.r;
  };
  for (glm::dvec3 p : {glm::dvec3(0.2, 0.7, 0.1), glm::dvec3(5.5, -3.25, 9.125)}) {
    const float f1 = at("f1", p), f2 = at("f2", p), d = at("f2_minus_f1", p);
    EXPECT_LE(f1, f2);
    EXPECT_FLOAT_EQ(d, f2 - f1);
  }
}

// The id hashes the canonical form: renaming nodes or listing them in another order keeps it;
// changing a constant changes it.
TEST(GraphEvaluation, TextureIdIgnoresNamesAndOrder) {
  TextureGraph a = testing::warped_graph();
  TextureGraph b = a;
  std::reverse(b.nodes.begin(), b.nodes.end());
  for (Node& n : b.nodes) {
    n.name = "renamed_" + n.name;
    for (NodeInput& in : n.inputs) {
      if (auto* r = std::get_if<NodeRef>(&in.value)) r->node = "renamed_" + r->node;
    }
    std::reverse(n.inputs.begin(), n.inputs.end());
  }
  b.outputs[0].node = "renamed_" + b.outputs[0].node;
  const Volume volume;
  const uint64_t id_a = texture_id(spec_of(a), volume, 16, MipSettings{});
  EXPECT_EQ(id_a, texture_id(spec_of(b), volume, 16, MipSettings{}));
  TextureGraph c = a;
  c.nodes[1].inputs[1].value = 3.5;
  EXPECT_NE(id_a, texture_id(spec_of(c), volume, 16, MipSettings{}));
  // Writing a default out changes nothing either.
  TextureGraph d = a;
  d.nodes[4].inputs.push_back({"lacunarity", 2.0});
  EXPECT_EQ(id_a, texture_id(spec_of(d), volume, 16, MipSettings{}));
}

TEST(GraphEvaluation, OpacityAndSpecularChannels) {
  TextureGraph g{{node("p", "position"), node("x", "extract", {{"in", ref("p")}}),
                  node("c", "constant", {{"value", glm::dvec3(0.5)}}, "color3")},
                 {{Channel::colour, "c"}, {Channel::opacity, "x"}, {Channel::specular, "x"}}};
  TextureSpec spec = spec_of(g, ChannelSet{true, true, true});
  spec.specular = {0.0f, 0.5f};
  const TextureEvaluator t(spec);
  Grid grid;
  grid.origin = glm::dvec3(0.25, 0.0, 0.0);
  std::vector<float> planes(5);
  t.evaluate_grid(grid, 0.0, planes);
  EXPECT_FLOAT_EQ(planes[0], 0.5f);
  EXPECT_FLOAT_EQ(planes[3], 0.25f);
  EXPECT_FLOAT_EQ(planes[4], 0.125f);
}

}  // namespace
}  // namespace soltex::graph
