// libFuzzer target for the client's text formats. Every input is parsed both as a scene file
// (parse_scene) and as a Wavefront OBJ file (parse_obj). Each either throws SceneError or
// ObjError, or gives what the loaders promise: meshes with one finite unit normal per position,
// indices in range and bounds that hold every position; in a scene also a texture spec that
// reads back from its own JSON, a finite transform and a valid default cache volume for every
// object ("a scene that loads is ready to draw").
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

#include "soltex/common/spec_error.h"
#include "soltex/scene/mesh.h"
#include "soltex/scene/obj_loader.h"
#include "soltex/scene/scene_error.h"
#include "soltex/scene/scene_loader.h"
#include "soltex/scene/texture_spec_json.h"
#include "soltex/scene/texture_volume.h"

namespace {

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "scene_parser_fuzz: %s\n", what.c_str());
  std::abort();
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void check_mesh(const soltex::Mesh& mesh, const std::string& what) {
  if (mesh.normals.size() != mesh.positions.size()) fail(what + ": not one normal per position");
  if (mesh.indices.size() % 3 != 0 || mesh.triangle_count() == 0) {
    fail(what + ": no triangles, or indices not a multiple of three");
  }
  for (uint32_t index : mesh.indices) {
    if (index >= mesh.positions.size()) fail(what + ": an index past the last position");
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const glm::vec3& p = mesh.positions[i];
    const glm::vec3& n = mesh.normals[i];
    if (!finite(p)) fail(what + ": a position is not finite");
    if (!finite(n) || std::abs(glm::length(n) - 1.0f) > 1e-3f) {
      fail(what + ": a normal is not of unit length");
    }
    for (int axis = 0; axis < 3; ++axis) {
      if (!(p[axis] >= mesh.bounds.min[axis] && p[axis] <= mesh.bounds.max[axis])) {
        fail(what + ": a position outside the mesh bounds");
      }
    }
  }
}

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

void fuzz_obj(std::string_view text) {
  soltex::LoadedObj loaded;
  try {
    loaded = soltex::parse_obj(text, "fuzz.obj");
  } catch (const soltex::ObjError&) {
    return;
  }
  check_mesh(loaded.mesh, "fuzz.obj");
  const soltex::ObjLoadStats& stats = loaded.stats;
  if (stats.vertices_read - stats.duplicate_vertices_merged - stats.unreferenced_vertices_removed !=
      loaded.mesh.vertex_count()) {
    fail("fuzz.obj: the load statistics do not add up to the vertices kept");
  }
  // What parse_obj does with {.normalize = true}: the longest side then spans [-1, 1].
  soltex::normalize_to_unit_box(loaded.mesh);
  check_mesh(loaded.mesh, "fuzz.obj normalized");
  constexpr float kUnitSlack = 1e-5f;
  for (int axis = 0; axis < 3; ++axis) {
    if (loaded.mesh.bounds.min[axis] < -1.0f - kUnitSlack ||
        loaded.mesh.bounds.max[axis] > 1.0f + kUnitSlack) {
      fail("fuzz.obj: normalized bounds outside [-1, 1]");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  fuzz_scene(text);
  fuzz_obj(text);
  return 0;
}
