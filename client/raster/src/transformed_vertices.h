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
  int64_t x = 0;  // fixed point
  int64_t y = 0;
  double depth = 0.0;  // window depth
  float inv_w = 0.0f;  // 1/w
};

// One vertex, transformed. Triangle setup reads the vertices of a triangle at random places,
// so everything it reads of one vertex is kept together: the first cache line holds what
// every triangle needs (clip position, validity, screen position), the second what only the
// drawn ones need.
struct alignas(64) TransformedVertex {
  glm::vec4 clip{0.0f};
  // Valid where `valid` is and the vertex is inside the guard band; unspecified elsewhere.
  ScreenVertex screen;
  uint8_t valid = 0;  // 0 when the position (or what it became) is not finite
  // Where `valid` is: the sides of the view volume the vertex is outside of (for trivial
  // rejection), and the planes (ClipPlaneBit) it would be clipped against.
  uint8_t frustum_outside = 0;
  uint8_t clip_outside = 0;
  glm::dvec3 texture{0.0};  // double: see GBuffer on texture-space precision
  glm::vec3 normal{0.0f};   // world space; zero when the mesh has no normals
};

// Every object's vertices, transformed once per frame (a mesh vertex is shared by about six
// triangles), indexed by ObjectFrame::first_vertex + index.
struct TransformedVertices {
  std::vector<TransformedVertex> vertex;
  std::vector<float> plane_distance;  // [vertex * plane_count + plane], user clip planes
  int plane_count = 0;

  void resize(std::size_t vertex_count, int planes);
};

// Transforms the object's vertices [begin, end) (indices into its mesh).
void transform_vertices(const ObjectFrame& object, std::size_t begin, std::size_t end,
                        TransformedVertices& out);

}  // namespace soltex::raster_internal
