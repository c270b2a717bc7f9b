#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

namespace soltex {

// Polygons with more vertices than this are fanned instead of ear-clipped (ear clipping is
// cubic in the worst case; faces this large are rare and usually convex caps).
inline constexpr std::size_t kMaxEarClippedPolygon = 64;

// Appends triangles covering the simple polygon `polygon` (indices into `positions`, in
// order) to `triangles`, each with the polygon's own winding. Non-convex polygons are
// ear-clipped in the plane of their Newell normal, so no triangle lies outside the polygon;
// where no ear can be found (a self-intersecting or collinear polygon) the rest is fanned
// and any zero-area triangles are left for the degenerate-triangle filter.
void triangulate_polygon(std::span<const glm::vec3> positions, std::span<const uint32_t> polygon,
                         std::vector<uint32_t>& triangles);

}  // namespace soltex
