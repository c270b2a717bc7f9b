#include "soltex/scene/scene_error.h"

#include <utility>

#include "soltex/common/spec_error.h"

namespace soltex {
namespace {

std::string compose(const std::string& file, const std::string& field, const std::string& problem) {
  return field.empty() ? file + ": " + problem : file + ": " + field + ": " + problem;
}

}  // namespace

SceneError::SceneError(std::string file, std::string field, std::string problem)
    : SceneError(file, field, problem, compose(file, field, problem)) {}

SceneError::SceneError(std::string file, std::string field, std::string problem,
                       std::string message)
    : std::runtime_error(std::move(message)),
      file_(std::move(file)),
      field_(std::move(field)),
      problem_(std::move(problem)) {}

SceneError SceneError::from_spec_error(std::string file, const std::string& path_prefix,
                                       const SpecError& error) {
  const std::string prefix = path_prefix.empty() ? "" : path_prefix + ".";
  std::string message = file + ": " + prefix + error.what();
  return SceneError(std::move(file), prefix + error.field(), error.value() + ": " + error.bound(),
                    std::move(message));
}

}  // namespace soltex
