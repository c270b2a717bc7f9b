#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "graph_builders.h"
#include "soltex/common/spec_error.h"
#include "soltex/graph/compiled_graph.h"
#include "soltex/graph/graph_limits.h"

namespace soltex::graph {
namespace {

using testing::node;
using testing::ref;

SpecError error_of(const TextureGraph& g) {
  try {
    compile(g);
  } catch (const SpecError& e) {
    return e;
  }
  ADD_FAILURE() << "the graph compiled";
  return SpecError("", "", "");
}

TextureGraph grey(std::vector<Node> nodes, const std::string& out) {
  return TextureGraph{std::move(nodes), {{Channel::colour, out}}};
}

TEST(GraphValidation, AcceptsTheExampleGraphs) {
  EXPECT_NO_THROW(compile(testing::builtin_marble_graph()));
  EXPECT_NO_THROW(compile(testing::warped_graph()));
}

TEST(GraphValidation, UnknownCategoryNamesTheNode) {
  const SpecError e = error_of(grey({node("c", "convolve")}, "c"));
  EXPECT_EQ(e.field(), "graph.nodes[c].category");
  EXPECT_EQ(e.value(), "\"convolve\"");
}

TEST(GraphValidation, CycleNamesTheClosingInput) {
  const SpecError e = error_of(grey(
      {node("a", "add", {{"in1", ref("b")}}, "color3"), node("b", "multiply", {{"in1", ref("a")}})},
      "a"));
  EXPECT_NE(e.field().find("].in1"), std::string::npos) << e.what();
  EXPECT_NE(e.bound().find("cycle"), std::string::npos) << e.what();
}

TEST(GraphValidation, SelfReferenceIsACycle) {
  const SpecError e = error_of(grey({node("a", "absval", {{"in", ref("a")}})}, "a"));
  EXPECT_EQ(e.field(), "graph.nodes[a].in");
}

TEST(GraphValidation, TypeMismatchNamesNodeInputAndTypes) {
  const SpecError e = error_of(grey({node("p", "position"), node("n", "noise3d"),
                                     node("c", "combine3", {{"in1", ref("p")}}, "color3")},
                                    "c"));
  EXPECT_EQ(e.field(), "graph.nodes[c].in1");
  EXPECT_EQ(e.value(), "node \"p\" (vector3)");
  EXPECT_EQ(e.bound(), "must be float");
}

TEST(GraphValidation, VectorAndColourDoNotMix) {
  const SpecError e = error_of(grey(
      {node("p", "position"), node("c", "constant", {{"value", glm::dvec3(1, 0, 0)}}, "color3"),
       node("s", "add", {{"in1", ref("c")}, {"in2", ref("p")}})},
      "s"));
  EXPECT_EQ(e.field(), "graph.nodes[s].in2");
}

// A constant [x, y, z] is vector3 or color3 alike: the node's type comes from the node it is
// combined with, whichever input comes first.
TEST(GraphValidation, AConstantVectorTakesTheTypeOfTheNodeBesideIt) {
  const auto colour_with = [](std::vector<NodeInput> inputs, const std::string& category) {
    return grey({node("cc", "colour_cube"), node("c", category, std::move(inputs))}, "c");
  };
  const glm::dvec3 blue(0, 0, 1);
  EXPECT_NO_THROW(compile(colour_with({{"in1", blue}, {"in2", ref("cc")}}, "add")));
  EXPECT_NO_THROW(compile(colour_with({{"in1", ref("cc")}, {"in2", blue}}, "add")));
  EXPECT_NO_THROW(compile(colour_with({{"fg", ref("cc")}, {"bg", blue}, {"mix", 0.5}}, "mix")));
  EXPECT_NO_THROW(compile(colour_with({{"bg", blue}, {"fg", ref("cc")}, {"mix", 0.5}}, "mix")));
  // Without a node beside it, a constant vector keeps its shape's type: vector3, no colour.
  const SpecError e = error_of(grey({node("c", "add", {{"in1", blue}, {"in2", blue}})}, "c"));
  EXPECT_EQ(e.field(), "graph.outputs.colour");
  EXPECT_EQ(e.bound(), "must be color3");
}

TEST(GraphValidation, MissingRequiredInput) {
  const SpecError e = error_of(grey({node("c", "ramp", {{"in", 0.5}})}, "c"));
  EXPECT_EQ(e.field(), "graph.nodes[c].keys");
  EXPECT_EQ(e.value(), "absent");
}

TEST(GraphValidation, ExtraInputListsTheKnownOnes) {
  const SpecError e = error_of(grey({node("n", "noise3d", {{"octaves", 3.0}})}, "n"));
  EXPECT_EQ(e.field(), "graph.nodes[n].octaves");
  EXPECT_NE(e.bound().find("amplitude, pivot, position, basis"), std::string::npos) << e.what();
}

TEST(GraphValidation, NonFiniteAndHugeConstants) {
  for (double bad :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), 1e300}) {
    const SpecError e =
        error_of(grey({node("a", "add", {{"in1", 1.0}, {"in2", bad}}, "color3")}, "a"));
    EXPECT_EQ(e.field(), "graph.nodes[a].in2");
  }
  const SpecError v =
      error_of(grey({node("a", "add", {{"in1", glm::dvec3(1, std::nan(""), 0)}}, "color3")}, "a"));
  EXPECT_EQ(v.field(), "graph.nodes[a].in1");
}

