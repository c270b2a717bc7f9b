#include "polygon_triangulation.h"

#include <cmath>
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

}  // namespace

void triangulate_polygon(std::span<const glm::vec3> positions, std::span<const uint32_t> polygon,
                         std::vector<uint32_t>& triangles) {
  const std::size_t n = polygon.size();
  if (n < 3) return;
  if (n == 3 || n > kMaxEarClippedPolygon) return fan(polygon, triangles);

  // Newell's normal: robust for non-planar and non-convex polygons.
  glm::dvec3 normal(0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 a(positions[polygon[i]]), b(positions[polygon[(i + 1) % n]]);
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
  if (normal[drop] == 0.0) return fan(polygon, triangles);
  int u = (drop + 1) % 3, v = (drop + 2) % 3;
  if (normal[drop] < 0.0) std::swap(u, v);

  std::vector<glm::dvec2> points(n);
  for (std::size_t i = 0; i < n; ++i) {
    points[i] = {positions[polygon[i]][u], positions[polygon[i]][v]};
  }
  std::vector<std::size_t> remaining(n);
  for (std::size_t i = 0; i < n; ++i) remaining[i] = i;

  while (remaining.size() > 3) {
    const std::size_t m = remaining.size();
    bool clipped = false;
    for (std::size_t k = 0; k < m && !clipped; ++k) {
      const std::size_t ip = remaining[(k + m - 1) % m], ic = remaining[k],
                        in = remaining[(k + 1) % m];
      const glm::dvec2 &a = points[ip], &b = points[ic], &c = points[in];
      if (cross2(b - a, c - b) <= 0.0) continue;  // reflex or flat: not an ear
      bool empty = true;
      for (std::size_t other : remaining) {
        if (other == ip || other == ic || other == in) continue;
        if (in_triangle(points[other], a, b, c)) {
          empty = false;
          break;
        }
      }
      if (!empty) continue;
      triangles.insert(triangles.end(), {polygon[ip], polygon[ic], polygon[in]});
      remaining.erase(remaining.begin() + static_cast<std::ptrdiff_t>(k));
      clipped = true;
    }
    if (!clipped) {
      std::vector<uint32_t> rest;
      for (std::size_t i : remaining) rest.push_back(polygon[i]);
      return fan(rest, triangles);
    }
  }
  triangles.insert(triangles.end(),
                   {polygon[remaining[0]], polygon[remaining[1]], polygon[remaining[2]]});
}

}  // namespace soltex
