#pragma once

#include <cstddef>

#include "soltex/scene/mesh.h"

// Repairs for meshes read from files. Each edits the mesh in place and returns how many
// vertices or triangles it removed; none computes normals or bounds.
namespace soltex {

// Merges vertices whose positions are bit-identical (after folding -0 into +0), so the
// triangles around a split seam share vertices and get smooth normals.
std::size_t merge_duplicate_vertices(Mesh& mesh);

// Drops triangles that use a vertex twice or have zero area (computed in double, where the
// cross product of exactly collinear float points is exactly zero).
std::size_t drop_degenerate_triangles(Mesh& mesh);

// Removes vertices no triangle uses, so they neither widen the bounds nor waste work.
std::size_t remove_unreferenced_vertices(Mesh& mesh);

}  // namespace soltex
