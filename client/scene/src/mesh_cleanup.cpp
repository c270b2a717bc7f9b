#include "mesh_cleanup.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <bit>
#include <glm/geometric.hpp>
#include <utility>
#include <vector>

namespace soltex {
namespace {

// A position's coordinates as integers of the same width: float -> uint32, double -> uint64.
template <class Position>
using Bits =
    std::array<std::conditional_t<sizeof(typename Position::value_type) == 4, uint32_t, uint64_t>,
               3>;

template <class Position>
Bits<Position> bits_of(const Position& p) {
  using Word = typename Bits<Position>::value_type;
  using Scalar = typename Position::value_type;
  // + 0 folds -0 into +0; the two are the same point.
  return {std::bit_cast<Word>(static_cast<Scalar>(p.x + Scalar(0))),
          std::bit_cast<Word>(static_cast<Scalar>(p.y + Scalar(0))),
          std::bit_cast<Word>(static_cast<Scalar>(p.z + Scalar(0)))};
}

// Moves vertex i to new_index_of[i] (~0u: dropped) and renumbers the indices.
template <class Position>
void compact_vertices(std::vector<Position>& positions, std::vector<uint32_t>& indices,
                      const std::vector<uint32_t>& new_index_of, std::size_t new_count) {
  std::vector<Position> kept(new_count);
  meshopt_remapVertexBuffer(kept.data(), positions.data(), positions.size(), sizeof(Position),
                            new_index_of.data());
  meshopt_remapIndexBuffer(indices.data(), indices.data(), indices.size(), new_index_of.data());
  positions = std::move(kept);
}

}  // namespace

template <class Position>
std::size_t merge_duplicate_vertices(std::vector<Position>& positions,
                                     std::vector<uint32_t>& indices) {
  // meshoptimizer compares vertices byte for byte; the bits with -0 folded into +0 make equal
  // positions equal bytes. Without indices it numbers vertices by first appearance, so the
  // first of each set of duplicates keeps its place.
  std::vector<Bits<Position>> bits;
  bits.reserve(positions.size());
  for (const Position& p : positions) bits.push_back(bits_of(p));
  std::vector<uint32_t> new_index_of(positions.size());
  const std::size_t kept = meshopt_generateVertexRemap(new_index_of.data(), nullptr, bits.size(),
                                                       bits.data(), bits.size(), sizeof(bits[0]));
  const std::size_t merged = positions.size() - kept;
  if (merged > 0) compact_vertices(positions, indices, new_index_of, kept);
  return merged;
}

template <class Position>
std::size_t drop_degenerate_triangles(const std::vector<Position>& positions,
                                      std::vector<uint32_t>& indices) {
  std::size_t kept = 0;
  const std::size_t count = indices.size() / 3;
  for (std::size_t t = 0; t < count; ++t) {
    const uint32_t a = indices[3 * t], b = indices[3 * t + 1], c = indices[3 * t + 2];
    if (a == b || b == c || a == c) continue;
    const glm::dvec3 pa(positions[a]), pb(positions[b]), pc(positions[c]);
    if (glm::cross(pb - pa, pc - pa) == glm::dvec3(0.0)) continue;
    indices[3 * kept] = a;
    indices[3 * kept + 1] = b;
    indices[3 * kept + 2] = c;
    ++kept;
  }
  indices.resize(3 * kept);
  return count - kept;
}

std::size_t drop_duplicate_triangles(std::vector<uint32_t>& indices) {
  using Corners = std::array<uint32_t, 3>;
  const std::size_t count = indices.size() / 3;
  std::vector<std::pair<Corners, uint32_t>> sorted(count);
  for (std::size_t t = 0; t < count; ++t) {
    Corners corners{indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
    std::sort(corners.begin(), corners.end());
    sorted[t] = {corners, static_cast<uint32_t>(t)};
  }
  std::sort(sorted.begin(), sorted.end());
  std::vector<bool> dropped(count, false);
  for (std::size_t i = 1; i < count; ++i) {
    if (sorted[i].first == sorted[i - 1].first) dropped[sorted[i].second] = true;
  }
  std::size_t kept = 0;
  for (std::size_t t = 0; t < count; ++t) {
    if (dropped[t]) continue;
    for (int k = 0; k < 3; ++k) indices[3 * kept + k] = indices[3 * t + k];
    ++kept;
  }
  indices.resize(3 * kept);
  return count - kept;
}

template <class Position>
std::size_t remove_unreferenced_vertices(std::vector<Position>& positions,
                                         std::vector<uint32_t>& indices) {
  std::vector<uint32_t> new_index_of(positions.size(), ~0u);
  for (uint32_t index : indices) new_index_of[index] = 0;
  uint32_t next = 0;
  for (uint32_t& to : new_index_of) {
    if (to == 0) to = next++;
  }
  const std::size_t removed = positions.size() - next;
  if (removed > 0) compact_vertices(positions, indices, new_index_of, next);
  return removed;
}

template std::size_t merge_duplicate_vertices(std::vector<glm::vec3>&, std::vector<uint32_t>&);
template std::size_t merge_duplicate_vertices(std::vector<glm::dvec3>&, std::vector<uint32_t>&);
template std::size_t drop_degenerate_triangles(const std::vector<glm::vec3>&,
                                               std::vector<uint32_t>&);
template std::size_t drop_degenerate_triangles(const std::vector<glm::dvec3>&,
                                               std::vector<uint32_t>&);
template std::size_t remove_unreferenced_vertices(std::vector<glm::vec3>&, std::vector<uint32_t>&);
template std::size_t remove_unreferenced_vertices(std::vector<glm::dvec3>&, std::vector<uint32_t>&);

}  // namespace soltex
