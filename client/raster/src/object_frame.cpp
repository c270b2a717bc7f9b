#include "object_frame.h"

#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <limits>

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

namespace {

// The texture-space box of an object's bounds: its eight corners' box, padded for the float
// rounding of the mesh's vertices and the transform.
void set_texture_box(const RasterObject& object, ObjectFrame& frame) {
  const glm::dvec3 low(object.bounds_min), high(object.bounds_max);
  for (int axis = 0; axis < 3; ++axis) {
    if (!std::isfinite(low[axis]) || !std::isfinite(high[axis])) return;  // unbounded
  }
  frame.texture_min = glm::dvec3(std::numeric_limits<double>::infinity());
  frame.texture_max = -frame.texture_min;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p((corner & 1) ? high.x : low.x, (corner & 2) ? high.y : low.y,
                       (corner & 4) ? high.z : low.z);
    const glm::dvec3 t(object.texture_from_object * glm::dvec4(p, 1.0));
    frame.texture_min = glm::min(frame.texture_min, t);
    frame.texture_max = glm::max(frame.texture_max, t);
  }
  const glm::dvec3 pad = 1e-5 * (frame.texture_max - frame.texture_min) +
                         1e-6 * glm::max(glm::abs(frame.texture_min), glm::abs(frame.texture_max));
  frame.texture_min -= pad;
  frame.texture_max += pad;
}

}  // namespace

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
  if (cutting != 0) set_texture_box(object, frame);
  return frame;
}

}  // namespace soltex::raster_internal
