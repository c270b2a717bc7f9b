#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <optional>
#include <span>

#include "soltex/raster/raster_view.h"

// Caps of clipped solids, traced per pixel in double.
//
// The kept region K is the intersection of the clip planes' half-spaces: convex. A pixel
// whose nearest remaining fragment is a back face of a closed solid S sees the inside of S;
// the visible surface of S ∩ K there is where the view ray enters K: the largest entry
// parameter over the planes the ray crosses into (the slab method on a convex region). When
// the ray starts inside K there is no entry (the near plane, not a clip plane, cut the solid),
// and the pixel stays a back face.
namespace soltex::raster_internal {

struct CapSample {
  glm::dvec3 texture_position{0.0};
  glm::vec3 normal{0.0f};  // unit, out of the kept half-space (towards the viewer)
  float depth = 0.0f;      // window depth of the cap point
  float footprint = 0.0f;  // texture-space distance to the neighbouring pixels' cap points
};

class CapTracer {
 public:
  explicit CapTracer(const RasterView& view);

  // The cap seen through pixel (x, y) of an object whose texture space is texture_from_world,
  // or nothing when the pixel's ray does not enter the kept region in front of the camera.
  std::optional<CapSample> trace(int x, int y, const glm::dmat4& texture_from_world,
                                 uint32_t plane_mask = ~0u) const;

 private:
  struct Ray {
    glm::dvec3 origin;     // on the near plane
    glm::dvec3 direction;  // towards the far plane
  };
  Ray ray_through(double pixel_x, double pixel_y) const;

  int width_;
  int height_;
  glm::dmat4 clip_from_world_;
  glm::dmat4 world_from_clip_;
  std::array<glm::dvec4, RasterView::kMaxClipPlanes> planes_{};
  std::size_t plane_count_;
};

}  // namespace soltex::raster_internal
