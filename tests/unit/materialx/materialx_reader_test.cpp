// MaterialX documents written by hand from the Standard Nodes specification, and the example
// documents in deploy/scenes/graphs.
#include "soltex/materialx/materialx_reader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "soltex/common/text_file.h"
#include "soltex/common/texture_id.h"
#include "soltex/materialx/example_graphs.h"
#include "soltex/scene/scene_loader.h"

namespace soltex::materialx {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

MaterialxSource source(std::string text, std::string graph = "g", std::string output = "out") {
  return {std::move(text), "hand.mtlx", std::move(graph), std::move(output)};
}

std::string error_of(const MaterialxSource& s) {
  try {
    compile_nodegraph(s);
  } catch (const MaterialxError& e) {
    return e.what();
  }
  return "(no error)";
}

const char* kNoise = R"(<?xml version="1.0"?>
<materialx version="1.38">
  <nodegraph name="g">
    <position name="p" type="vector3" />
    <multiply name="p4" type="vector3">
      <input name="in1" type="vector3" nodename="p" />
      <input name="in2" type="float" value="4.0" />
    </multiply>
    <noise3d name="n" type="float">
      <input name="position" type="vector3" nodename="p4" />
      <input name="amplitude" type="float" value="0.5" />
      <input name="pivot" type="float" value="0.5" />
    </noise3d>
    <mix name="c" type="color3">
      <input name="fg" type="color3" value="1, 1, 1" />
      <input name="bg" type="color3" value="0.1, 0.2, 0.3" />
      <input name="mix" type="float" nodename="n" />
    </mix>
    <output name="out" type="color3" nodename="c" />
  </nodegraph>
</materialx>
)";

TEST(MaterialxReader, ReadsStandardNodes) {
  const graph::TextureGraph g = read_nodegraph(source(kNoise));
  ASSERT_EQ(g.nodes.size(), 4u);
  EXPECT_EQ(g.nodes[2].category, "noise3d");
  EXPECT_EQ(g.outputs.size(), 1u);
  EXPECT_EQ(g.outputs[0].node, "c");
  const auto compiled = compile_nodegraph(source(kNoise));
  EXPECT_TRUE(compiled->has_colour());
}

TEST(MaterialxReader, RefusesUnsupportedNodesWithNameCategoryAndLine) {
  std::string text = kNoise;
  text.replace(text.find("<noise3d name=\"n\""), 8, "<blur");
  text.replace(text.find("</noise3d>"), 10, "</blur>");
  const std::string e = error_of(source(text));
  EXPECT_THAT(e, HasSubstr("hand.mtlx:9:"));
  EXPECT_THAT(e, HasSubstr("node \"n\" (blur)"));
}

TEST(MaterialxReader, GraphErrorsPointAtTheNodesLine) {
  std::string text = kNoise;
  // p4 <- c <- n <- p4 (the input's type left out: it is not what is wrong here)
  text.replace(text.find("type=\"float\" value=\"4.0\""), 24, "nodename=\"c\"");
  const std::string e = error_of(source(text));
  EXPECT_THAT(e, HasSubstr("cycle"));
  EXPECT_THAT(e, HasSubstr("hand.mtlx:"));
  std::string wrong_type = kNoise;
  const std::string colour_mix = "<mix name=\"c\" type=\"color3\"";
  wrong_type.replace(wrong_type.find(colour_mix), colour_mix.size(),
                     "<mix name=\"c\" type=\"vector3\"");
  EXPECT_THAT(error_of(source(wrong_type)), HasSubstr("must be color3"));
}

TEST(MaterialxReader, NameAndOutputErrorsPointAtTheirElementsLine) {
  // kNoise's lines: 4 position "p", 5 multiply "p4", 9 noise3d "n", 14 mix "c", 19 output.
  std::string long_name = kNoise;
  long_name.replace(long_name.find("name=\"n\""), 8, "name=\"" + std::string(65, 'n') + "\"");
  long_name.replace(long_name.find("nodename=\"n\""), 12,
                    "nodename=\"" + std::string(65, 'n') + "\"");
  EXPECT_THAT(error_of(source(long_name)),
              AllOf(HasSubstr("hand.mtlx:9: graph.nodes[2].name"), HasSubstr("1 to 64 bytes")));
  std::string not_utf8 = kNoise;
  not_utf8.replace(not_utf8.find("name=\"n\""), 8, "name=\"\xff\xfe\"");
  EXPECT_THAT(error_of(source(not_utf8)), AllOf(HasSubstr("hand.mtlx:9:"), HasSubstr("UTF-8")));
  std::string to_nothing = kNoise;
  to_nothing.replace(to_nothing.find("nodename=\"c\""), 12, "nodename=\"zz\"");
  EXPECT_THAT(error_of(source(to_nothing)),
              AllOf(HasSubstr("hand.mtlx:19: graph.outputs.colour"), HasSubstr("names no node")));
}

