#pragma once

#include <cstdint>

// What one render did, counted. Work that only clip planes cause has its own counters, so a
// scene without clip planes can be checked to do none of it (clip_plane_work() == 0).
namespace soltex {

struct RasterStats {
  // Triangles
  uint64_t triangles_in = 0;                  // submitted (every object's triangle_count())
  uint64_t triangles_invalid = 0;             // skipped: non-finite vertex or index out of range
  uint64_t triangles_degenerate = 0;          // skipped: zero area on screen (after snapping)
  uint64_t triangles_culled = 0;              // outside the view volume or between pixel centres
  uint64_t triangles_back_face_culled = 0;    // facing away, object draws front faces only
  uint64_t triangles_clipped_near = 0;        // cut by the near plane (homogeneous space)
  uint64_t triangles_clipped_guard_band = 0;  // cut to keep screen coordinates bounded
  uint64_t triangles_rasterized = 0;  // screen triangles set up (a clipped one may give more)

  // Fragments and pixels
  uint64_t fragments_rasterized = 0;    // pixel centres inside a triangle (fill rule)
  uint64_t fragments_depth_passed = 0;  // nearer than what the pixel had so far
  uint64_t pixels_covered = 0;
  uint64_t back_face_pixels = 0;  // covered, nearest is a back face, not a cap

  // User clip planes only
  uint64_t triangles_clip_tested = 0;      // classified against the clip planes
  uint64_t triangles_clip_rejected = 0;    // wholly on the removed side of some plane
  uint64_t triangles_clip_straddling = 0;  // need a per-fragment test
  uint64_t fragments_clip_tested = 0;
  uint64_t fragments_clip_discarded = 0;
  uint64_t cap_rays = 0;  // back-face pixels of closed objects ray-traced
  uint64_t cap_pixels = 0;

  uint64_t clip_plane_work() const {
    return triangles_clip_tested + triangles_clip_rejected + triangles_clip_straddling +
           fragments_clip_tested + fragments_clip_discarded + cap_rays + cap_pixels;
  }

  RasterStats& operator+=(const RasterStats& other);
};

}  // namespace soltex
