#include "mesh_for_view.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

namespace soltex::render {

RasterMesh mesh_for_view(const PreparedObject& object, const Camera& camera, int height) {
  const RasterMesh own = object.raster.mesh;
  if (object.object == nullptr || object.object->levels == nullptr ||
      object.object->levels->empty() || object.object->mesh == nullptr || height < 1) {
    return own;
  }
  const glm::dmat4& m = object.world_from_object;
  // The transform stretches lengths by at most its largest column (exact for rotations and
  // uniform scales, an over-estimate under shear only: the choice stays on the fine side).
  const double scale = std::max({glm::length(glm::dvec3(m[0])), glm::length(glm::dvec3(m[1])),
                                 glm::length(glm::dvec3(m[2]))});
  const BoundingBox& box = object.object->mesh->bounds;
  const glm::dvec3 low(box.min), high(box.max);
  const glm::dvec3 centre = glm::dvec3(m * glm::dvec4(0.5 * (low + high), 1.0));
  const double radius = 0.5 * glm::length(high - low) * scale;
  const double distance = std::max(glm::length(centre - camera.position) - radius, camera.near);
  const double pixel = 2.0 * distance *
                       std::tan(0.5 * camera.fov_y_degrees * std::numbers::pi / 180.0) /
                       static_cast<double>(height);
  if (!std::isfinite(scale) || !std::isfinite(pixel) || !(pixel > 0.0)) return own;
  const double allowed = kMaxLevelErrorPixels * pixel / scale;  // in the mesh's units
  RasterMesh chosen = own;
  for (const MeshLevel& level : *object.object->levels) {
    if (!(static_cast<double>(level.error) <= allowed)) break;  // errors grow level by level
    chosen = {level.mesh.positions, level.mesh.normals, level.mesh.indices};
  }
  return chosen;
}

}  // namespace soltex::render
