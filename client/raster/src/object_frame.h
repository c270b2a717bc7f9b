#pragma once

#include <array>
#include <cstddef>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <glm/vector_relational.hpp>
#include <limits>
#include <span>

#include "soltex/raster/raster_object.h"
#include "soltex/raster/raster_view.h"

// What one render needs to know about one object, derived once per frame.
namespace soltex::raster_internal {

struct ObjectFrame {
  const RasterObject* source = nullptr;
  glm::mat4 clip_from_object{1.0f};          // view_projection * model, multiplied in double
  glm::mat3 world_normal_from_object{1.0f};  // inverse transpose of the model's 3x3
  glm::dmat4 texture_from_world{1.0};        // texture_from_object * inverse(model), for caps
  // The user clip planes pulled back to object space (plane . (model * p) = (model^T plane)
  // . p), so a vertex's signed distance needs no world position.
  std::array<glm::dvec4, RasterView::kMaxClipPlanes> object_planes{};
  std::size_t first_vertex = 0;  // where its vertices start in TransformedVertices
  // RasterObject::cull_back_faces, unless one of this frame's clip planes cuts the object.
  bool cull_back_faces = false;
  // The planes cutting the object whose kept side holds the eye, when another plane cutting
  // it does not: a view ray may then enter the kept region through one plane and leave it
  // through one of these before meeting the object, and whether it entered inside the solid
  // is told by the surface beyond (TileRasterizer's "beyond" fragments). Triangles wholly on
  // the cut side of these planes are drawn for that test alone. 0 for most objects.
  uint32_t beyond_planes = 0;
  // RasterObject's bounds in texture space (their corners' box, padded by float rounding):
  // where a cap of the object can lie.
  glm::dvec3 texture_min{-std::numeric_limits<double>::infinity()};
  glm::dvec3 texture_max{std::numeric_limits<double>::infinity()};

  // Whether a cap point can be the object's: within its bounds, or for an edge sample within
  // `slack` of them (an edge sample's ray passes up to about a pixel beside the face it
  // samples, so the cap point of a face on the bounds, a cut box's, may lie that far outside).
  bool may_hold_cap(const glm::dvec3& texture_position, double slack = 0.0) const {
    return glm::all(glm::greaterThanEqual(texture_position, texture_min - slack)) &&
           glm::all(glm::lessThanEqual(texture_position, texture_max + slack));
  }
};

// The frame's clip planes whose kept side holds the eye (bit j for plane j); 0 when the view
// has no eye at a finite point.
uint32_t planes_keeping_the_eye(const RasterView& view);

// `keeping_eye`: planes_keeping_the_eye(view), made once for the frame's objects.
ObjectFrame make_object_frame(const RasterObject& object, const RasterView& view,
                              std::size_t first_vertex, uint32_t keeping_eye);

}  // namespace soltex::raster_internal
