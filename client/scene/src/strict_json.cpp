#include "soltex/scene/strict_json.h"

#include <set>
#include <vector>

#include "soltex/common/quoted_text.h"
#include "soltex/scene/scene_error.h"

namespace soltex {
namespace {

// Strips nlohmann's "[json.exception.parse_error.101] " tag: the rest says what and where.
std::string without_exception_tag(const std::string& message) {
  const std::size_t end = message.find("] ");
  return message.rfind("[json.exception.", 0) == 0 && end != std::string::npos
             ? message.substr(end + 2)
             : message;
}

}  // namespace

nlohmann::json parse_strict_json(std::string_view text, const std::string& file) {
  // Where the parser is, as a JSON path ("objects[2].transform.translate[0]"), so that an error
  // the parser itself raises (a number too large for a double) names its field too.
  struct Level {
    bool array;
    std::string key;             // objects: the key being read
    std::size_t index = 0;       // arrays: the element being read
    std::set<std::string> keys;  // objects: keys seen, to refuse repeats
  };
  std::vector<Level> levels;
  const auto path = [&] {
    std::string out;
    for (const Level& level : levels) {
      if (level.array) {
        out += "[" + std::to_string(level.index) + "]";
      } else if (!level.key.empty()) {
        out += (out.empty() ? "" : ".") + escaped_text(level.key);
      }
    }
    return out;
  };
  const auto element_done = [&] {
    if (!levels.empty() && levels.back().array) ++levels.back().index;
  };
  const nlohmann::json::parser_callback_t track = [&](int, nlohmann::json::parse_event_t event,
                                                      nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    switch (event) {
      case Event::object_start:
        levels.push_back({false, {}, 0, {}});
        break;
      case Event::array_start:
        levels.push_back({true, {}, 0, {}});
        break;
      case Event::object_end:
      case Event::array_end:
        levels.pop_back();
        element_done();
        break;
      case Event::key: {
        const std::string key = parsed.get<std::string>();
        // nlohmann keeps the last of two equal keys; a repeated key is a mistake to name.
        if (!levels.back().keys.insert(key).second) {
          throw SceneError(file, path(), "duplicate key " + quoted_text(key) + " in one object");
        }
        levels.back().key = key;
        break;
      }
      case Event::value:
        element_done();
        break;
    }
    return true;
  };
  try {
    return nlohmann::json::parse(text.begin(), text.end(), track);
  } catch (const nlohmann::json::exception& error) {
    throw SceneError(file, path(), "not valid JSON: " + without_exception_tag(error.what()));
  }
}

}  // namespace soltex
