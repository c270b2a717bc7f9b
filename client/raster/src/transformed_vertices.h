#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <vector>

#include "object_frame.h"

// Every object's vertices, transformed once per frame (a mesh vertex is shared by about six
// triangles), in one structure of arrays indexed by ObjectFrame::first_vertex + index.
namespace soltex::raster_internal {

// A vertex projected to the screen (TriangleSetup::project_vertices()): what triangle setup
// would compute from it for every triangle that uses it unclipped.
struct ScreenVertex {
  int64_t x = 0;  // fixed point
  int64_t y = 0;
  double depth = 0.0;  // window depth
  float inv_w = 0.0f;  // 1/w
};

struct TransformedVertices {
  std::vector<glm::vec4> clip;
  std::vector<glm::dvec3> texture;    // double: see GBuffer on texture-space precision
  std::vector<glm::vec3> normal;      // world space; zero when the mesh has no normals
  std::vector<uint8_t> valid;         // 0 when the position (or what it became) is not finite
  std::vector<float> plane_distance;  // [vertex * plane_count + plane], user clip planes
  // Valid where `valid` is and the vertex is inside the guard band; unspecified elsewhere.
  std::vector<ScreenVertex> screen;
  int plane_count = 0;

  void resize(std::size_t vertex_count, int planes);
};

// Transforms the object's vertices [begin, end) (indices into its mesh).
void transform_vertices(const ObjectFrame& object, std::size_t begin, std::size_t end,
                        TransformedVertices& out);

}  // namespace soltex::raster_internal
