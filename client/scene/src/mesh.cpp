#include "soltex/scene/mesh.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace soltex {

void compute_vertex_normals(Mesh& mesh) {
  // Sums in double: a vertex of a dense scan has many small triangles around it.
  std::vector<glm::dvec3> sums(mesh.positions.size(), glm::dvec3(0.0));
  std::vector<glm::dvec3> fallbacks(mesh.positions.size(), glm::dvec3(0.0));
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t ia = mesh.indices[t], ib = mesh.indices[t + 1], ic = mesh.indices[t + 2];
    const glm::dvec3 a(mesh.positions[ia]), b(mesh.positions[ib]), c(mesh.positions[ic]);
    const glm::dvec3 area_weighted = glm::cross(b - a, c - a);  // |.| = twice the area
    for (uint32_t i : {ia, ib, ic}) {
      sums[i] += area_weighted;
      if (fallbacks[i] == glm::dvec3(0.0)) fallbacks[i] = area_weighted;
    }
  }
  mesh.normals.resize(mesh.positions.size());
  for (std::size_t i = 0; i < sums.size(); ++i) {
    glm::dvec3 n = sums[i];
    if (!(glm::length(n) > 0.0)) n = fallbacks[i];
    mesh.normals[i] = glm::length(n) > 0.0 ? glm::vec3(glm::normalize(n)) : glm::vec3(0, 0, 1);
  }
}

void normalize_to_unit_box(Mesh& mesh) {
  mesh.update_bounds();
  if (mesh.bounds.empty()) return;
  const glm::dvec3 centre = 0.5 * (glm::dvec3(mesh.bounds.min) + glm::dvec3(mesh.bounds.max));
  const glm::dvec3 size = glm::dvec3(mesh.bounds.max) - glm::dvec3(mesh.bounds.min);
  const double longest = std::max({size.x, size.y, size.z});
  const double scale = longest > 0.0 ? 2.0 / longest : 1.0;
  for (glm::vec3& p : mesh.positions) p = glm::vec3((glm::dvec3(p) - centre) * scale);
  mesh.update_bounds();
}

}  // namespace soltex
