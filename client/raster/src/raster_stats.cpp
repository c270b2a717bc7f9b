#include "soltex/raster/raster_stats.h"

namespace soltex {

RasterStats& RasterStats::operator+=(const RasterStats& other) {
  triangles_in += other.triangles_in;
  triangles_invalid += other.triangles_invalid;
  triangles_degenerate += other.triangles_degenerate;
  triangles_culled += other.triangles_culled;
  triangles_back_face_culled += other.triangles_back_face_culled;
  triangles_clipped_near += other.triangles_clipped_near;
  triangles_clipped_guard_band += other.triangles_clipped_guard_band;
  triangles_rasterized += other.triangles_rasterized;
  fragments_rasterized += other.fragments_rasterized;
  fragments_depth_passed += other.fragments_depth_passed;
  pixels_covered += other.pixels_covered;
  back_face_pixels += other.back_face_pixels;
  triangles_clip_tested += other.triangles_clip_tested;
  triangles_clip_rejected += other.triangles_clip_rejected;
  triangles_clip_straddling += other.triangles_clip_straddling;
  fragments_clip_tested += other.fragments_clip_tested;
  fragments_clip_discarded += other.fragments_clip_discarded;
  cap_rays += other.cap_rays;
  cap_pixels += other.cap_pixels;
  return *this;
}

}  // namespace soltex
