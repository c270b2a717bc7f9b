#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "soltex/common/texture_spec.h"

// Texture specs as JSON, mirroring proto soltex.v1.TextureSpec field for field:
//   {"marble": {"frequency": 2, "turbulence": {"octave_max": 6}},
//    "ramp": {"keys": [{"position": 0, "colour": [0.2, 0.2, 0.3]}, ...]},
//    "channels": ["colour", "specular"], "specular": {"low": 0, "high": 0.6}}
// Absent fields take the documented defaults; enums are lower-case names ("x", "gradient",
// "product"); vectors and colours are [x, y, z] arrays or {"x", "y", "z"} / {"r", "g", "b"}
// objects. docs/SCENES.md lists every field.
namespace soltex {

// Reads and validates a spec. Throws SceneError naming `file` and the field's path, which
// starts with `path` (e.g. "objects[2].material.texture"): unknown keys, wrong types, not
// exactly one pattern, and every bound of validated().
TextureSpec texture_spec_from_json(const nlohmann::json& json, const std::string& file,
                                   const std::string& path);

// Every field written, defaults included, so equal specs give equal JSON and reading the
// result gives the spec back.
nlohmann::json texture_spec_to_json(const TextureSpec& spec);

}  // namespace soltex
