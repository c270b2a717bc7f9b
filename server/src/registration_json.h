#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>

#include "soltex/v1/brick_service.pb.h"
#include "texture_registry.h"

namespace soltex::server {

// A texture registration as JSON, for HTTP clients: RegisterTextureRequest field for field,
// the spec in the scene files' texture format (docs/SCENES.md):
//   {"texture": {"marble": {...}, "ramp": {...}, "channels": [...]},
//    "volume": {"min": [x, y, z], "max": [x, y, z], "finest_level_log2": 9},
//    "brick_size": 16, "mip_mode": "band_limited", "supersample": 2}
// Only "texture" is required; the rest default as in the proto (volume: the unit cube at
// level 8; brick_size 16; mip_mode band_limited; supersample 2).

// Reads `text` into a request. Throws RegistrationError (INVALID_ARGUMENT) naming the field:
// not JSON, unknown keys, wrong types, and every bound the spec reader checks. Bounds on
// brick_size, mip_mode and supersample are left to register_texture(), which words them as it
// does for gRPC.
v1::RegisterTextureRequest registration_from_json(std::string_view text);

// The canonical registration of a registered texture: every field written, defaults
// included, doubles in shortest round-trip form. Reading it back registers the same id.
nlohmann::json registration_to_json(const RegisteredTexture& texture);

// What POST /v1/textures answers: id, levels, brick_size, finest_level_log2, channels, and the
// canonical registration as base64url ("spec", for brick URLs any replica can answer).
nlohmann::json handle_json(const RegisteredTexture& texture);

// base64url of the canonical registration's compact text.
std::string registration_parameter(const RegisteredTexture& texture);

}  // namespace soltex::server