TEST(MaterialxReader, TwoNodegraphsOfTheNameAskedForAreRefused) {
  std::string twice = kNoise;
  const std::size_t end = twice.find("</materialx>");
  const std::size_t first = twice.find("  <nodegraph");
  twice.insert(end, twice.substr(first, end - first));
  EXPECT_THAT(error_of(source(twice)),
              AllOf(HasSubstr("hand.mtlx:21: a second nodegraph named \"g\""),
                    HasSubstr("the first is on line 3")));
}

TEST(MaterialxReader, AnInputIsAValueOrANodeOfItsOwnType) {
  std::string boolean_amplitude = kNoise;
  boolean_amplitude.replace(boolean_amplitude.find(R"(type="float" value="0.5" />)"), 27,
                            R"(type="boolean" value="true" />)");
  EXPECT_THAT(error_of(source(boolean_amplitude)),
              AllOf(HasSubstr("hand.mtlx:"), HasSubstr("\"amplitude\": takes a number")));
  std::string both = kNoise;
  both.replace(both.find(R"(nodename="n" />)"), 15, R"(nodename="n" value="0.5" />)");
  EXPECT_THAT(error_of(source(both)), HasSubstr("a value or a nodename, not both"));
  std::string constant_output = kNoise;
  constant_output.replace(constant_output.find(R"(nodename="c" />)"), 15, R"(value="1, 0, 0" />)");
  EXPECT_THAT(error_of(source(constant_output)),
              AllOf(HasSubstr("hand.mtlx:"), HasSubstr("\"out\" needs a nodename")));
  // A type the graphs do not have is named as such, not as a value that fails to parse.
  for (const std::string type : {"vector2", "filename", "color4"}) {
    std::string unsupported = kNoise;
    unsupported.replace(unsupported.find(R"(type="float" value="0.5" />)"), 27,
                        R"(type=")" + type + R"(" value="1, 1" />)");
    EXPECT_THAT(error_of(source(unsupported)),
                AllOf(HasSubstr("hand.mtlx:"),
                      HasSubstr("type \"" + type + "\" is not supported (float, integer")))
        << type;
  }
  // A colour constant where a float belongs is described by its shape, not as a vector3.
  std::string colour_amplitude = kNoise;
  colour_amplitude.replace(colour_amplitude.find(R"(type="float" value="0.5" />)"), 27,
                           R"(type="color3" value="1, 1, 1" />)");
  EXPECT_THAT(error_of(source(colour_amplitude)),
              AllOf(HasSubstr("(three components): must be"), Not(HasSubstr("(vector3)"))));
}

// Attributes that change what an input means are honoured or refused, never ignored.
TEST(MaterialxReader, ColourSpacesSwizzlesAndDeclaredTypes) {
  std::string srgb = kNoise;
  srgb.replace(srgb.find(R"(value="1, 1, 1" />)"), 18,
               R"(value="0.5, 0.04, 1" colorspace="srgb_texture" />)");
  const graph::TextureGraph g = read_nodegraph(source(srgb));
  const glm::dvec3 fg = std::get<glm::dvec3>(g.nodes[3].inputs[0].value);
  EXPECT_NEAR(fg.x, 0.21404, 1e-5);  // sRGB 0.5 is linear 0.214
  EXPECT_DOUBLE_EQ(fg.y, 0.04 / 12.92);
  EXPECT_DOUBLE_EQ(fg.z, 1.0);
  std::string whole_document = kNoise;  // the document's space holds for its colours
  whole_document.replace(whole_document.find(R"(version="1.38")"), 14,
                         R"(version="1.38" colorspace="srgb_texture")");
  EXPECT_NEAR(
      std::get<glm::dvec3>(read_nodegraph(source(whole_document)).nodes[3].inputs[1].value).x,
      0.01002, 1e-5);
  std::string acescg = kNoise;
  acescg.replace(acescg.find(R"(value="1, 1, 1" />)"), 18,
                 R"(value="1, 1, 1" colorspace="acescg" />)");
  EXPECT_THAT(error_of(source(acescg)), AllOf(HasSubstr("hand.mtlx:15:"),
                                              HasSubstr("colorspace \"acescg\" is not supported")));
  std::string swizzle = kNoise;
  swizzle.replace(swizzle.find(R"(nodename="p" />)"), 15, R"(nodename="p" channels="zyx" />)");
  EXPECT_THAT(error_of(source(swizzle)),
              AllOf(HasSubstr("hand.mtlx:6:"), HasSubstr("channels=\"zyx\") are not supported")));
  std::string declared = kNoise;
  declared.replace(declared.find(R"(type="vector3" nodename="p4")"), 28,
                   R"(type="color3" nodename="p4")");
  EXPECT_THAT(error_of(source(declared)),
              AllOf(HasSubstr("hand.mtlx:10:"),
                    HasSubstr("is declared \"color3\", but node \"p4\" is \"vector3\"")));
}

