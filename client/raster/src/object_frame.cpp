#include "object_frame.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace soltex::raster_internal {

uint32_t planes_keeping_the_eye(const RasterView& view) {
  // The eye projects to clip (0, 0, z, 0): it is where the inverse takes that direction.
  const glm::dvec4 eye = glm::inverse(glm::dmat4(view.view_projection)) * glm::dvec4(0, 0, 1, 0);
  if (!(std::abs(eye.w) > 0.0)) return 0;
  const glm::dvec3 at = glm::dvec3(eye) / eye.w;
  uint32_t mask = 0;
  for (std::size_t j = 0; j < view.clip_planes.size(); ++j) {
    const glm::dvec4& plane = view.clip_planes[j];
    if (glm::dot(glm::dvec3(plane), at) + plane.w >= 0.0) mask |= 1u << j;
  }
  return mask;
}

ObjectFrame make_object_frame(const RasterObject& object, const RasterView& view,
                              std::size_t first_vertex, uint32_t keeping_eye) {
  const glm::dmat4 model(object.model);
  ObjectFrame frame;
  frame.source = &object;
  frame.clip_from_object = glm::mat4(glm::dmat4(view.view_projection) * model);
  frame.world_normal_from_object = glm::mat3(glm::transpose(glm::inverse(glm::dmat3(model))));
  frame.texture_from_world = object.texture_from_object * glm::inverse(model);
  const glm::dmat4 model_transposed = glm::transpose(model);
  for (std::size_t j = 0; j < view.clip_planes.size(); ++j) {
    // A plane that does not cut this object becomes one that keeps everything (distance 1).
    frame.object_planes[j] = (object.clip_plane_mask >> j) & 1u
                                 ? model_transposed * view.clip_planes[j]
                                 : glm::dvec4(0.0, 0.0, 0.0, 1.0);
  }
  frame.first_vertex = first_vertex;
  const uint32_t planes_here = (1u << view.clip_planes.size()) - 1u;  // at most kMaxClipPlanes
  frame.cull_back_faces = object.cull_back_faces && (object.clip_plane_mask & planes_here) == 0;
  const uint32_t cutting = object.clip_plane_mask & planes_here;
  const uint32_t exits = cutting & keeping_eye;
  if (object.closed && exits != 0 && exits != cutting) frame.beyond_planes = exits;
  return frame;
}

}  // namespace soltex::raster_internal
