#include "polygon_triangulation.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/vec2.hpp>

namespace soltex {
namespace {

double cross2(const glm::dvec2& a, const glm::dvec2& b) {
  return a.x * b.y - a.y * b.x;
}

// Whether p lies in or on the counter-clockwise triangle abc.
bool in_triangle(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b,
                 const glm::dvec2& c) {
  return cross2(b - a, p - a) >= 0.0 && cross2(c - b, p - b) >= 0.0 && cross2(a - c, p - c) >= 0.0;
}

void fan(std::span<const uint32_t> polygon, std::vector<uint32_t>& triangles) {
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
    triangles.insert(triangles.end(), {polygon[0], polygon[i], polygon[i + 1]});
  }
}

// Ear clipping on a doubly linked ring of a counter-clockwise 2D polygon. An ear is a
// strictly convex corner whose triangle holds no other vertex; only reflex (or flat)
// vertices can be inside it, so only those are tested, and they are kept in a uniform grid
// so that a test mostly looks at the few near the triangle. A star of 65536 vertices takes
// milliseconds; a comb, whose ears are long and thin, stays quadratic (0.15 s at 16384).
class EarClipper {
 public:
  explicit EarClipper(std::vector<glm::dvec2> points)
      : points_(std::move(points)), prev_(points_.size()), next_(points_.size()) {
    const uint32_t n = static_cast<uint32_t>(points_.size());
    for (uint32_t i = 0; i < n; ++i) {
      prev_[i] = (i + n - 1) % n;
      next_[i] = (i + 1) % n;
    }
    remaining_ = n;
    build_grid();
  }

  // Emits triangles as positions in the ring (0..n-1); returns the vertices left unclipped
  // when no ear could be found (empty when the polygon was fully triangulated).
  std::vector<uint32_t> clip(std::vector<uint32_t>& triangles) {
    uint32_t ear = 0, stop = 0;
    while (remaining_ > 3) {
      if (corner(ear) == 0.0) {
        // Straight on or doubled back: a triangle here has no area, and leaving the vertex
        // in place blocks its neighbours' ears (it lies on their diagonal).
        const uint32_t a = prev_[ear];
        unlink(ear);
        ear = stop = a;
        continue;
      }
      if (is_ear(ear)) {
        const uint32_t a = prev_[ear], c = next_[ear];
        triangles.insert(triangles.end(), {a, ear, c});
        unlink(ear);
        ear = stop = a;  // its corner changed: it may be an ear now
        continue;
      }
      ear = next_[ear];
      if (ear != stop) continue;
      // A whole lap without an ear: only a self-intersecting outline gets here.
      return ring_from(ear);
    }
    const uint32_t b = next_[ear];
    triangles.insert(triangles.end(), {ear, b, next_[b]});
    return {};
  }

 private:
  double corner(uint32_t b) const {
    const glm::dvec2 &a = points_[prev_[b]], &p = points_[b], &c = points_[next_[b]];
    return cross2(p - a, c - p);
  }

  std::size_t cell_of(const glm::dvec2& p, int axis) const {
    const double t = (p[axis] - min_[axis]) * cells_per_unit_[axis];
    const std::size_t side = axis == 0 ? side_x_ : side_y_;
    return static_cast<std::size_t>(std::clamp(t, 0.0, static_cast<double>(side - 1)));
  }

  void add_to_grid(uint32_t v) {
    grid_[cell_of(points_[v], 1) * side_x_ + cell_of(points_[v], 0)].push_back(v);
  }

  void build_grid() {
    min_ = max_ = points_[0];
    for (const glm::dvec2& p : points_) {
      min_ = glm::min(min_, p);
      max_ = glm::max(max_, p);
    }
    reflex_.resize(points_.size());
    std::size_t reflex_count = 0;
    for (uint32_t v = 0; v < points_.size(); ++v) {
      reflex_[v] = corner(v) <= 0.0;
      reflex_count += reflex_[v];
    }
    // About two reflex vertices a cell, the cells about square: a long thin polygon gets a
    // long thin grid, so a small triangle's box covers few cells.
    const double cells = std::clamp(static_cast<double>(reflex_count) / 2.0, 1.0, 1048576.0);
    const glm::dvec2 extent = max_ - min_;
    const double aspect = extent.y > 0.0 ? extent.x / extent.y : (extent.x > 0.0 ? cells : 1.0);
    side_x_ = static_cast<std::size_t>(std::clamp(std::sqrt(cells * aspect), 1.0, cells));
    side_y_ =
        static_cast<std::size_t>(std::clamp(cells / static_cast<double>(side_x_), 1.0, cells));
    for (int axis = 0; axis < 2; ++axis) {
      const double side = static_cast<double>(axis == 0 ? side_x_ : side_y_);
      cells_per_unit_[axis] = extent[axis] > 0.0 ? side / extent[axis] : 0.0;
    }
    grid_.assign(side_x_ * side_y_, {});
    for (uint32_t v = 0; v < points_.size(); ++v) {
      if (reflex_[v]) add_to_grid(v);
    }
  }

  // Whether no reflex vertex of the cell other than a, b, c lies in or on abc. Entries go
  // stale as vertices are clipped or turn convex; they are dropped here, or every later test
  // would step over them again.
  bool cell_is_clear(std::vector<uint32_t>& cell, uint32_t a, uint32_t b, uint32_t c) {
    std::erase_if(cell, [&](uint32_t v) { return !reflex_[v] || next_[v] == kClipped; });
    for (uint32_t v : cell) {
      if (v != a && v != b && v != c &&
          in_triangle(points_[v], points_[a], points_[b], points_[c])) {
        return false;
      }
    }
    return true;
  }

