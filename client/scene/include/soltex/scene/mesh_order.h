#pragma once

#include "soltex/scene/mesh.h"

// Mesh order for drawing. A scanned mesh (the Stanford bunny) lists its triangles in no
// spatial order: neighbouring triangles use vertices tens of kilobytes apart, and triangle
// setup waits on memory for most of them. Sorting the triangles along a space-filling curve and
// numbering the vertices in the order the triangles first use them keeps both close.
namespace soltex {

// Reorders the triangles along the Morton curve of their centroids (meshoptimizer's
// meshopt_spatialSortTriangles; ties keep the file's order), keeping each triangle's own vertex
// order (so its winding and first vertex), then renumbers the vertices by first use
// (meshopt_optimizeVertexFetchRemap); vertices no triangle uses follow, in their old order.
// Positions and normals (when there is one per position) move with their vertices, unchanged,
// so the mesh draws the same surface; only which of two fragments at exactly equal depth wins
// can differ. Triangles with an index out of range come last, as they were; a NaN coordinate
// sorts as the lowest on its axis. A mesh of fewer than two triangles, or whose index count is
// not a multiple of three, is left as it is.
void order_for_locality(Mesh& mesh);

}  // namespace soltex
