#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

namespace soltex {

// Appends triangles covering the simple polygon `polygon` (indices into `positions`, in
// order) to `triangles`, each with the polygon's own winding. Polygons of any size are
// ear-clipped in the plane of their Newell normal, so no triangle lies outside the polygon;
// vertices where the outline runs straight on or doubles back on itself are left out (they
// would only make zero-area triangles). Where no ear can be found even then (a
// self-intersecting polygon) the rest is fanned and any zero-area triangles are left for
// the degenerate-triangle filter. The caller bounds the polygon's size (kMaxFaceVertices for
// OBJ files): the worst case is quadratic.
void triangulate_polygon(std::span<const glm::dvec3> positions, std::span<const uint32_t> polygon,
                         std::vector<uint32_t>& triangles);

}  // namespace soltex
