#include "registration_json.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "base64url.h"
#include "texture_registration.h"
#include "texture_registry.h"

namespace soltex::server {
namespace {

TexturePin register_json(TextureRegistry& registry, const std::string& text) {
  return register_texture(registry, registration_from_json(text), "test");
}

TEST(RegistrationJson, DefaultsAsTheProtoAndACanonicalFormThatRegistersTheSameId) {
  TextureRegistry registry(RegistryLimits{});
  const TexturePin pin = register_json(
      registry, R"({"texture": {"wood": {"ring_spacing": 0.15}, "channels": ["specular"]},
                    "volume": {"min": [-2, -1, 0], "max": [2, 3, 4], "finest_level_log2": 7},
                    "brick_size": 8, "mip_mode": "supersampled", "supersample": 3})");
  const RegisteredTexture& texture = *pin.texture();
  EXPECT_EQ(texture.layout.brick_size(), 8);
  EXPECT_EQ(texture.layout.finest_level_log2(), 7);
  EXPECT_EQ(texture.mip.mode, MipMode::supersampled);
  EXPECT_EQ(texture.mip.supersample, 3);

  const nlohmann::json canonical = registration_to_json(texture);
  EXPECT_EQ(canonical["volume"]["min"], nlohmann::json::array({-2.0, -1.0, 0.0}));
  EXPECT_EQ(canonical["mip_mode"], "supersampled");
  TextureRegistry other(RegistryLimits{});
  EXPECT_EQ(register_json(other, canonical.dump()).texture()->id, texture.id);
  const auto decoded = base64url_decode(registration_parameter(texture));
  ASSERT_TRUE(decoded);
  EXPECT_EQ(nlohmann::json::parse(*decoded), canonical);

  const nlohmann::json handle = handle_json(texture);
  EXPECT_EQ(handle["levels"], 5);  // 2^7 cells in bricks of 2^3: levels 0 to 4
  EXPECT_EQ(handle["channels"], nlohmann::json::array({"specular"}));
}

TEST(RegistrationJson, OnlyTheTextureIsRequired) {
  TextureRegistry registry(RegistryLimits{});
  const TexturePin pin = register_json(registry, R"({"texture": {"marble": {}}})");
  EXPECT_EQ(pin.texture()->layout.brick_size(), 16);
  EXPECT_EQ(pin.texture()->layout.finest_level_log2(), 8);
  EXPECT_EQ(pin.texture()->mip.mode, MipMode::band_limited);
}

TEST(RegistrationJson, RefusalsNameTheField) {
  const struct {
    const char* body;
    const char* names;
  } cases[] = {
      {"[]", "body: must be a JSON object"},
      {"{", "body: not valid JSON"},
      {R"({"texture": {"marble": {"frequency": 2, "frequency": 3}}})",
       "texture.marble.frequency: duplicate key \"frequency\""},
      {"{}", "texture: is required"},
      {R"({"texture": {"marble": {}}, "colour": 1})", "colour: unknown key"},
      {R"({"texture": {"marble": {}}, "volume": {"min": [0, 0]}})", "volume.min: must be an array"},
      {R"({"texture": {"marble": {}}, "volume": {"max": [1, "a", 1]}})", "volume.max[1]"},
      {R"({"texture": {"marble": {}}, "volume": {"size": 1}})", "volume.size: unknown key"},
      {R"({"texture": {"marble": {}}, "brick_size": -8})", "brick_size: must be 8 or 16"},
      {R"({"texture": {"marble": {}}, "volume": {"finest_level_log2": 2.5}})",
       "volume.finest_level_log2: must be an integer in [3, 14]"},
      {R"({"texture": {"marble": {}}, "mip_mode": "box"})", "mip_mode: must be"},
      {R"({"texture": {"marble": {"turbulence": {"octave_max": 99}}}})", "texture.marble"},
  };
  for (const auto& c : cases) {
    try {
      (void)registration_from_json(c.body);
      ADD_FAILURE() << c.body << " was accepted";
    } catch (const RegistrationError& e) {
      EXPECT_EQ(e.code(), grpc::StatusCode::INVALID_ARGUMENT);
      EXPECT_NE(std::string(e.what()).find(c.names), std::string::npos) << e.what();
    }
  }
}

TEST(RegistrationJson, RefusalsQuoteWhatWasSentShortly) {
  const std::string huge(1000000, 'k');
  const std::string graph_with_category =
      R"({"texture": {"graph": {"nodes": [{"name": "a", "category": ")" + huge +
      R"("}], "outputs": {"colour": "a"}}}})";
  const std::string bodies[] = {
      graph_with_category,
      R"({"texture": {"marble": {}}, ")" + huge + R"(": 1})",
      R"({"texture": {"marble": {}}, "volume": {")" + huge + R"(": 1}})",
      R"({"texture": {"marble": {")" + huge + R"(": 1}}})",
      R"({"texture": {"marble": {}, ")" + huge + R"(": 1, ")" + huge + R"(": 2}})",
  };
  TextureRegistry registry(RegistryLimits{});
  for (const std::string& body : bodies) {
    try {
      (void)register_json(registry, body);
      ADD_FAILURE() << body.substr(0, 100) << " was accepted";
    } catch (const RegistrationError& e) {
      EXPECT_EQ(e.code(), grpc::StatusCode::INVALID_ARGUMENT);
      EXPECT_LT(std::string(e.what()).size(), 400u) << e.what();
      EXPECT_NE(std::string(e.what()).find("(1000000 bytes)"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace soltex::server
