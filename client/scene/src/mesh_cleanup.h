#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

// Repairs for meshes read from files, on positions in float (a finished Mesh) or in double (an
// OBJ file's coordinates before they are normalised). Each edits positions and triangle
// indices in place and returns how many vertices or triangles it removed; none computes
// normals or bounds.
namespace soltex {

// Merges vertices whose positions are bit-identical (after folding -0 into +0), so the
// triangles around a split seam share vertices and get smooth normals.
template <class Position>
std::size_t merge_duplicate_vertices(std::vector<Position>& positions,
                                     std::vector<uint32_t>& indices);

// Drops triangles that use a vertex twice or have zero area (computed in double, where the
// cross product of exactly collinear float points is exactly zero).
template <class Position>
std::size_t drop_degenerate_triangles(const std::vector<Position>& positions,
                                      std::vector<uint32_t>& indices);

// Drops every triangle but the first over the same three vertices, in either winding: a face
// written twice, or once each way to make it two-sided, would otherwise cancel its own vertex
// normals and fight itself for depth. Returns how many it dropped.
std::size_t drop_duplicate_triangles(std::vector<uint32_t>& indices);

// Removes vertices no triangle uses, so they neither widen the bounds nor waste work.
template <class Position>
std::size_t remove_unreferenced_vertices(std::vector<Position>& positions,
                                         std::vector<uint32_t>& indices);

extern template std::size_t merge_duplicate_vertices(std::vector<glm::vec3>&,
                                                     std::vector<uint32_t>&);
extern template std::size_t merge_duplicate_vertices(std::vector<glm::dvec3>&,
                                                     std::vector<uint32_t>&);
extern template std::size_t drop_degenerate_triangles(const std::vector<glm::vec3>&,
                                                      std::vector<uint32_t>&);
extern template std::size_t drop_degenerate_triangles(const std::vector<glm::dvec3>&,
                                                      std::vector<uint32_t>&);
extern template std::size_t remove_unreferenced_vertices(std::vector<glm::vec3>&,
                                                         std::vector<uint32_t>&);
extern template std::size_t remove_unreferenced_vertices(std::vector<glm::dvec3>&,
                                                         std::vector<uint32_t>&);

}  // namespace soltex
