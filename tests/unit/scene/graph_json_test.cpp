#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "../graph/graph_builders.h"
#include "soltex/common/texture_id.h"
#include "soltex/graph/compiled_graph.h"
#include "soltex/scene/scene_error.h"
#include "soltex/scene/texture_spec_json.h"

namespace soltex {
namespace {

using nlohmann::json;

TEST(GraphJson, HandWrittenGraphReads) {
  const json text = json::parse(R"({
    "graph": {
      "nodes": [
        {"name": "p", "category": "position"},
        {"name": "p4", "category": "multiply", "inputs": {"in1": {"node": "p"}, "in2": 4}},
        {"name": "cells", "category": "worleynoise3d",
         "inputs": {"position": {"node": "p4"}, "feature": "f2_minus_f1", "jitter": 0.9}},
        {"name": "mask", "category": "smoothstep",
         "inputs": {"in": {"node": "cells"}, "low": 0.0, "high": 0.1}},
        {"name": "colour", "category": "ramp",
         "inputs": {"in": {"node": "mask"},
                    "keys": [{"position": 0, "colour": [0.1, 0.1, 0.1]},
                             {"position": 1, "colour": [0.9, 0.8, 0.7]}]}}
      ],
      "outputs": {"colour": "colour", "specular": "mask"}
    },
    "channels": ["colour", "specular"]
  })");
  const TextureSpec spec = texture_spec_from_json(text, "hand.json", "texture");
  ASSERT_NE(spec.graph, nullptr);
  EXPECT_TRUE(spec.channels.specular);
  const json written = texture_spec_to_json(spec);
  const TextureSpec again = texture_spec_from_json(written, "written", "texture");
  EXPECT_EQ(texture_spec_to_json(again), written);
  EXPECT_EQ(texture_id(again, Volume{}, 16, MipSettings{}),
            texture_id(spec, Volume{}, 16, MipSettings{}));
}

TEST(GraphJson, ErrorsCarryTheScenePath) {
  const json text = json::parse(R"({"graph": {
      "nodes": [{"name": "a", "category": "add", "inputs": {"in1": 1, "in3": 2}}],
      "outputs": {"colour": "a"}}})");
  try {
    (void)texture_spec_from_json(text, "scene.json", "objects[0].material.texture");
    FAIL() << "accepted an unknown input";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "objects[0].material.texture.graph.nodes[a].in3") << e.what();
  }
}

TEST(GraphJson, RefusesARampBesideAGraph) {
  const json text = json::parse(R"({"graph": {
      "nodes": [{"name": "c", "category": "constant", "type": "color3", "inputs": {"value": [1, 0, 0]}}],
      "outputs": {"colour": "c"}},
      "ramp": {"keys": [{"position": 0, "colour": [0, 0, 0]}]}})");
  EXPECT_THROW((void)texture_spec_from_json(text, "scene.json", "texture"), SceneError);
}

TEST(GraphJson, AnEmptyListSaysWhatItMightHaveBeen) {
  const json text = json::parse(R"({"graph": {
      "nodes": [{"name": "r", "category": "ramp", "inputs": {"keys": []}}],
      "outputs": {"colour": "r"}}})");
  try {
    (void)texture_spec_from_json(text, "scene.json", "texture");
    FAIL() << "accepted an empty list";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "texture.graph.nodes[0].inputs.keys") << e.what();
    EXPECT_NE(std::string(e.what()).find("an empty list: expected ramp keys"), std::string::npos)
        << e.what();
  }
}

// true and false are for true/false inputs; elsewhere they would be a 1 or 0 nobody wrote.
TEST(GraphJson, ABooleanIsOnlyForATrueFalseInput) {
  const json number = json::parse(R"({"graph": {
      "nodes": [{"name": "n", "category": "noise3d", "inputs": {"amplitude": true}}],
      "outputs": {"colour": "n"}}})");
  try {
    (void)texture_spec_from_json(number, "scene.json", "texture");
    FAIL() << "accepted a boolean amplitude";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "texture.graph.nodes[0].inputs.amplitude") << e.what();
    EXPECT_NE(std::string(e.what()).find("found a boolean"), std::string::npos) << e.what();
  }
  const json flag = json::parse(R"({"graph": {
      "nodes": [{"name": "c", "category": "checker", "inputs": {"three_d": true}},
                {"name": "m", "category": "mix", "type": "color3",
                 "inputs": {"fg": [1, 1, 1], "bg": [0, 0, 0], "mix": {"node": "c"}}}],
      "outputs": {"colour": "m"}}})");
  EXPECT_NO_THROW((void)texture_spec_from_json(flag, "scene.json", "texture"));
  // ... and only true or false: a number or a word is refused, as the built-in checker's is.
  for (const char* value : {"1", "0", "\"yes\""}) {
    json other = flag;
    other["graph"]["nodes"][0]["inputs"]["three_d"] = json::parse(value);
    try {
      (void)texture_spec_from_json(other, "scene.json", "texture");
      ADD_FAILURE() << "accepted three_d = " << value;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.field(), "texture.graph.nodes[0].inputs.three_d") << e.what();
      EXPECT_NE(std::string(e.what()).find("expected true or false"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace soltex
