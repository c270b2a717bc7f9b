#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "soltex/raster/raster_view.h"

// CapTracer's arithmetic across a run of pixels, dispatched at run time to the widest vector
// target the CPU has (cap_kernels.cpp). Each lane does the same IEEE operations in the same
// order as CapTracer::ray_through() and CapTracer::trace() do for one pixel (glm's products
// written out in glm's order), selects standing in for their branches: the same bits.
namespace soltex::raster_internal {

// Rays through pixel centres (px, py), as CapTracer::ray_through() makes them.
struct CapRayLanes {
  // A run's rays: at most 65 of its own row and 64 of the row below (CapTracer::trace_run()),
  // 129 rounded up to whole blocks of 8.
  static constexpr std::size_t kCapacity = 136;
  template <typename T>
  using Lanes = std::array<T, kCapacity>;

  alignas(64) Lanes<double> px, py;  // in
  alignas(64) Lanes<double> origin_x, origin_y, origin_z, direction_x, direction_y, direction_z;
};
void trace_ray_lanes(const glm::dmat4& world_from_clip, int width, int height, CapRayLanes& lanes,
                     std::size_t count);

// What the caps of one object in one frame share.
struct CapFrame {
  glm::dmat4 clip_from_world;
  glm::dmat4 texture_from_world;
  const std::array<glm::dvec4, RasterView::kMaxClipPlanes>* planes;
  const std::array<glm::vec3, RasterView::kMaxClipPlanes>* cap_normals;
  std::size_t plane_count;
  uint32_t plane_mask;
};

// Per pixel: its own ray and its right and lower neighbours' rays (in); whether its ray
// enters the kept region, and the cap it sees there (out).
struct CapPixelLanes {
  static constexpr std::size_t kCapacity = 64;
  template <typename T>
  using Lanes = std::array<T, kCapacity>;
  struct Rays {
    alignas(64) Lanes<double> origin_x, origin_y, origin_z, direction_x, direction_y, direction_z;
  };

  Rays own, right, below;
  alignas(64) Lanes<uint8_t> hit;
  alignas(64) Lanes<double> texture_x, texture_y, texture_z;
  alignas(64) Lanes<float> normal_x, normal_y, normal_z, depth, footprint;
};
void trace_cap_lanes(const CapFrame& frame, CapPixelLanes& lanes, std::size_t count);

}  // namespace soltex::raster_internal
