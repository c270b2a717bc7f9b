#include "mesh_cleanup.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <glm/geometric.hpp>
#include <utility>
#include <vector>

namespace soltex {
namespace {

// A hash of a face's corners as a set (FNV-1a over them sorted): the same for every order.
uint64_t corner_set_hash(std::span<const uint32_t> face) {
  // Most faces are triangles and quads: sorted on the stack, no allocation per face.
  std::array<uint32_t, 8> small;
  std::vector<uint32_t> large;
  std::span<uint32_t> sorted;
  if (face.size() <= small.size()) {
    sorted = std::span(small).first(face.size());
  } else {
    large.resize(face.size());
    sorted = large;
  }
  std::copy(face.begin(), face.end(), sorted.begin());
  std::sort(sorted.begin(), sorted.end());
  uint64_t hash = 1469598103934665603ull;
  for (uint32_t corner : sorted) hash = (hash ^ corner) * 1099511628211ull;
  return hash;
}

bool same_corner_set(std::span<const uint32_t> a, std::span<const uint32_t> b) {
  return a.size() == b.size() && std::is_permutation(a.begin(), a.end(), b.begin());
}

// Whether two faces over the same corners run the same way round: b continues from a's first
// corner to a's second.
bool same_winding(std::span<const uint32_t> a, std::span<const uint32_t> b) {
  const std::size_t n = a.size();
  const std::size_t at = static_cast<std::size_t>(std::find(b.begin(), b.end(), a[0]) - b.begin());
  return b[(at + 1) % n] == a[1];
}

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

// The repeats among `count` faces, `face(f)` giving face f's corners.
template <class Face>
RepeatedFaces find_repeats(std::size_t count, const Face& face) {
  // Faces ordered by a hash of their sorted corners, so that repeats lie side by side; equal
  // hashes are compared in full.
  std::vector<std::pair<uint64_t, uint32_t>> keyed(count);
  for (std::size_t f = 0; f < count; ++f) {
    keyed[f] = {corner_set_hash(face(f)), static_cast<uint32_t>(f)};
  }
  std::sort(keyed.begin(), keyed.end());
  RepeatedFaces found;
  found.repeated.assign(count, false);
  std::vector<uint32_t> kept;  // the distinct faces of one run of equal hashes, first first
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first) kept.clear();
    const auto later = face(keyed[i].second);
    const auto same = std::find_if(kept.begin(), kept.end(),
                                   [&](uint32_t f) { return same_corner_set(face(f), later); });
    if (same == kept.end()) {
      kept.push_back(keyed[i].second);
      continue;
    }
    found.repeated[keyed[i].second] = true;
    ++found.count;
    found.reversed += same_winding(face(*same), later) ? 0 : 1;
  }
  return found;
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

namespace {

// `v` times the power of two that brings its largest component into [0.5, 1): exact, and the
// same direction, so that an edge's cross product neither underflows (a mesh 1e-165 across)
// nor overflows; zero stays zero.
glm::dvec3 scaled_to_unit(const glm::dvec3& v) {
  const double largest = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  if (!(largest > 0.0) || !std::isfinite(largest)) return v;
  int exponent = 0;
  std::frexp(largest, &exponent);
  return {std::ldexp(v.x, -exponent), std::ldexp(v.y, -exponent), std::ldexp(v.z, -exponent)};
}

}  // namespace

template <class Position>
std::size_t drop_degenerate_triangles(const std::vector<Position>& positions,
                                      std::vector<uint32_t>& indices) {
  std::size_t kept = 0;
  const std::size_t count = indices.size() / 3;
  for (std::size_t t = 0; t < count; ++t) {
    const uint32_t a = indices[3 * t], b = indices[3 * t + 1], c = indices[3 * t + 2];
    if (a == b || b == c || a == c) continue;
    const glm::dvec3 pa(positions[a]), pb(positions[b]), pc(positions[c]);
    if (glm::cross(scaled_to_unit(pb - pa), scaled_to_unit(pc - pa)) == glm::dvec3(0.0)) continue;
    indices[3 * kept] = a;
    indices[3 * kept + 1] = b;
    indices[3 * kept + 2] = c;
    ++kept;
  }
  indices.resize(3 * kept);
  return count - kept;
}

RepeatedFaces find_repeated_polygons(std::span<const uint32_t> corners,
                                     std::span<const uint32_t> sizes) {
  std::vector<std::size_t> starts(sizes.size());
  for (std::size_t f = 0, at = 0; f < sizes.size(); at += sizes[f], ++f) starts[f] = at;
  return find_repeats(sizes.size(),
                      [&](std::size_t f) { return corners.subspan(starts[f], sizes[f]); });
}

RepeatedFaces drop_duplicate_triangles(std::vector<uint32_t>& indices) {
  const std::span<const uint32_t> all(indices);
  const std::size_t count = indices.size() / 3;
  RepeatedFaces found = find_repeats(count, [&](std::size_t t) { return all.subspan(3 * t, 3); });
  std::size_t kept = 0;
  for (std::size_t t = 0; t < count; ++t) {
    if (found.repeated[t]) continue;
    for (int k = 0; k < 3; ++k) indices[3 * kept + k] = indices[3 * t + k];
    ++kept;
  }
  indices.resize(3 * kept);
  return found;
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
