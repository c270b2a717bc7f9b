// libFuzzer target for scene files (parse_scene). Every input either throws SceneError or
// ObjError, or gives what the loader promises: meshes with one finite unit normal per position,
// indices in range and bounds that hold every position, a texture spec that reads back from its
// own JSON, a finite transform and a valid default cache volume for every object ("a scene
// that loads is ready to draw"). obj_loader_fuzz covers the OBJ parser on its own.
//
// Relative OBJ paths in a scene resolve against SOLTEX_FUZZ_OBJ_DIR, which the seed writer
// fills with small OBJ files.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "mesh_checks.h"
#include "soltex/common/spec_error.h"
#include "soltex/scene/mesh.h"
#include "soltex/scene/obj_loader.h"
#include "soltex/scene/scene_error.h"
#include "soltex/scene/scene_loader.h"
#include "soltex/scene/texture_spec_json.h"
#include "soltex/scene/texture_volume.h"

namespace {

using soltex::fuzz::check_mesh;
using soltex::fuzz::fail;

void check_object(const soltex::SceneObject& object, const std::string& scene_name) {
  const std::string what = scene_name + " object \"" + object.name + "\"";
  if (!object.mesh) fail(what + ": no mesh");
  check_mesh(*object.mesh, what);

  const glm::dmat4 matrix = object.transform.matrix();
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) {
      if (!std::isfinite(matrix[column][row])) fail(what + ": the transform is not finite");
    }
  }

  // texture_spec_to_json writes every field, and reading that gives the same spec.
  const nlohmann::json json = soltex::texture_spec_to_json(object.material.texture);
  const soltex::TextureSpec again = soltex::texture_spec_from_json(json, "<round trip>", "texture");
  if (soltex::texture_spec_to_json(again) != json) {
    fail(what + ": the texture spec changed across a JSON round trip: " + json.dump());
  }

  // What the renderer asks for every object it prepares.
  for (int client_level : {0, 8, soltex::SpecLimits::kMaxFinestLevelLog2}) {
    try {
      (void)soltex::texture_volume(object, client_level);
    } catch (const soltex::SpecError& error) {
      fail(what + ": the scene loaded but its texture volume is invalid: " + error.what());
    }
  }
}

void fuzz_scene(std::string_view text) {
  soltex::Scene scene;
  try {
    scene = soltex::parse_scene(text, "fuzz", SOLTEX_FUZZ_OBJ_DIR);
  } catch (const soltex::SceneError&) {
    return;
  } catch (const soltex::ObjError&) {
    return;
  }
  if (scene.objects.empty()) fail("a scene without objects loaded");
  for (const soltex::SceneObject& object : scene.objects) check_object(object, scene.name);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  fuzz_scene(text);
  return 0;
}
