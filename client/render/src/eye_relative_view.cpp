#include "soltex/render/eye_relative_view.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>

#include "mesh_for_view.h"
#include "soltex/render/frame_renderer.h"

namespace soltex {
namespace {

// The near plane a frame is drawn with: the camera's, or further out where no object comes
// nearer. Float depth resolves about 2^-24 of a window's depth range, and a distance z from
// the eye maps to 1 - 2 near / z (for far >> near), so the depth step at z is about
// z^2 / near * 6e-8: with near 1e-5, surfaces 5 units away 0.15 apart would draw in the wrong
// order. No point of an object lies nearer the eye than its bounds, nor, inside the frustum,
// at a view depth below that distance times the cosine of the frustum's widest angle: a near
// plane there (halved, for margin) clips nothing a nearer one showed.
double frame_near(const PreparedScene& scene, const Camera& camera, int width, int height,
                  const glm::dmat4& eye_from_world) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const PreparedObject& o : scene.objects) {
    if (o.object == nullptr || !o.object->mesh || o.object->mesh->bounds.empty()) continue;
    const BoundingBox& bounds = o.object->mesh->bounds;
    const glm::dmat4 eye_from_object = eye_from_world * o.world_from_object;
    glm::dvec3 low(std::numeric_limits<double>::infinity());
    glm::dvec3 high(-std::numeric_limits<double>::infinity());
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec3 p(corner & 1 ? bounds.max.x : bounds.min.x,
                         corner & 2 ? bounds.max.y : bounds.min.y,
                         corner & 4 ? bounds.max.z : bounds.min.z);
      const glm::dvec3 q = glm::dvec3(eye_from_object * glm::dvec4(p, 1.0));
      low = glm::min(low, q);
      high = glm::max(high, q);
    }
    // From the eye (the origin here) to the nearest point of the box.
    nearest = std::min(nearest, glm::length(glm::max(glm::max(low, -high), glm::dvec3(0.0))));
  }
  const double tan_y = std::tan(glm::radians(camera.fov_y_degrees) * 0.5);
  const double tan_x =
      tan_y * static_cast<double>(width) / static_cast<double>(std::max(height, 1));
  const double cos_widest = 1.0 / std::sqrt(1.0 + tan_x * tan_x + tan_y * tan_y);
  const double clear = 0.5 * nearest * cos_widest;
  if (!std::isfinite(clear) || !(clear > camera.near)) return camera.near;
  return std::min(clear, 0.5 * camera.far);
}

}  // namespace

EyeRelativeView eye_relative_view(const PreparedScene& scene, const Camera& camera, int width,
                                  int height, bool simplified) {
  const glm::dvec3& eye = camera.position;
  const glm::dmat4 from_world = glm::translate(glm::dmat4(1.0), -eye);
  EyeRelativeView r;
  r.objects.reserve(scene.objects.size());
  for (const PreparedObject& o : scene.objects) {
    RasterObject object = o.raster;
    object.model = glm::mat4(from_world * o.world_from_object);
    if (simplified) object.mesh = render::mesh_for_view(o, camera, height);
    r.objects.push_back(object);
  }
  for (const glm::dvec4& plane : scene.clip_planes) {
    // a.(p + eye) + d >= 0  <=>  a.p + (d + a.eye) >= 0
    r.clip_planes.emplace_back(glm::dvec3(plane), plane.w + glm::dot(glm::dvec3(plane), eye));
  }
  Camera at_origin = camera;
  at_origin.target = camera.target - eye;
  at_origin.position = glm::dvec3(0.0);
  at_origin.near = frame_near(scene, camera, width, height, from_world);
  r.near = at_origin.near;
  r.view_projection = view_projection(at_origin, width, height);
  return r;
}

}  // namespace soltex
