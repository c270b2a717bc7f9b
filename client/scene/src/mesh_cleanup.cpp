#include "mesh_cleanup.h"

#include <array>
#include <bit>
#include <cstdint>
#include <glm/geometric.hpp>
#include <unordered_map>

namespace soltex {
namespace {

using PositionBits = std::array<uint32_t, 3>;

struct PositionBitsHash {
  std::size_t operator()(const PositionBits& bits) const {
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (uint32_t b : bits) h = (h ^ b) * 0xBF58476D1CE4E5B9ull;
    return static_cast<std::size_t>(h ^ (h >> 31));
  }
};

PositionBits bits_of(const glm::vec3& p) {
  // + 0.0f folds -0 into +0; the two are the same point.
  return {std::bit_cast<uint32_t>(p.x + 0.0f), std::bit_cast<uint32_t>(p.y + 0.0f),
          std::bit_cast<uint32_t>(p.z + 0.0f)};
}

// Moves vertex i to new_index_of[i] (UINT32_MAX: dropped) and renumbers the indices.
void compact_vertices(Mesh& mesh, const std::vector<uint32_t>& new_index_of,
                      std::size_t new_count) {
  std::vector<glm::vec3> positions(new_count);
  std::vector<glm::vec3> normals(mesh.normals.empty() ? 0 : new_count);
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const uint32_t to = new_index_of[i];
    if (to == UINT32_MAX) continue;
    positions[to] = mesh.positions[i];
    if (!normals.empty()) normals[to] = mesh.normals[i];
  }
  for (uint32_t& index : mesh.indices) index = new_index_of[index];
  mesh.positions = std::move(positions);
  mesh.normals = std::move(normals);
}

}  // namespace

std::size_t merge_duplicate_vertices(Mesh& mesh) {
  std::unordered_map<PositionBits, uint32_t, PositionBitsHash> first_with_position;
  first_with_position.reserve(mesh.positions.size());
  std::vector<uint32_t> new_index_of(mesh.positions.size());
  std::vector<uint32_t> kept_index;  // new index -> first old index with that position
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto [it, inserted] = first_with_position.try_emplace(
        bits_of(mesh.positions[i]), static_cast<uint32_t>(kept_index.size()));
    if (inserted) kept_index.push_back(static_cast<uint32_t>(i));
    new_index_of[i] = it->second;
  }
  const std::size_t merged = mesh.positions.size() - kept_index.size();
  if (merged > 0) compact_vertices(mesh, new_index_of, kept_index.size());
  return merged;
}

std::size_t drop_degenerate_triangles(Mesh& mesh) {
  std::size_t kept = 0;
  const std::size_t count = mesh.triangle_count();
  for (std::size_t t = 0; t < count; ++t) {
    const uint32_t a = mesh.indices[3 * t], b = mesh.indices[3 * t + 1],
                   c = mesh.indices[3 * t + 2];
    if (a == b || b == c || a == c) continue;
    const glm::dvec3 pa(mesh.positions[a]), pb(mesh.positions[b]), pc(mesh.positions[c]);
    if (glm::cross(pb - pa, pc - pa) == glm::dvec3(0.0)) continue;
    mesh.indices[3 * kept] = a;
    mesh.indices[3 * kept + 1] = b;
    mesh.indices[3 * kept + 2] = c;
    ++kept;
  }
  mesh.indices.resize(3 * kept);
  return count - kept;
}

std::size_t remove_unreferenced_vertices(Mesh& mesh) {
  std::vector<uint32_t> new_index_of(mesh.positions.size(), UINT32_MAX);
  for (uint32_t index : mesh.indices) new_index_of[index] = 0;
  uint32_t next = 0;
  for (uint32_t& to : new_index_of) {
    if (to == 0) to = next++;
  }
  const std::size_t removed = mesh.positions.size() - next;
  if (removed > 0) compact_vertices(mesh, new_index_of, next);
  return removed;
}

}  // namespace soltex
