#include "registration_json.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "base64url.h"
#include "soltex/common/quoted_text.h"
#include "soltex/common/spec_error.h"
#include "soltex/common/texture_id.h"
#include "soltex/common/texture_spec.h"
#include "soltex/scene/scene_error.h"
#include "soltex/scene/strict_json.h"
#include "soltex/scene/texture_spec_json.h"
#include "soltex/spec_proto/brick_proto.h"
#include "soltex/spec_proto/spec_from_proto.h"
#include "texture_registration.h"
#include "texture_registry.h"

namespace soltex::server {
namespace {

using nlohmann::json;

constexpr const char* kBody = "registration";

[[noreturn]] void fail(const std::string& field, const std::string& problem) {
  throw RegistrationError(grpc::StatusCode::INVALID_ARGUMENT,
                          std::string(kBody) + ": " + field + ": " + problem);
}

double number(const json& value, const std::string& field) {
  if (!value.is_number()) fail(field, "must be a number");
  const double v = value.get<double>();
  if (!std::isfinite(v)) fail(field, "must be finite");
  return v;
}

// Unsigned integers are passed on as the client wrote them (up to 2^32 - 1) so that the
// registration's own checks quote the value sent.
// A whole number for a uint32 field; `allowed` is what the field takes, which the message
// names (the value itself is checked against it where the request is registered).
uint32_t unsigned_integer(const json& value, const std::string& field, const std::string& allowed) {
  if (!value.is_number_integer() || value.get<int64_t>() < 0 ||
      value.get<int64_t>() > int64_t{0xFFFFFFFF}) {
    fail(field, "must be " + allowed);
  }
  return static_cast<uint32_t>(value.get<int64_t>());
}

v1::Vec3 vec3(const json& value, const std::string& field) {
  if (!value.is_array() || value.size() != 3) fail(field, "must be an array of 3 numbers");
  v1::Vec3 v;
  v.set_x(number(value[0], field + "[0]"));
  v.set_y(number(value[1], field + "[1]"));
  v.set_z(number(value[2], field + "[2]"));
  return v;
}

v1::Volume volume_from(const json& value) {
  if (!value.is_object()) fail("volume", "must be an object");
  v1::Volume volume;
  *volume.mutable_min() = vec3(json::array({0.0, 0.0, 0.0}), "volume.min");
  *volume.mutable_max() = vec3(json::array({1.0, 1.0, 1.0}), "volume.max");
  volume.set_finest_level_log2(8);
  for (const auto& [key, field] : value.items()) {
    if (key == "min") {
      *volume.mutable_min() = vec3(field, "volume.min");
    } else if (key == "max") {
      *volume.mutable_max() = vec3(field, "volume.max");
    } else if (key == "finest_level_log2") {
      volume.set_finest_level_log2(unsigned_integer(
          field, "volume.finest_level_log2",
          "an integer in [3, " + std::to_string(SpecLimits::kMaxFinestLevelLog2) + "]"));
    } else {
      fail("volume." + escaped_text(key), "unknown key (known: min, max, finest_level_log2)");
    }
  }
  return volume;
}

v1::MipMode mip_mode_from(const json& value) {
  if (value == "band_limited") return v1::MIP_MODE_BAND_LIMITED;
  if (value == "point") return v1::MIP_MODE_POINT;
  if (value == "supersampled") return v1::MIP_MODE_SUPERSAMPLED;
  fail("mip_mode", "must be \"band_limited\", \"point\" or \"supersampled\"");
}

const char* mip_mode_text(MipMode mode) {
  switch (mode) {
    case MipMode::point:
      return "point";
    case MipMode::supersampled:
      return "supersampled";
    case MipMode::band_limited:
      break;
  }
  return "band_limited";
}

json channels_json(const ChannelSet& channels) {
  json out = json::array();
  if (channels.colour) out.push_back("colour");
  if (channels.opacity) out.push_back("opacity");
  if (channels.specular) out.push_back("specular");
  return out;
}

}  // namespace

v1::RegisterTextureRequest registration_from_json(std::string_view text) {
  json body;
  try {
    // A repeated key is refused, as in a scene file, not silently the last one.
    body = parse_strict_json(text, kBody);
  } catch (const SceneError& e) {
    fail(e.field().empty() ? "body" : e.field(), e.problem());
  }
  if (!body.is_object()) fail("body", "must be a JSON object");
  if (!body.contains("texture")) fail("texture", "is required (the texture spec)");
  v1::RegisterTextureRequest request;
  request.set_mip_mode(v1::MIP_MODE_BAND_LIMITED);
  *request.mutable_volume() = volume_from(json::object());
  for (const auto& [key, value] : body.items()) {
    if (key == "texture") {
      try {
        *request.mutable_spec() = to_proto(texture_spec_from_json(value, kBody, "texture"));
      } catch (const SceneError& e) {
        throw RegistrationError(grpc::StatusCode::INVALID_ARGUMENT, e.what());
      }
    } else if (key == "volume") {
      *request.mutable_volume() = volume_from(value);
    } else if (key == "brick_size") {
      request.set_brick_size(unsigned_integer(value, "brick_size", "8 or 16"));
    } else if (key == "mip_mode") {
      request.set_mip_mode(mip_mode_from(value));
    } else if (key == "supersample") {
      request.set_supersample(unsigned_integer(
          value, "supersample",
          "an integer in [0, " + std::to_string(kMaxSupersample) + "] (0: the default, 2)"));
    } else {
      fail(escaped_text(key),
           "unknown key (known: texture, volume, brick_size, mip_mode, supersample)");
    }
  }
  return request;
}

json registration_to_json(const RegisteredTexture& texture) {
  const Volume& volume = texture.layout.volume();
  json out;
  out["texture"] = texture_spec_to_json(texture.evaluator.spec());
  out["volume"] = {{"min", {volume.min.x, volume.min.y, volume.min.z}},
                   {"max", {volume.max.x, volume.max.y, volume.max.z}},
                   {"finest_level_log2", volume.finest_level_log2}};
  out["brick_size"] = texture.layout.brick_size();
  out["mip_mode"] = mip_mode_text(texture.mip.mode);
  out["supersample"] = texture.mip.mode == MipMode::supersampled ? texture.mip.supersample : 2;
  return out;
}

std::string registration_parameter(const RegisteredTexture& texture) {
  return base64url_encode(registration_to_json(texture).dump());
}

json handle_json(const RegisteredTexture& texture) {
  json out;
  out["id"] = texture_id_hex(texture.id);
  out["levels"] = texture.layout.level_count();
  out["brick_size"] = texture.layout.brick_size();
  out["finest_level_log2"] = texture.layout.finest_level_log2();
  out["channels"] = channels_json(texture.evaluator.spec().channels);
  out["spec"] = registration_parameter(texture);
  out["bricks"] = "/v1/textures/" + texture_id_hex(texture.id) +
                  "/bricks/{level}/{x}/{y}/{z}?spec=" + out["spec"].get<std::string>();
  return out;
}

}  // namespace soltex::server
