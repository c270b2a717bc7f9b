#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <limits>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

// The rasterizer's output: what each pixel sees, for shading and texture lookup later.
//
// One plane per quantity (structure of arrays), row-major, row 0 at the top; index(x, y) =
// y * width + x. Every pixel of every plane is written by each render.
//
// Texture-space positions are doubles. The rasterizer interpolates each triangle's positions
// as float offsets from a double origin (the texture position of one of its vertices), so
// the interpolation is float-fast and its error is relative to the triangle's size, not to
// the distance from the texture origin; the stored sum origin + offset keeps that precision
// for objects at 1e6 or 1e9 in texture space, where a float would be off by 0.06 or 64 units.
namespace soltex {

// A std::allocator whose value-less construct() default-initialises: vector::resize then
// leaves new pixels unwritten instead of zeroing them. Every render writes every pixel of
// every plane, so zeroing only cost the first frame a single-threaded pass over the whole
// buffer (about 45 MB at 1280 x 720), faulting in each page before the render threads wrote it.
template <typename T>
struct UninitializedAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <typename U>
  UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}  // NOLINT: rebinding

  template <typename U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <typename T>
using GBufferPlane = std::vector<T, UninitializedAllocator<T>>;

struct GBuffer {
  static constexpr uint32_t kNoObject = std::numeric_limits<uint32_t>::max();

  enum PixelFlag : uint8_t {
    kCovered = 1u << 0,   // some surface was drawn here
    kBackFace = 1u << 1,  // the nearest surface is the back of a triangle (and not a cap)
    kCap = 1u << 2,       // the pixel looks through a clip plane into a cut solid
  };

  int width = 0;
  int height = 0;

  // Window depth in [0, 1] (NDC z mapped like glDepthRange(0, 1)); +inf where not covered.
  GBufferPlane<float> depth;
  GBufferPlane<uint8_t> flags;       // PixelFlag bits
  GBufferPlane<uint32_t> object_id;  // RasterObject::object_id; kNoObject where not covered
  // Where to evaluate the texture. On a cap: the view ray's intersection with the clip
  // plane, in the texture space of the cut object. Zero where not covered.
  GBufferPlane<glm::dvec3> texture_position;
  // World-space unit normal, interpolated, not flipped on back faces (see kBackFace). On a
  // cap: the clip plane's unit normal pointing out of the kept half-space, towards the
  // viewer: minus (a, b, c) normalized. Zero where not covered.
  GBufferPlane<glm::vec3> normal;
  // Texture-space size of the pixel: max(|dP/dx|, |dP/dy|) of the texture position P per
  // pixel step. >= 0; +inf at grazing angles where the derivative is unbounded; never NaN.
  // Zero where not covered.
  GBufferPlane<float> footprint;
  // The footprint's long side as a vector: the longer of dP/dx and dP/dy (its length is the
  // footprint), and the shorter one's length. Anisotropic lookups space their taps along the
  // first and take their level from the two. Zero and the footprint where the footprint has
  // no direction (caps, uncovered pixels, non-finite derivatives): one tap.
  GBufferPlane<glm::vec3> footprint_axis;
  GBufferPlane<float> footprint_minor;
  // Debug (RasterOptions::count_coverage): how many triangle fragments passed the fill rule
  // at each pixel, before depth and clip tests. Empty unless asked for.
  GBufferPlane<uint32_t> coverage_count;

  std::size_t pixel_count() const {
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
           static_cast<std::size_t>(x);
  }
  bool covered(std::size_t i) const { return (flags[i] & kCovered) != 0; }
  bool back_face(std::size_t i) const { return (flags[i] & kBackFace) != 0; }
  bool is_cap(std::size_t i) const { return (flags[i] & kCap) != 0; }

  // Sizes every plane for width x height (coverage_count only when count_coverage). New
  // pixels are left unwritten, for the next render to write.
  void resize(int new_width, int new_height, bool count_coverage);
};

}  // namespace soltex
