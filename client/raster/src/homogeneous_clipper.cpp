#include "homogeneous_clipper.h"

#include <glm/geometric.hpp>

namespace soltex::raster_internal {

ClipPlanes::ClipPlanes(float guard_x, float guard_y)
    : planes{glm::vec4(0.0f, 0.0f, 1.0f, 1.0f),    glm::vec4(0.0f, 0.0f, 0.0f, 1.0f),
             glm::vec4(1.0f, 0.0f, 0.0f, guard_x), glm::vec4(-1.0f, 0.0f, 0.0f, guard_x),
             glm::vec4(0.0f, 1.0f, 0.0f, guard_y), glm::vec4(0.0f, -1.0f, 0.0f, guard_y)} {}

namespace {

float signed_distance(const glm::vec4& plane, int index, const glm::vec4& clip) {
  return glm::dot(plane, clip) - clip_plane_offset(static_cast<std::size_t>(index));
}

// The point where the edge from `inside` to `outside` crosses the plane; always computed in
// this direction (see the header).
ClipVertex crossing(const ClipVertex& inside, float inside_distance, const ClipVertex& outside,
                    float outside_distance) {
  const float t = inside_distance / (inside_distance - outside_distance);
  return {inside.clip + t * (outside.clip - inside.clip),
          inside.weights + t * (outside.weights - inside.weights)};
}

// Sutherland-Hodgman against one plane. Returns false when the result would not fit.
bool clip_against(const glm::vec4& plane, int index, const ClipPolygon& polygon,
                  ClipPolygon& result) {
  std::array<float, ClipPolygon::kCapacity> distance{};
  for (int i = 0; i < polygon.size; ++i) {
    const auto at = static_cast<std::size_t>(i);
    distance[at] = signed_distance(plane, index, polygon.vertices[at].clip);
  }
  result.size = 0;
  const auto push = [&result](const ClipVertex& vertex) {
    if (result.size == ClipPolygon::kCapacity) return false;
    result.vertices[static_cast<std::size_t>(result.size++)] = vertex;
    return true;
  };
  for (int i = 0; i < polygon.size; ++i) {
    const auto current = static_cast<std::size_t>(i);
    const auto following = static_cast<std::size_t>((i + 1) % polygon.size);
    const bool current_in = distance[current] >= 0.0f;
    const bool following_in = distance[following] >= 0.0f;
    if (current_in && !push(polygon.vertices[current])) return false;
    if (current_in != following_in) {
      const std::size_t in = current_in ? current : following;
      const std::size_t out = current_in ? following : current;
      if (!push(
              crossing(polygon.vertices[in], distance[in], polygon.vertices[out], distance[out]))) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace

uint32_t ClipPlanes::outside(const glm::vec4& clip) const {
  uint32_t bits = 0;
  for (int i = 0; i < ClipPolygon::kMaxPlanes; ++i) {
    if (!(signed_distance(planes[static_cast<std::size_t>(i)], i, clip) >= 0.0f)) bits |= 1u << i;
  }
  return bits;
}

ClipPolygon clip_triangle(const ClipPlanes& planes, uint32_t mask, const glm::vec4& a,
                          const glm::vec4& b, const glm::vec4& c) {
  ClipPolygon polygon;
  polygon.vertices[0] = {a, {1.0f, 0.0f, 0.0f}};
  polygon.vertices[1] = {b, {0.0f, 1.0f, 0.0f}};
  polygon.vertices[2] = {c, {0.0f, 0.0f, 1.0f}};
  polygon.size = 3;

  ClipPolygon next;
  for (int p = 0; p < ClipPolygon::kMaxPlanes && polygon.size > 0; ++p) {
    if ((mask & (1u << p)) == 0) continue;
    if (!clip_against(planes.planes[static_cast<std::size_t>(p)], p, polygon, next)) {
      polygon.size = 0;
      break;
    }
    polygon = next;
  }
  return polygon;
}

}  // namespace soltex::raster_internal