  bool is_ear(uint32_t b) {
    const uint32_t a = prev_[b], c = next_[b];
    if (corner(b) <= 0.0) return false;
    const glm::dvec2 &pa = points_[a], &pb = points_[b], &pc = points_[c];
    const glm::dvec2 lo = glm::min(pa, glm::min(pb, pc)), hi = glm::max(pa, glm::max(pb, pc));
    const std::size_t x0 = cell_of(lo, 0), x1 = cell_of(hi, 0);
    const std::size_t y0 = cell_of(lo, 1), y1 = cell_of(hi, 1);
    for (std::size_t y = y0; y <= y1; ++y) {
      for (std::size_t x = x0; x <= x1; ++x) {
        if (!cell_is_clear(grid_[y * side_x_ + x], a, b, c)) return false;
      }
    }
    return true;
  }

  // Takes b out of the ring and updates its neighbours' convexity.
  void unlink(uint32_t b) {
    const uint32_t a = prev_[b], c = next_[b];
    next_[a] = c;
    prev_[c] = a;
    next_[b] = prev_[b] = kClipped;
    --remaining_;
    for (uint32_t v : {a, c}) {
      const bool reflex = corner(v) <= 0.0;
      if (reflex && !reflex_[v]) add_to_grid(v);  // only a non-simple outline does this
      reflex_[v] = reflex;
    }
  }

  std::vector<uint32_t> ring_from(uint32_t start) const {
    std::vector<uint32_t> ring;
    uint32_t v = start;
    do {
      ring.push_back(v);
      v = next_[v];
    } while (v != start);
    return ring;
  }

  static constexpr uint32_t kClipped = UINT32_MAX;
  std::vector<glm::dvec2> points_;
  std::vector<uint32_t> prev_, next_;
  std::vector<bool> reflex_;
  std::size_t remaining_ = 0;
  glm::dvec2 min_{0.0}, max_{0.0}, cells_per_unit_{0.0};
  std::size_t side_x_ = 1, side_y_ = 1;
  std::vector<std::vector<uint32_t>> grid_;
};

// The polygon's vertices relative to its first, scaled by a power of two (exact) that brings
// the largest of those differences near 1: the cross products of the ear test then neither
// overflow at 1e300 nor underflow for a polygon 1e-100 across, wherever it lies.
std::vector<glm::dvec3> scaled_from_first(std::span<const glm::dvec3> positions,
                                          std::span<const uint32_t> polygon) {
  // Halved first: the difference of two values near DBL_MAX would overflow. Halving is exact,
  // so each difference is the unhalved one's rounding, halved.
  const glm::dvec3 origin = 0.5 * positions[polygon[0]];
  std::vector<glm::dvec3> scaled(polygon.size());
  double largest = 0.0;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    scaled[k] = 0.5 * positions[polygon[k]] - origin;
    const glm::dvec3 a = glm::abs(scaled[k]);
    largest = std::max({largest, a.x, a.y, a.z});
  }
  const int exponent = largest > 0.0 && std::isfinite(largest) ? std::ilogb(largest) : 0;
  for (glm::dvec3& p : scaled) {
    for (int axis = 0; axis < 3; ++axis) p[axis] = std::ldexp(p[axis], -exponent);
  }
  return scaled;
}

}  // namespace

void triangulate_polygon(std::span<const glm::dvec3> positions, std::span<const uint32_t> polygon,
                         std::vector<uint32_t>& triangles) {
  const std::size_t n = polygon.size();
  if (n < 3) return;
  if (n == 3) return fan(polygon, triangles);

  // Relative to the first vertex, so a polygon far from the origin is as exact as one near it.
  const std::vector<glm::dvec3> relative = scaled_from_first(positions, polygon);
  // Newell's normal: robust for non-planar and non-convex polygons.
  glm::dvec3 normal(0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3& a = relative[i];
    const glm::dvec3& b = relative[(i + 1) % n];
    normal +=
        glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
  }
  // Drop the dominant axis; order the other two so the polygon is counter-clockwise in 2D.
  int drop = 2;
  if (std::abs(normal.x) >= std::abs(normal.y) && std::abs(normal.x) >= std::abs(normal.z)) {
    drop = 0;
  } else if (std::abs(normal.y) >= std::abs(normal.z)) {
    drop = 1;
  }
  if (!(normal[drop] != 0.0) || !std::isfinite(normal[drop])) {
    return fan(polygon, triangles);  // no area, or not finite
  }
  int u = (drop + 1) % 3, v = (drop + 2) % 3;
  if (normal[drop] < 0.0) std::swap(u, v);

  std::vector<glm::dvec2> points(n);
  for (std::size_t i = 0; i < n; ++i) points[i] = {relative[i][u], relative[i][v]};
  std::vector<uint32_t> local;
  EarClipper clipper(std::move(points));
  const std::vector<uint32_t> rest = clipper.clip(local);
  // No reserve here: an exact one per polygon would copy the whole array for every quad.
  for (uint32_t i : local) triangles.push_back(polygon[i]);
  if (!rest.empty()) {
    std::vector<uint32_t> rest_indices;
    for (uint32_t i : rest) rest_indices.push_back(polygon[i]);
    fan(rest_indices, triangles);
  }
}

}  // namespace soltex
