#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <vector>

#include "object_frame.h"

namespace soltex::raster_internal {

// A vertex projected to the screen (TriangleSetup::project_vertices()): what triangle setup
// would compute from it for every triangle that uses it unclipped.
struct ScreenVertex {
  int32_t x = 0;  // fixed point; the guard band keeps it below 2^24 in magnitude
  int32_t y = 0;
  double depth = 0.0;  // window depth
  float inv_w = 0.0f;  // 1/w
};

// One vertex, transformed, in one cache line: triangle setup reads the vertices of a triangle
// at random places, and a fine mesh's vertices outnumber what the caches hold, so a vertex
// costs one line rather than two. Its clip-space position, read only to project it and to
// clip the few triangles that need it, lives apart (TransformedVertices::clip).
struct alignas(64) TransformedVertex {
  // Valid where `valid` is and the vertex is inside the guard band (clip_outside == 0);
  // unspecified elsewhere. ScreenVertex's fields, laid out to leave room for the rest.
  int32_t x = 0;
  int32_t y = 0;
  double depth = 0.0;
  float inv_w = 0.0f;
  uint8_t valid = 0;  // 0 when the position (or what it became) is not finite
  // Where `valid` is: the sides of the view volume the vertex is outside of (for trivial
  // rejection), and the planes (ClipPlaneBit) it would be clipped against.
  uint8_t frustum_outside = 0;
  uint8_t clip_outside = 0;
  glm::dvec3 texture{0.0};  // double: see GBuffer on texture-space precision
  glm::vec3 normal{0.0f};   // world space; zero when the mesh has no normals

  ScreenVertex screen() const { return {x, y, depth, inv_w}; }
  void set_screen(const ScreenVertex& s) {
    x = s.x;
    y = s.y;
    depth = s.depth;
    inv_w = s.inv_w;
  }
};
static_assert(sizeof(TransformedVertex) == 64);

// Every object's vertices, transformed once per frame (a mesh vertex is shared by about six
// triangles), indexed by ObjectFrame::first_vertex + index.
struct TransformedVertices {
  std::vector<TransformedVertex> vertex;
  std::vector<glm::vec4> clip;        // clip-space positions, by the same index
  std::vector<float> plane_distance;  // [vertex * plane_count + plane], user clip planes
  int plane_count = 0;

  void resize(std::size_t vertex_count, int planes);
};

// Transforms the object's vertices [begin, end) (indices into its mesh), one at a time: the
// definition that transform_and_project() (vertex_kernels.h) computes in vector lanes.
void transform_vertices(const ObjectFrame& object, std::size_t begin, std::size_t end,
                        TransformedVertices& out);

// The user clip planes' signed distances of the object's vertices [begin, end), in double,
// saturated to float (TransformedVertices::plane_distance); nothing when the frame has none.
void write_plane_distances(const ObjectFrame& object, std::size_t begin, std::size_t end,
                           TransformedVertices& out);

}  // namespace soltex::raster_internal
