#pragma once

#include <array>
#include <cstddef>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
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
};

ObjectFrame make_object_frame(const RasterObject& object, const RasterView& view,
                              std::size_t first_vertex);

}  // namespace soltex::raster_internal