TEST(GraphValidation, ParametersOutOfRangeOrConnected) {
  EXPECT_EQ(error_of(grey({node("n", "fractal3d", {{"octaves", 40.0}})}, "n")).field(),
            "graph.nodes[n].octaves");
  EXPECT_EQ(error_of(grey({node("n", "fractal3d", {{"octaves", 2.5}})}, "n")).bound(),
            "must be an integer");
  EXPECT_EQ(
      error_of(grey({node("n", "fractal3d", {{"basis", std::string("simplex")}})}, "n")).bound(),
      "must be one of gradient|value");
  EXPECT_EQ(error_of(grey({node("k", "constant", {{"value", 3.0}}),
                           node("n", "fractal3d", {{"octaves", ref("k")}})},
                          "n"))
                .field(),
            "graph.nodes[n].octaves");
  // Built-in pattern parameters keep the patterns' own bounds.
  const SpecError s = error_of(grey({node("s", "stripes", {{"width", 0.0}})}, "s"));
  EXPECT_EQ(s.field(), "graph.nodes[s].width");
}

TEST(GraphValidation, NamesAndReferences) {
  EXPECT_EQ(error_of(grey({node("a", "position"), node("a", "position")}, "a")).field(),
            "graph.nodes[a].name");
  EXPECT_EQ(error_of(grey({node("", "position")}, "a")).field(), "graph.nodes[0].name");
  EXPECT_EQ(error_of(grey({node("a", "absval", {{"in", ref("ghost")}})}, "a")).field(),
            "graph.nodes[a].in");
  EXPECT_EQ(error_of(grey({node("a", "position")}, "ghost")).field(), "graph.outputs.colour");
}

TEST(GraphValidation, NamesAreAtMost64BytesOfWellFormedUtf8) {
  // 32 two-byte letters fill the bound; one more, or a byte that is not UTF-8, does not fit.
  std::string cyrillic;
  for (int i = 0; i < 32; ++i) cyrillic += "\xd1\x8f";
  EXPECT_NO_THROW(compile(
      grey({node(cyrillic, "constant", {{"value", glm::dvec3(1.0)}}, "color3")}, cyrillic)));
  EXPECT_EQ(error_of(grey({node(cyrillic + "\xd1\x8f", "position")}, "a")).field(),
            "graph.nodes[0].name");
  for (const std::string bad :
       {"\xff\xfe", "a\xc0\xaf", "\xed\xa0\x80", "\xf4\x90\x80\x80", "\xe2\x82"}) {
    const SpecError e = error_of(grey({node(bad, "position")}, bad));
    EXPECT_EQ(e.field(), "graph.nodes[0].name");
    EXPECT_NE(e.value().find("\\x"), std::string::npos) << e.what();  // the bytes, escaped
    EXPECT_NE(e.bound().find("bytes of UTF-8"), std::string::npos) << e.what();
  }
}

TEST(GraphValidation, MessagesShowClientStringsShortAndEscaped) {
  // However long a name or category is sent, the message names the field and the bound in a
  // few hundred bytes: a gRPC status must fit the client's metadata limit.
  const SpecError name = error_of(grey({node(std::string(10000, 'n'), "position")}, "a"));
  EXPECT_EQ(name.field(), "graph.nodes[0].name");
  EXPECT_NE(name.bound().find("must be 1 to 64 bytes of UTF-8"), std::string::npos);
  EXPECT_NE(name.value().find("(10000 bytes)"), std::string::npos) << name.value();
  EXPECT_LT(std::string(name.what()).size(), 300u) << name.what();

  const SpecError category = error_of(grey({node("c", std::string(100000, 'x'))}, "c"));
  EXPECT_EQ(category.field(), "graph.nodes[c].category");
  EXPECT_NE(category.value().find("(100000 bytes)"), std::string::npos);
  EXPECT_LT(std::string(category.what()).size(), 300u) << category.what();

  // A NUL in a name is shown, not an end of the message.
  const std::string nul_name("a\0b", 3);
  const SpecError nul = error_of(grey({node(nul_name, "nonesuch")}, nul_name));
  EXPECT_EQ(nul.field(), "graph.nodes[a\\x00b].category");
  EXPECT_EQ(std::string(nul.what()).find('\0'), std::string::npos);

  const SpecError input =
      error_of(grey({node("a", "absval", {{std::string(5000, 'i'), 1.0}})}, "a"));
  EXPECT_LT(std::string(input.what()).size(), 300u) << input.what();
  const SpecError choice =
      error_of(grey({node("a", "noise3d", {{"basis", std::string(5000, 'z')}})}, "a"));
  EXPECT_LT(std::string(choice.what()).size(), 400u) << choice.what();
}

