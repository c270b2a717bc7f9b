#include "soltex/scene/mesh_order.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace soltex {
namespace {

constexpr uint32_t kUnused = ~0u;  // meshoptimizer's mark for a vertex no triangle uses

// Positions as meshoptimizer reads them, every coordinate finite and small enough that sums of
// three stay finite: it turns centroids into Morton codes with a float-to-int conversion, which
// is undefined for NaN and infinity. NaN counts as the lowest coordinate on its axis, so its
// triangles sort to the start of that axis; the positions themselves are not changed.
std::vector<float> sortable_positions(const std::vector<glm::vec3>& positions) {
  constexpr float kLargest = 1e37f;
  std::vector<float> xyz;
  xyz.reserve(3 * positions.size());
  glm::vec3 low(kLargest);
  for (const glm::vec3& p : positions) {
    for (int axis = 0; axis < 3; ++axis) {
      const float v = std::clamp(p[axis], -kLargest, kLargest);  // NaN stays NaN
      xyz.push_back(v);
      if (v < low[axis]) low[axis] = v;
    }
  }
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    if (std::isnan(xyz[i])) xyz[i] = low[static_cast<int>(i % 3)];
  }
  return xyz;
}

// `values` moved so that old vertex v lands at remap[v] (a permutation).
template <class T>
void apply_remap(std::vector<T>& values, const std::vector<uint32_t>& remap) {
  std::vector<T> moved(values.size());
  meshopt_remapVertexBuffer(moved.data(), values.data(), values.size(), sizeof(T), remap.data());
  values = std::move(moved);
}

}  // namespace

void order_for_locality(Mesh& mesh) {
  const std::size_t triangles = mesh.triangle_count();
  const std::size_t vertices = mesh.positions.size();
  // Fewer than two triangles have no order to improve; a ragged index list is left for the
  // rasterizer to refuse as it is.
  if (triangles < 2 || mesh.indices.size() % 3 != 0) return;

  // meshoptimizer reads every index as a vertex, so a triangle with an index out of range
  // stays out of its hands: such triangles follow the others, unchanged, for the rasterizer to
  // refuse.
  std::vector<uint32_t> drawable, broken;
  drawable.reserve(mesh.indices.size());
  for (std::size_t t = 0; t < triangles; ++t) {
    const uint32_t* corner = &mesh.indices[3 * t];
    const bool in_range = corner[0] < vertices && corner[1] < vertices && corner[2] < vertices;
    (in_range ? drawable : broken).insert((in_range ? drawable : broken).end(), corner, corner + 3);
  }

  // Triangles along the Morton curve of their centroids (a stable radix sort: triangles in one
  // cell keep their order), each keeping its own corner order, so its winding.
  const std::vector<float> xyz = sortable_positions(mesh.positions);
  std::vector<uint32_t> indices(drawable.size());
  meshopt_spatialSortTriangles(indices.data(), drawable.data(), drawable.size(), xyz.data(),
                               vertices, 3 * sizeof(float));

  // Vertices numbered by first use; those no drawable triangle uses follow in their old order,
  // so the vertex count and the bounds stay as they were.
  std::vector<uint32_t> remap(vertices);
  uint32_t next = static_cast<uint32_t>(
      meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), indices.size(), vertices));
  for (uint32_t& to : remap) {
    if (to == kUnused) to = next++;
  }
  meshopt_remapIndexBuffer(indices.data(), indices.data(), indices.size(), remap.data());
  indices.insert(indices.end(), broken.begin(), broken.end());
  apply_remap(mesh.positions, remap);
  if (mesh.normals.size() == vertices) apply_remap(mesh.normals, remap);
  mesh.indices = std::move(indices);
}

}  // namespace soltex
