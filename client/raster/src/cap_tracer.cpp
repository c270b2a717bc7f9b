#include "cap_tracer.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <optional>

#include "saturating_cast.h"

namespace soltex::raster_internal {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

double signed_distance(const glm::dvec4& plane, const glm::dvec3& point) {
  return glm::dot(glm::dvec3(plane), point) + plane.w;
}

// Where the ray meets the plane; nothing when it runs parallel to it.
std::optional<glm::dvec3> intersect(const glm::dvec3& origin, const glm::dvec3& direction,
                                    const glm::dvec4& plane) {
  const double along = glm::dot(glm::dvec3(plane), direction);
  if (along == 0.0) return std::nullopt;
  const double t = -signed_distance(plane, origin) / along;
  if (!std::isfinite(t)) return std::nullopt;
  return origin + t * direction;
}

}  // namespace

CapTracer::CapTracer(const RasterView& view)
    : width_(view.width),
      height_(view.height),
      clip_from_world_(glm::dmat4(view.view_projection)),
      world_from_clip_(glm::inverse(glm::dmat4(view.view_projection))),
      plane_count_(view.clip_planes.size()) {
  std::copy(view.clip_planes.begin(), view.clip_planes.end(), planes_.begin());
  for (std::size_t j = 0; j < plane_count_; ++j) {
    cap_normals_[j] = glm::vec3(-glm::normalize(glm::dvec3(planes_[j])));
  }
}

CapTracer::Ray CapTracer::ray_through(double pixel_x, double pixel_y) const {
  const double ndc_x = pixel_x / width_ * 2.0 - 1.0;
  const double ndc_y = 1.0 - pixel_y / height_ * 2.0;
  // The near plane and the middle of the depth range: both finite for an infinite far plane.
  const glm::dvec4 near = world_from_clip_ * glm::dvec4(ndc_x, ndc_y, -1.0, 1.0);
  const glm::dvec4 middle = world_from_clip_ * glm::dvec4(ndc_x, ndc_y, 0.0, 1.0);
  const glm::dvec3 origin = glm::dvec3(near) / near.w;
  return {origin, glm::dvec3(middle) / middle.w - origin};
}

void CapRayRows::begin(int x0, int y) {
  x0_ = x0;
  y_ = y;
  first_ = 0;
  traced_[0].fill(false);
  traced_[1].fill(false);
}

void CapRayRows::next_row() {
  traced_[static_cast<std::size_t>(first_)].fill(false);
  first_ ^= 1;
  ++y_;
}

const CapTracer::Ray& CapTracer::ray_at(int x, int y, CapRayRows& rows) const {
  assert(x >= rows.x0_ && x - rows.x0_ < CapRayRows::kColumns);
  assert(y == rows.y_ || y == rows.y_ + 1);
  const auto row = static_cast<std::size_t>(rows.first_ ^ (y - rows.y_));
  const auto column = static_cast<std::size_t>(x - rows.x0_);
  Ray& ray = rows.rays_[row][column];
  if (!rows.traced_[row][column]) {
    // x + 0.5 and y + 0.5 are exact: the centre's coordinates whichever pixel asks.
    ray = ray_through(x + 0.5, y + 0.5);
    rows.traced_[row][column] = true;
  }
  return ray;
}

bool CapTracer::trace(int x, int y, const glm::dmat4& texture_from_world, uint32_t plane_mask,
                      CapRayRows& rows, CapSample& sample) const {
  const Ray& ray = ray_at(x, y, rows);
  double entry = 0.0;
  std::size_t entry_plane = plane_count_;
  for (std::size_t j = 0; j < plane_count_; ++j) {
    if (((plane_mask >> j) & 1u) == 0) continue;  // this plane does not cut the object
    const double start = signed_distance(planes_[j], ray.origin);
    if (start >= 0.0) continue;  // starts on the kept side: no entry through this plane
    const double along = glm::dot(glm::dvec3(planes_[j]), ray.direction);
    if (!(along > 0.0)) return false;  // never reaches the kept side
    const double t = -start / along;
    if (t > entry) {
      entry = t;
      entry_plane = j;
    }
  }
  if (entry_plane == plane_count_ || !std::isfinite(entry)) return false;

  const glm::dvec4& plane = planes_[entry_plane];
  const glm::dvec3 point = ray.origin + entry * ray.direction;
  const glm::dvec4 clip = clip_from_world_ * glm::dvec4(point, 1.0);
  const glm::dmat3 texture_linear(texture_from_world);

  sample.texture_position = glm::dvec3(texture_from_world * glm::dvec4(point, 1.0));
  sample.normal = cap_normals_[entry_plane];
  sample.depth = to_float_saturated(clip.z / clip.w * 0.5 + 0.5);
  // The same plane seen through the next pixel to the right and the next one down.
  double footprint = 0.0;
  for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
    const Ray& neighbour = ray_at(x + dx, y + dy, rows);
    const std::optional<glm::dvec3> hit = intersect(neighbour.origin, neighbour.direction, plane);
    footprint = std::max(footprint, hit ? glm::length(texture_linear * (*hit - point)) : kInfinity);
  }
  sample.footprint = to_footprint(footprint);
  return true;
}

}  // namespace soltex::raster_internal
