#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace soltex {

// JSON as soltex reads its files and request bodies: a key repeated in one object is an error
// (nlohmann would keep the last), and a parse error names where the parser was as a JSON path
// ("objects[2].transform.translate[0]"). Throws SceneError naming `file`.
nlohmann::json parse_strict_json(std::string_view text, const std::string& file);

}  // namespace soltex
