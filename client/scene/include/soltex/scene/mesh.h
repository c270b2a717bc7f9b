#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "soltex/scene/bounding_box.h"

namespace soltex {

// An indexed triangle mesh. Triangles are counter-clockwise seen from outside, so
// cross(b - a, c - a) points out of a closed mesh. `normals` has one unit-length normal per
// position; `bounds` is the box of `positions`. The builders and the OBJ loader keep all
// three consistent; code that edits positions calls update_bounds() (and
// compute_vertex_normals() when the shape changes).
struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<uint32_t> indices;  // three per triangle
  BoundingBox bounds;
  // Its file wrote faces once in each winding, to be seen from both sides: one copy of each
  // is kept, so its objects draw back faces whatever their double_sided says.
  bool two_sided = false;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t triangle_count() const { return indices.size() / 3; }
  void update_bounds() { bounds = bounds_of(positions); }
};

// Smooth vertex normals: the sum of the normals of the triangles around a vertex, each
// weighted by its area (the unnormalised cross product), then normalised. A vertex whose
// sum cancels takes the normal of one of its triangles; an isolated vertex gets +z.
void compute_vertex_normals(Mesh& mesh);

// Vertex normals that keep hard edges: at each corner, the area-weighted normals of the
// triangles around its vertex that turn from the corner's own triangle by at most
// `crease_degrees` (a cube's faces meet at 90 degrees: sharp at 60; a 32-sided cylinder's at
// 11.25: smooth). Where a vertex's corners get different normals it is split into one vertex
// per normal, at the same position. 180 gives compute_vertex_normals()'s smooth normals.
// Returns how many vertices it added.
std::size_t compute_creased_normals(Mesh& mesh, double crease_degrees);

// Moves and uniformly scales the mesh so that its bounding box is centred at the origin and
// its longest side spans [-1, 1], the box of the unit sphere: a model then replaces a
// built-in sphere without changing the look of a texture. Normals are unchanged (uniform
// scale). A mesh with no extent is only centred.
void normalize_to_unit_box(Mesh& mesh);

}  // namespace soltex
