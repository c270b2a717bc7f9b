#include "transformed_vertices.h"

#include <cmath>
#include <glm/geometric.hpp>

#include "saturating_cast.h"

namespace soltex::raster_internal {

namespace {

bool is_finite(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}
bool is_finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Normalized per vertex so that a scaled model does not weigh some vertices more in the
// interpolation; zero (then triangle setup uses the face normal) when there is no direction.
glm::vec3 unit_or_zero(const glm::vec3& v) {
  const float length = glm::length(v);
  if (!(length > 0.0f) || !std::isfinite(length)) return glm::vec3(0.0f);
  return v / length;
}

}  // namespace

void TransformedVertices::resize(std::size_t vertex_count, int planes) {
  plane_count = planes;
  vertex.resize(vertex_count);
  clip.resize(vertex_count);
  plane_distance.resize(vertex_count * static_cast<std::size_t>(planes));
}

void transform_vertices(const ObjectFrame& object, std::size_t begin, std::size_t end,
                        TransformedVertices& out) {
  const RasterMesh& mesh = object.source->mesh;
  const bool has_normals = !mesh.normals.empty();
  for (std::size_t i = begin; i < end; ++i) {
    const std::size_t at = object.first_vertex + i;
    const glm::vec3 position = mesh.positions[i];
    const glm::dvec4 position_d(glm::dvec3(position), 1.0);
    TransformedVertex& v = out.vertex[at];
    const glm::vec4 clip = object.clip_from_object * glm::vec4(position, 1.0f);
    out.clip[at] = clip;
    v.texture = glm::dvec3(object.source->texture_from_object * position_d);
    v.normal = has_normals ? unit_or_zero(object.world_normal_from_object * mesh.normals[i])
                           : glm::vec3(0.0f);
    v.valid = is_finite(clip) && is_finite(v.texture) ? 1 : 0;
  }
  write_plane_distances(object, begin, end, out);
}

void write_plane_distances(const ObjectFrame& object, std::size_t begin, std::size_t end,
                           TransformedVertices& out) {
  const auto planes = static_cast<std::size_t>(out.plane_count);
  if (planes == 0) return;
  const RasterMesh& mesh = object.source->mesh;
  for (std::size_t i = begin; i < end; ++i) {
    const std::size_t at = object.first_vertex + i;
    const glm::dvec4 position_d(glm::dvec3(mesh.positions[i]), 1.0);
    for (std::size_t j = 0; j < planes; ++j) {
      out.plane_distance[at * planes + j] =
          to_float_saturated(glm::dot(object.object_planes[j], position_d));
    }
  }
}

}  // namespace soltex::raster_internal
