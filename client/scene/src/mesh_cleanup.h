#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
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

// Faces over the same vertices as an earlier one, in either winding: a face written twice, or
// once each way to make it two-sided, would otherwise cancel its own vertex normals and fight
// itself for depth. `reversed`: how many of them ran the other way round.
struct RepeatedFaces {
  std::vector<bool> repeated;  // per face; the first of each set is kept
  std::size_t count = 0;
  std::size_t reversed = 0;
};

// Among polygons given as their corners one after another (`sizes` corners each).
RepeatedFaces find_repeated_polygons(std::span<const uint32_t> corners,
                                     std::span<const uint32_t> sizes);

// Drops the repeated triangles of an indexed mesh (three indices per triangle).
RepeatedFaces drop_duplicate_triangles(std::vector<uint32_t>& indices);

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
