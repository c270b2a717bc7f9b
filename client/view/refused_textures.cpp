#include "refused_textures.h"

#include <spdlog/spdlog.h>

#include <string>

namespace soltex::view {
namespace {

void warn_of_refused_texture(const PreparedScene& prepared, std::size_t i) {
  const PreparedObject& o = prepared.objects[i];
  spdlog::warn("objects[{}] \"{}\": {}; its texture is evaluated per pixel here instead", i,
               o.object != nullptr ? o.object->name : std::string(), o.refusal);
}

}  // namespace

void warn_of_refused_textures(const PreparedScene& prepared) {
  for (std::size_t i = 0; i < prepared.objects.size(); ++i) {
    if (prepared.objects[i].evaluated_here) warn_of_refused_texture(prepared, i);
  }
}

void adopt_refused_textures(PreparedScene& prepared, net::BrickSource& source) {
  for (const std::size_t i : evaluate_refused_textures(prepared, source)) {
    warn_of_refused_texture(prepared, i);
  }
}

}  // namespace soltex::view
