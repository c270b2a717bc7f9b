#pragma once

#include <cstddef>
#include <cstdint>

#include "homogeneous_clipper.h"
#include "object_frame.h"
#include "transformed_vertices.h"

// A frame's first pass in vector lanes: an object's vertices transformed (clip position,
// texture position, unit world normal, validity) and projected to the screen (outcodes, guard
// band planes, fixed-point position, depth, 1/w), dispatched at run time to the widest vector
// target the CPU has (vertex_kernels.cpp). A fine mesh has tens of thousands of vertices a
// frame; one at a time, each waited on its own divisions and square root.
namespace soltex::raster_internal {

// The screen a vertex is projected to, as TriangleSetup projects it.
struct VertexProjection {
  int width = 0;
  int height = 0;
  const ClipPlanes* planes = nullptr;  // the guard band and near planes
};

// transform_vertices() and then TriangleSetup::project_vertices() over the object's vertices
// [begin, end) (indices into its mesh), bit for bit: each lane runs the same IEEE operations in
// the same order as those functions do for one vertex.
void transform_and_project(const ObjectFrame& object, const VertexProjection& projection,
                           std::size_t begin, std::size_t end, TransformedVertices& out);

// For tests: the Highway targets compiled into vertex_kernels.cpp, and the one
// transform_and_project() runs now.
int64_t vertex_kernels_compiled_targets();
int64_t vertex_kernels_dispatched_target();

}  // namespace soltex::raster_internal
