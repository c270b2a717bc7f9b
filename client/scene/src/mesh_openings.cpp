#include "soltex/scene/mesh_openings.h"

#include <algorithm>
#include <cstdint>
#include <glm/geometric.hpp>
#include <utility>
#include <vector>

#include "mesh_cleanup.h"
#include "soltex/common/check.h"

namespace soltex {
namespace {

struct DirectedEdge {
  uint32_t from;
  uint32_t to;
};

// Each edge's faces, counted +1 along the edge's lower-to-higher vertex order and -1 against
// it: a nonzero sum is that many open sides, in the sum's direction.
std::vector<DirectedEdge> open_edges(const std::vector<uint32_t>& indices) {
  std::vector<std::pair<uint64_t, int>> sides;
  sides.reserve(indices.size());
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = indices[t + k], b = indices[t + (k + 1) % 3];
      if (a == b) continue;
      const uint64_t key = (uint64_t{std::min(a, b)} << 32) | std::max(a, b);
      sides.emplace_back(key, a < b ? 1 : -1);
    }
  }
  std::sort(sides.begin(), sides.end());
  std::vector<DirectedEdge> open;
  for (std::size_t i = 0; i < sides.size();) {
    const uint64_t key = sides[i].first;
    int sum = 0;
    for (; i < sides.size() && sides[i].first == key; ++i) sum += sides[i].second;
    const uint32_t low = static_cast<uint32_t>(key >> 32), high = static_cast<uint32_t>(key);
    for (int n = 0; n < std::abs(sum); ++n) {
      open.push_back(sum > 0 ? DirectedEdge{low, high} : DirectedEdge{high, low});
    }
  }
  return open;
}

// Follows the open edges head to tail into loops and sums the area each spans. An edge chain
// that does not come back to its start (a non-manifold boundary) is closed by a straight
// segment. The edges are sorted by their start, so a vertex's unwalked ones are a range.
double loops_area(const std::vector<glm::vec3>& positions, std::vector<DirectedEdge> open) {
  std::sort(open.begin(), open.end(),
            [](const DirectedEdge& a, const DirectedEdge& b) { return a.from < b.from; });
  const auto first_from = [&](uint32_t vertex) {
    return static_cast<std::size_t>(
        std::lower_bound(open.begin(), open.end(), vertex,
                         [](const DirectedEdge& e, uint32_t v) { return e.from < v; }) -
        open.begin());
  };
  // A vertex's edges are walked from the front of its range: `taken`, kept at the range's
  // first edge, counts those gone.
  std::vector<bool> walked(open.size(), false);
  std::vector<uint32_t> taken(open.size(), 0);
  const auto next_from = [&](uint32_t vertex) -> std::size_t {
    const std::size_t range = first_from(vertex);
    const std::size_t at = range + (range < open.size() ? taken[range] : 0);
    if (at >= open.size() || open[at].from != vertex) return open.size();
    ++taken[range];
    return at;
  };
  double area = 0.0;
  for (std::size_t start = 0; start < open.size(); ++start) {
    if (walked[start]) continue;
    ++taken[first_from(open[start].from)];  // all before it in its range are walked
    const uint32_t first = open[start].from;
    const glm::dvec3 origin(positions[first]);
    glm::dvec3 twice_area(0.0);
    for (std::size_t e = start; e < open.size(); e = next_from(open[e].to)) {
      walked[e] = true;
      twice_area += glm::cross(glm::dvec3(positions[open[e].from]) - origin,
                               glm::dvec3(positions[open[e].to]) - origin);
      if (open[e].to == first) break;
    }
    area += 0.5 * glm::length(twice_area);
  }
  return area;
}

}  // namespace

double opening_fraction(const Mesh& mesh) {
  std::vector<glm::vec3> positions = mesh.positions;
  std::vector<uint32_t> indices = mesh.indices;
  merge_duplicate_vertices(positions, indices);
  double surface = 0.0;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
    const glm::dvec3 a(positions[indices[t]]);
    surface += 0.5 * glm::length(glm::cross(glm::dvec3(positions[indices[t + 1]]) - a,
                                            glm::dvec3(positions[indices[t + 2]]) - a));
  }
  std::vector<DirectedEdge> open = open_edges(indices);
  if (open.empty()) return 0.0;
  if (!(surface > 0.0)) return 1.0;
  const double fraction = loops_area(positions, std::move(open)) / surface;
  SOLTEX_DCHECK(fraction >= 0.0);
  return fraction;
}

}  // namespace soltex
