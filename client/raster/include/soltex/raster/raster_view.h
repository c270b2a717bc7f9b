#pragma once

#include <cstddef>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <span>

// The camera, the image size and the user clip planes of one frame.
//
// Conventions (OpenGL): right-handed world, clip z in [-w, w], front faces counter-clockwise
// in normalized device coordinates. Pixel (x, y) is column x, row y, row 0 at the TOP (image
// order); its centre is NDC ((x + 0.5) / width * 2 - 1, 1 - (y + 0.5) / height * 2).
namespace soltex {

struct RasterView {
  // Bounded so that fixed-point screen coordinates (with the guard band) fit in 32 bits and
  // edge functions in 64 bits.
  static constexpr int kMaxSize = 16384;
  static constexpr std::size_t kMaxClipPlanes = 8;

  int width = 0;                    // pixels, 1..kMaxSize
  int height = 0;                   // pixels, 1..kMaxSize
  glm::mat4 view_projection{1.0f};  // world space -> clip space
  // World-space planes (a, b, c, d): a point x is kept where a*x + b*y + c*z + d >= 0.
  // At most kMaxClipPlanes, each finite with a non-zero normal. Empty: no clipping or capping
  // work is done at all.
  std::span<const glm::dvec4> clip_planes;
  // The frame's edge pixels are sampled between pixel centres afterwards
  // (Rasterizer::sample_edges): triangles that cover no pixel centre are kept and binned by the
  // pixels they touch, where otherwise they are culled, so that a silhouette of triangles
  // smaller than a pixel is not thinned.
  bool edge_sampling = false;
};

}  // namespace soltex