TEST(GraphValidation, OutputTypes) {
  const SpecError e = error_of(grey({node("n", "noise3d")}, "n"));
  EXPECT_EQ(e.field(), "graph.outputs.colour");
  EXPECT_EQ(e.bound(), "must be color3");
  TextureGraph opacity{{node("c", "constant", {{"value", glm::dvec3(1.0)}}, "color3")},
                       {{Channel::opacity, "c"}}};
  EXPECT_EQ(error_of(opacity).bound(), "must be float");
}

// The depth bound counts every node on a chain as written, whatever it starts from (the
// position, a constant) and whatever lowering makes of it.
TEST(GraphValidation, TheDepthBoundCountsEveryNodeOnTheChain) {
  for (const char* start : {"position", "constant"}) {
    for (const int nodes : {GraphLimits::kMaxDepth, GraphLimits::kMaxDepth + 1}) {
      std::vector<Node> chain{start == std::string("position")
                                  ? node("n0", "position")
                                  : node("n0", "constant", {{"value", glm::dvec3(0.5)}})};
      for (int i = 1; i < nodes - 1; ++i) {
        chain.push_back(
            node("n" + std::to_string(i), "absval", {{"in", ref("n" + std::to_string(i - 1))}}));
      }
      chain.push_back(node("c", "convert", {{"in", ref(chain.back().name)}}, "color3"));
      ASSERT_EQ(static_cast<int>(chain.size()), nodes);
      if (nodes <= GraphLimits::kMaxDepth) {
        EXPECT_NO_THROW(compile(grey(chain, "c"))) << start << ", " << nodes << " nodes";
        continue;
      }
      const SpecError e = error_of(grey(chain, "c"));
      EXPECT_EQ(e.value(), "a chain of " + std::to_string(nodes) + " nodes") << start;
      EXPECT_EQ(e.bound(), "at most 64 nodes on a chain from an output") << start;
    }
  }
}

// dotproduct takes vectors of either kind, but two of one kind, as every other node does.
TEST(GraphValidation, DotproductTakesTwoVectorsOfOneKind) {
  const glm::dvec3 blue(0.0, 0.0, 1.0);
  const auto graph_with = [&](InputValue in2) {
    return grey({node("p", "position"), node("k", "constant", {{"value", blue}}, "color3"),
                 node("d", "dotproduct", {{"in1", ref("p")}, {"in2", std::move(in2)}}),
                 node("c", "convert", {{"in", ref("d")}}, "color3")},
                "c");
  };
  const SpecError e = error_of(graph_with(ref("k")));
  EXPECT_EQ(e.field(), "graph.nodes[d].in2");
  EXPECT_EQ(e.bound(), "must be vector3 like in1: vector3 and color3 do not mix");
  EXPECT_NO_THROW(compile(graph_with(blue)));  // a constant [x, y, z] is either kind
  EXPECT_NO_THROW(compile(graph_with(ref("p"))));
}

TEST(GraphValidation, NodeCountDepthAndCostBounds) {
  std::vector<Node> chain{node("n0", "constant", {{"value", 0.5}})};
  for (int i = 1; i <= GraphLimits::kMaxDepth + 1; ++i) {
    chain.push_back(
        node("n" + std::to_string(i), "absval", {{"in", ref("n" + std::to_string(i - 1))}}));
  }
  chain.push_back(node("c", "convert", {{"in", ref(chain.back().name)}}, "color3"));
  const SpecError depth = error_of(grey(chain, "c"));
  EXPECT_EQ(depth.field(), "graph.nodes");
  EXPECT_NE(depth.value().find("a chain of"), std::string::npos) << depth.value();

  std::vector<Node> many;
  for (int i = 0; i <= GraphLimits::kMaxNodes; ++i) {
    many.push_back(node("n" + std::to_string(i), "position"));
  }
  EXPECT_EQ(error_of(grey(many, "n0")).field(), "graph.nodes");

  // Seven 16-octave vector fractals: 336 octaves per sample.
  std::vector<Node> costly{node("s0", "fractal3d", {{"octaves", 16.0}}, "vector3")};
  for (int i = 1; i < 7; ++i) {
    costly.push_back(node("s" + std::to_string(i), "fractal3d",
                          {{"octaves", 16.0}, {"position", ref("s" + std::to_string(i - 1))}},
                          "vector3"));
  }
  costly.push_back(node("c", "convert", {{"in", ref("s6")}}, "color3"));
  const SpecError cost = error_of(grey(costly, "c"));
  EXPECT_NE(cost.value().find("estimated cost"), std::string::npos) << cost.what();
}

TEST(GraphValidation, SpecRefusesChannelsTheGraphLacks) {
  TextureSpec spec;
  spec.graph = compile(testing::builtin_marble_graph());
  spec.channels.specular = true;
  try {
    validated(spec);
    FAIL() << "validated a spec whose graph has no specular output";
  } catch (const SpecError& e) {
    EXPECT_EQ(e.field(), "graph.outputs.specular");
  }
  spec.channels.specular = false;
  spec.ramp = default_ramp(MarbleParams{});
  EXPECT_THROW(validated(spec), SpecError);
}

}  // namespace
}  // namespace soltex::graph
