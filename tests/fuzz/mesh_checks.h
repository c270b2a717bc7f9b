#pragma once
// What every loaded mesh promises, checked by the fuzz targets that load meshes: one finite
// unit normal per position, whole triangles, indices in range, bounds that hold every position.

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <string>

#include "soltex/scene/mesh.h"

namespace soltex::fuzz {

[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz: %s\n", what.c_str());
  std::abort();
}

inline bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

inline void check_mesh(const soltex::Mesh& mesh, const std::string& what) {
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

}  // namespace soltex::fuzz