// A name holding ']' still finds its node's line.
TEST(MaterialxReader, ANameWithABracketFindsItsLine) {
  std::string text = kNoise;
  text.replace(text.find(R"(name="n")"), 8, R"(name="a]b")");
  text.replace(text.find(R"(nodename="n")"), 12, R"(nodename="a]b")");
  text.replace(text.find(R"(name="amplitude" type="float" value="0.5")"), 42,
               R"(name="amplitude" type="float" value="1e300")");
  EXPECT_THAT(error_of(source(text)), HasSubstr("hand.mtlx:9:"));
}

TEST(MaterialxReader, DocumentProblems) {
  EXPECT_THAT(error_of(source("<materialx><nodegraph")), HasSubstr("not XML"));
  EXPECT_THAT(error_of(source(kNoise, "other")), HasSubstr("no nodegraph named \"other\""));
  EXPECT_THAT(error_of(source(kNoise, "g", "colour")), HasSubstr("has no output \"colour\""));
  std::string interface = kNoise;
  interface.replace(interface.find("value=\"0.5\""), 11, "interfacename=\"amp\"");
  EXPECT_THAT(error_of(source(interface)), HasSubstr("interface inputs are not supported"));
  for (const char* text : {"four", "0x4", "4,", ""}) {
    std::string bad_value = kNoise;
    bad_value.replace(bad_value.find("value=\"4.0\""), 11, std::string("value=\"") + text + "\"");
    EXPECT_THAT(error_of(source(bad_value)), HasSubstr("is not a float")) << text;
  }
  std::string trailing = kNoise;
  trailing.replace(trailing.find("\"1, 1, 1\""), 9, "\"1, 1, 1,\"");
  EXPECT_THAT(error_of(source(trailing)), HasSubstr("is not a color3"));
}

// The example scene's graphs, inline and from their .mtlx documents, are the same textures.
TEST(MaterialxReader, ExampleDocumentsEqualTheirJsonGraphs) {
  const std::filesystem::path scenes = std::filesystem::path(SOLTEX_SOURCE_DIR) / "deploy/scenes";
  const Scene inline_graphs = load_scene(scenes / "graph-examples.json");
  const Scene documents = load_scene(scenes / "graph-examples-mtlx.json");
  ASSERT_EQ(inline_graphs.objects.size(), 4u);
  ASSERT_EQ(documents.objects.size(), inline_graphs.objects.size());
  for (std::size_t i = 0; i < documents.objects.size(); ++i) {
    const TextureSpec& a = inline_graphs.objects[i].material.texture;
    const TextureSpec& b = documents.objects[i].material.texture;
    ASSERT_NE(a.graph, nullptr);
    EXPECT_EQ(texture_id(a, Volume{}, 16, MipSettings{}),
              texture_id(b, Volume{}, 16, MipSettings{}))
        << inline_graphs.objects[i].name;
  }
}

// The built-in examples are the documents in deploy/scenes/graphs, as the files read now.
TEST(MaterialxReader, BuiltInExamplesAreTheDocuments) {
  const std::filesystem::path dir =
      std::filesystem::path(SOLTEX_SOURCE_DIR) / "deploy/scenes/graphs";
  ASSERT_EQ(example_graphs().size(), 4u);
  for (const ExampleGraph& example : example_graphs()) {
    std::string nodegraph = example.name;
    std::replace(nodegraph.begin(), nodegraph.end(), '-', '_');
    TextureSpec built_in, from_file;
    built_in.graph = example.graph;
    from_file.graph =
        compile_nodegraph({read_text_file((dir / (example.name + ".mtlx")).string(), "MaterialX"),
                           example.name, nodegraph, "out"});
    EXPECT_EQ(texture_id(built_in, Volume{}, 16, MipSettings{}),
              texture_id(from_file, Volume{}, 16, MipSettings{}))
        << example.name;
  }
}

}  // namespace
}  // namespace soltex::materialx
