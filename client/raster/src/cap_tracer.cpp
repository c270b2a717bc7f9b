#include "cap_tracer.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <optional>

#include "saturating_cast.h"
#include "whole_blocks.h"

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

// Lanes are traced in blocks of 8: a multiple of every target's vector width in doubles.
constexpr std::size_t kLaneBlock = 8;

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

std::optional<CapTracer::Crossing> CapTracer::crossing(const Ray& ray, uint32_t plane_mask) const {
  Crossing c{0.0, plane_count_, kInfinity};
  for (std::size_t j = 0; j < plane_count_; ++j) {
    if (((plane_mask >> j) & 1u) == 0) continue;  // this plane does not cut the object
    const double start = signed_distance(planes_[j], ray.origin);
    const double along = glm::dot(glm::dvec3(planes_[j]), ray.direction);
    if (start >= 0.0) {
      // Starts on the kept side: no entry through this plane, an exit where it heads out.
      if (along < 0.0) c.exit = std::min(c.exit, -start / along);
      continue;
    }
    if (!(along > 0.0)) return std::nullopt;  // never reaches the kept side
    const double t = -start / along;
    if (t > c.entry) {
      c.entry = t;
      c.entry_plane = j;
    }
  }
  return c;
}

bool CapTracer::trace(int x, int y, const glm::dmat4& texture_from_world, uint32_t plane_mask,
                      CapRayRows& rows, CapSample& sample) const {
  const Ray& ray = ray_at(x, y, rows);
  const std::optional<Crossing> c = crossing(ray, plane_mask);
  return c && cap_at(x, y, ray, *c, texture_from_world, rows, sample);
}

bool CapTracer::trace_through(int x, int y, const glm::dmat4& texture_from_world,
                              uint32_t plane_mask, CapRayRows& rows, CapSample& sample) const {
  const Ray& ray = ray_at(x, y, rows);
  const std::optional<Crossing> c = crossing(ray, plane_mask);
  return c && c->entry < c->exit && cap_at(x, y, ray, *c, texture_from_world, rows, sample);
}

bool CapTracer::cap_at(int x, int y, const Ray& ray, const Crossing& c,
                       const glm::dmat4& texture_from_world, CapRayRows& rows,
                       CapSample& sample) const {
  if (c.entry_plane == plane_count_ || !std::isfinite(c.entry)) return false;
  const glm::dvec4& plane = planes_[c.entry_plane];
  const glm::dvec3 point = ray.origin + c.entry * ray.direction;
  const glm::dvec4 clip = clip_from_world_ * glm::dvec4(point, 1.0);
  const glm::dmat3 texture_linear(texture_from_world);

  sample.texture_position = glm::dvec3(texture_from_world * glm::dvec4(point, 1.0));
  sample.normal = cap_normals_[c.entry_plane];
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

void CapTracer::trace_run(int x_begin, int x_end, int y, const glm::dmat4& texture_from_world,
                          uint32_t plane_mask, CapRayRows& rows, CapRayLanes& rays,
                          CapPixelLanes& lanes) const {
  assert(x_end - x_begin <= static_cast<int>(CapPixelLanes::kCapacity));
  assert(x_begin >= rows.x0_ && x_end - rows.x0_ < CapRayRows::kColumns);
  assert(y == rows.y_);
  // The rays not yet traced: row y's over [x_begin, x_end] (the last one the right neighbour's)
  // and row y + 1's over [x_begin, x_end), traced together, kept in `rows` as ray_at() keeps
  // them.
  struct Missing {
    std::size_t row, column;
  };
  std::array<Missing, CapRayLanes::kCapacity> missing;
  std::size_t count = 0;
  const auto want = [&](int x, int row_y, int last) {
    const auto row = static_cast<std::size_t>(rows.first_ ^ (row_y - rows.y_));
    for (; x <= last; ++x) {
      const auto column = static_cast<std::size_t>(x - rows.x0_);
      if (rows.traced_[row][column]) continue;
      missing[count] = {row, column};
      rays.px[count] = x + 0.5;
      rays.py[count] = row_y + 0.5;
      ++count;
    }
  };
  want(x_begin, y, x_end);
  want(x_begin, y + 1, x_end - 1);
  // Whole blocks of lanes, the last ray repeated (and not kept): a run's few rays would
  // otherwise fall to the vector loop's remainder, a lane at a time.
  const std::size_t ray_lanes = std::min(whole_blocks(count, kLaneBlock), CapRayLanes::kCapacity);
  for (std::size_t k = count; k < ray_lanes && count > 0; ++k) {
    rays.px[k] = rays.px[count - 1];
    rays.py[k] = rays.py[count - 1];
  }
  trace_ray_lanes(world_from_clip_, width_, height_, rays, count > 0 ? ray_lanes : 0);
  for (std::size_t k = 0; k < count; ++k) {
    Ray& ray = rows.rays_[missing[k].row][missing[k].column];
    ray.origin = {rays.origin_x[k], rays.origin_y[k], rays.origin_z[k]};
    ray.direction = {rays.direction_x[k], rays.direction_y[k], rays.direction_z[k]};
    rows.traced_[missing[k].row][missing[k].column] = true;
  }
  const auto put = [](const Ray& ray, CapPixelLanes::Rays& to, std::size_t k) {
    to.origin_x[k] = ray.origin.x;
    to.origin_y[k] = ray.origin.y;
    to.origin_z[k] = ray.origin.z;
    to.direction_x[k] = ray.direction.x;
    to.direction_y[k] = ray.direction.y;
    to.direction_z[k] = ray.direction.z;
  };
  const auto n = static_cast<std::size_t>(x_end - x_begin);
  const std::size_t pixel_lanes = whole_blocks(n, kLaneBlock);
  for (std::size_t k = 0; k < pixel_lanes; ++k) {
    // Past the run: its last pixel again, not read back.
    const int x = x_begin + static_cast<int>(std::min(k, n - 1));
    put(ray_at(x, y, rows), lanes.own, k);
    put(ray_at(x + 1, y, rows), lanes.right, k);
    put(ray_at(x, y + 1, rows), lanes.below, k);
  }
  const CapFrame frame{clip_from_world_, texture_from_world, &planes_,
                       &cap_normals_,    plane_count_,       plane_mask};
  trace_cap_lanes(frame, lanes, pixel_lanes);
}

}  // namespace soltex::raster_internal
