#pragma once

#include <stdexcept>
#include <string>

namespace soltex {

class SpecError;

// A scene that cannot be used. The message names the file, the field path inside it and the
// problem, e.g.
// "museum.json: objects[2].transform.scale[0]: -1 is out of range: must be in [1e-06, 1e+06]".
// field() is empty for problems with the file as a whole (unreadable, not JSON).
class SceneError : public std::runtime_error {
 public:
  SceneError(std::string file, std::string field, std::string problem);

  // A texture or volume bound broken inside the scene: SpecError's own message, prefixed by
  // the file and the JSON path of the texture ("objects[0].material.texture").
  static SceneError from_spec_error(std::string file, const std::string& path_prefix,
                                    const SpecError& error);

  const std::string& file() const { return file_; }
  const std::string& field() const { return field_; }
  const std::string& problem() const { return problem_; }

 private:
  SceneError(std::string file, std::string field, std::string problem, std::string message);

  std::string file_;
  std::string field_;
  std::string problem_;
};

}  // namespace soltex
