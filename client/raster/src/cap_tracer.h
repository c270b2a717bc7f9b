#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <optional>
#include <span>

#include "cap_kernels.h"
#include "soltex/raster/gbuffer.h"
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

// Writes `cap` as pixel `at` of a G-buffer's planes (a GBuffer, or GBufferPlanes' pointers),
// a cap of the object `object_id`.
template <typename Planes>
void write_cap_pixel(Planes& target, std::size_t at, uint32_t object_id, const CapSample& cap) {
  target.depth[at] = cap.depth;
  target.flags[at] = GBuffer::kCovered | GBuffer::kCap;
  target.object_id[at] = object_id;
  target.texture_position[at] = cap.texture_position;
  target.normal[at] = cap.normal;
  target.footprint[at] = cap.footprint;
  target.footprint_axis[at] = glm::vec3(0.0f);  // a cap's footprint has no direction
  target.footprint_minor[at] = cap.footprint;
}

struct CapRay {
  glm::dvec3 origin;     // on the near plane
  glm::dvec3 direction;  // towards the far plane
};

// The rays through the pixel centres of two rows of a tile, y and y + 1, over columns x0 to
// x0 + kColumns - 1, each traced when first asked for. A cap pixel reads its own ray and those
// of its right and lower neighbours, which are those neighbours' own rays (the same centre,
// so the same bits): kept here, a cap region costs about one ray per pixel instead of three.
class CapRayRows {
 public:
  static constexpr int kColumns = 65;  // a tile's 64 and the right neighbour of its last

  // Starts at row y of the tile whose first column is x0, nothing traced.
  void begin(int x0, int y);
  // Moves on to row y + 1 (whose traced rays are kept).
  void next_row();

 private:
  friend class CapTracer;
  int x0_ = 0, y_ = 0;
  int first_ = 0;  // rays_[first_] holds row y_, the other row y_ + 1
  std::array<std::array<CapRay, kColumns>, 2> rays_;
  std::array<std::array<bool, kColumns>, 2> traced_{};
};

class CapTracer {
 public:
  explicit CapTracer(const RasterView& view);

  // Writes the cap seen through pixel (x, y) of an object whose texture space is
  // texture_from_world to `sample` and returns true, or returns false (`sample` left partly
  // written) when the pixel's ray does not enter the kept region in front of the camera.
  // `rows`: begun at the tile's first column and at row y; pixel x + 1 of the row must lie in
  // it.
  bool trace(int x, int y, const glm::dmat4& texture_from_world, uint32_t plane_mask,
             CapRayRows& rows, CapSample& sample) const;

  // trace() for a pixel whose ray met the object only past the kept region: also false when
  // the ray leaves the region (through a plane whose kept side holds its start) before it
  // enters it, so that the region is empty along the ray.
  bool trace_through(int x, int y, const glm::dmat4& texture_from_world, uint32_t plane_mask,
                     CapRayRows& rows, CapSample& sample) const;

  // trace() for the pixels [x_begin, x_end) of row y (at most CapPixelLanes::kCapacity), in
  // vector lanes (cap_kernels.cpp): lane k of `lanes` holds pixel x_begin + k's result, its
  // `hit` what trace() returns, the rest the sample trace() writes. The same bits.
  void trace_run(int x_begin, int x_end, int y, const glm::dmat4& texture_from_world,
                 uint32_t plane_mask, CapRayRows& rows, CapRayLanes& rays,
                 CapPixelLanes& lanes) const;

 private:
  using Ray = CapRay;
  Ray ray_through(double pixel_x, double pixel_y) const;
  // The ray through pixel (x, y)'s centre, y the rows' row or the one below.
  const Ray& ray_at(int x, int y, CapRayRows& rows) const;
  // Where a ray enters the kept region of the planes in a mask (the largest entry parameter,
  // 0 and no plane when it starts inside) and where it leaves it (the smallest exit).
  struct Crossing {
    double entry;
    std::size_t entry_plane;  // plane_count_ for none
    double exit;
  };
  // Nothing when the ray never reaches the kept side of one of the planes.
  std::optional<Crossing> crossing(const Ray& ray, uint32_t plane_mask) const;
  // The cap where `ray` (pixel (x, y)'s) enters the region; false when it does not enter.
  bool cap_at(int x, int y, const Ray& ray, const Crossing& c, const glm::dmat4& texture_from_world,
              CapRayRows& rows, CapSample& sample) const;

  int width_;
  int height_;
  glm::dmat4 clip_from_world_;
  glm::dmat4 world_from_clip_;
  std::array<glm::dvec4, RasterView::kMaxClipPlanes> planes_{};
  // Per plane: the unit normal out of the kept half-space, as a cap writes it.
  std::array<glm::vec3, RasterView::kMaxClipPlanes> cap_normals_{};
  std::size_t plane_count_;
};

}  // namespace soltex::raster_internal
