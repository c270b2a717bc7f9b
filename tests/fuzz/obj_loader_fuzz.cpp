// libFuzzer target for the Wavefront OBJ parser (parse_obj). Every input either throws ObjError
// or gives a mesh that keeps mesh_checks.h's promises, load statistics that add up, and — once
// normalized as scenes do — bounds inside [-1, 1].
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "mesh_checks.h"
#include "soltex/scene/obj_loader.h"

namespace {

using soltex::fuzz::check_mesh;
using soltex::fuzz::fail;

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
  fuzz_obj(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
