#include "soltex/scene/mesh_order.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

namespace soltex {
namespace {

// 1024 cells per axis: a cell per triangle or finer up to about 10^9 triangles; triangles
// sharing a cell keep their file order.
constexpr int kBitsPerAxis = 10;

// 0 .. 2^kBitsPerAxis - 1 for `value` across [low, low + extent]; 0 for NaN or a flat axis.
uint32_t cell_of(float value, float low, float extent) {
  constexpr float kCells = static_cast<float>(1u << kBitsPerAxis);
  const float t = extent > 0.0f ? (value - low) / extent * kCells : 0.0f;
  if (!(t > 0.0f)) return 0;  // also NaN
  return static_cast<uint32_t>(std::min(t, kCells - 1.0f));
}

// The bits of `v` (kBitsPerAxis of them) spread to every third bit.
uint32_t spread_bits(uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

}  // namespace

void order_for_locality(Mesh& mesh) {
  const std::size_t triangles = mesh.triangle_count();
  const std::size_t vertices = mesh.positions.size();
  // Fewer than two triangles have no order to improve; a ragged index list is left for the
  // rasterizer to refuse as it is.
  if (triangles < 2 || mesh.indices.size() % 3 != 0) return;
  const BoundingBox box = bounds_of(mesh.positions);
  const glm::vec3 extent = box.size();

  std::vector<uint32_t> code(triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    glm::vec3 centroid(0.0f);
    for (std::size_t k = 0; k < 3; ++k) {
      const uint32_t index = mesh.indices[3 * t + k];
      if (index < vertices) centroid += mesh.positions[index] / 3.0f;
    }
    code[t] = spread_bits(cell_of(centroid.x, box.min.x, extent.x)) |
              spread_bits(cell_of(centroid.y, box.min.y, extent.y)) << 1 |
              spread_bits(cell_of(centroid.z, box.min.z, extent.z)) << 2;
  }
  std::vector<uint32_t> order(triangles);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&code](uint32_t a, uint32_t b) { return code[a] < code[b]; });

  // New number of each old vertex, in the order the sorted triangles first use them.
  constexpr uint32_t kUnset = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> renumber(vertices, kUnset);
  std::vector<uint32_t> old_of_new;
  old_of_new.reserve(vertices);
  std::vector<uint32_t> indices;
  indices.reserve(mesh.indices.size());
  for (const uint32_t t : order) {
    for (std::size_t k = 0; k < 3; ++k) {
      const uint32_t index = mesh.indices[3 * t + k];
      if (index >= vertices) {
        indices.push_back(index);  // out of range stays out of range: the rasterizer rejects it
        continue;
      }
      if (renumber[index] == kUnset) {
        renumber[index] = static_cast<uint32_t>(old_of_new.size());
        old_of_new.push_back(index);
      }
      indices.push_back(renumber[index]);
    }
  }
  for (std::size_t v = 0; v < vertices; ++v) {
    if (renumber[v] == kUnset) old_of_new.push_back(static_cast<uint32_t>(v));
  }
  const bool has_normals = mesh.normals.size() == vertices;
  std::vector<glm::vec3> positions(vertices), normals(has_normals ? vertices : 0);
  for (std::size_t n = 0; n < vertices; ++n) {
    positions[n] = mesh.positions[old_of_new[n]];
    if (has_normals) normals[n] = mesh.normals[old_of_new[n]];
  }
  mesh.positions = std::move(positions);
  if (has_normals) mesh.normals = std::move(normals);
  mesh.indices = std::move(indices);
}

}  // namespace soltex
