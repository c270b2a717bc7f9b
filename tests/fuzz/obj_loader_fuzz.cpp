// libFuzzer target for the Wavefront OBJ parser (parse_obj). Every input either throws ObjError
// or gives a mesh that keeps mesh_checks.h's promises, load statistics that add up, and — once
// normalized as scenes do — bounds inside [-1, 1]. The file's coordinates are read in double
// and normalized there, so the input is also loaded as scenes load it ({.normalize = true}),
// which must keep the same promises.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "mesh_checks.h"
#include "soltex/scene/obj_loader.h"

namespace {

using soltex::fuzz::check_mesh;
using soltex::fuzz::fail;

void check_unit_bounds(const soltex::Mesh& mesh, const char* what) {
  constexpr float kUnitSlack = 1e-5f;
  for (int axis = 0; axis < 3; ++axis) {
    if (mesh.bounds.min[axis] < -1.0f - kUnitSlack || mesh.bounds.max[axis] > 1.0f + kUnitSlack) {
      fail(std::string(what) + ": normalized bounds outside [-1, 1]");
    }
  }
}

void check_stats(const soltex::LoadedObj& loaded, const char* what) {
  const soltex::ObjLoadStats& stats = loaded.stats;
  if (stats.vertices_read - stats.duplicate_vertices_merged - stats.unreferenced_vertices_removed +
          stats.vertices_split_at_creases !=
      loaded.mesh.vertex_count()) {
    fail(std::string(what) + ": the load statistics do not add up to the vertices kept");
  }
}

// As scenes load OBJ files: normalized in double before the positions become float.
void fuzz_normalized(std::string_view text) {
  soltex::LoadedObj loaded;
  try {
    loaded = soltex::parse_obj(text, "fuzz.obj", {.normalize = true});
  } catch (const soltex::ObjError&) {
    return;
  }
  check_mesh(loaded.mesh, "fuzz.obj loaded normalized");
  check_stats(loaded, "fuzz.obj loaded normalized");
  check_unit_bounds(loaded.mesh, "fuzz.obj loaded normalized");
}

void fuzz_obj(std::string_view text) {
  fuzz_normalized(text);
  soltex::LoadedObj loaded;
  try {
    loaded = soltex::parse_obj(text, "fuzz.obj");
  } catch (const soltex::ObjError&) {
    return;
  }
  check_mesh(loaded.mesh, "fuzz.obj");
  check_stats(loaded, "fuzz.obj");
  // What parse_obj does with {.normalize = true}: the longest side then spans [-1, 1].
  soltex::normalize_to_unit_box(loaded.mesh);
  check_mesh(loaded.mesh, "fuzz.obj normalized");
  check_unit_bounds(loaded.mesh, "fuzz.obj normalized");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  fuzz_obj(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
