#pragma once

#include <cstddef>
#include <functional>
#include <glm/vec2.hpp>
#include <memory>
#include <span>

#include "soltex/raster/edge_surfaces.h"
#include "soltex/raster/gbuffer.h"
#include "soltex/raster/raster_object.h"
#include "soltex/raster/raster_stats.h"
#include "soltex/raster/raster_view.h"

// The software rasterizer: objects in, a G-buffer out.
//
// Pipeline (details in src/rasterizer.cpp): vertices are transformed, triangles are clipped
// in homogeneous space (near plane, guard band), snapped to 1/256 pixel and binned into
// 64 x 64 tiles; threads take whole tiles, so no two threads write one pixel. Within a tile,
// triangles are drawn in submission order with integer edge functions and a top-left fill
// rule (a pixel centre on an edge shared by two triangles belongs to exactly one), and float
// depth where the strictly nearer fragment wins: on a tie the earlier triangle stays, so the
// image does not depend on the thread count. Attributes are resolved once per pixel, for the
// winner only, perspective-correct (attribute/w and 1/w interpolated).
//
// Both faces are drawn; GBuffer::kBackFace records which won. With user clip planes, a
// fragment on the removed side is discarded, and a pixel whose nearest remaining fragment is
// a back face of a closed object looks into the cut solid: it becomes a cap, at the point
// where its view ray enters the kept region (computed in double). Where several planes cut an
// object and the eye is on the kept side of some, a ray may cross the whole kept region inside
// the solid, its back faces all cut away behind the region (a slab, a box of planes): the
// nearest fragment past the region then tells, and the cap is drawn in front of whatever the
// pixel keeps behind it.
namespace soltex {

struct RasterOptions {
  int threads = 0;  // render threads including the caller's; 0: std::thread::hardware_concurrency
  bool count_coverage = false;  // fill GBuffer::coverage_count (debug, tests)
};

class Rasterizer {
 public:
  explicit Rasterizer(RasterOptions options = {});
  ~Rasterizer();
  Rasterizer(Rasterizer&&) noexcept;
  Rasterizer& operator=(Rasterizer&&) noexcept;
  Rasterizer(const Rasterizer&) = delete;
  Rasterizer& operator=(const Rasterizer&) = delete;

  int thread_count() const;

  // Draws the objects, in order, into `target` (resized to the view; every pixel written).
  // Throws std::invalid_argument for a bad view (size out of range, too many or malformed
  // clip planes) or a malformed mesh view (indices not a multiple of 3, normals neither empty
  // nor one per position), before drawing anything. Bad triangles are skipped and counted.
  // One render at a time per Rasterizer; the render itself uses thread_count() threads.
  RasterStats render(const RasterView& view, std::span<const RasterObject> objects,
                     GBuffer& target);

  // The same, calling after_tile(x0, y0, x1, y1, worker) for each tile of pixels [x0, x1) x
  // [y0, y1) as soon as that tile of `target` is final, on the render thread that drew it
  // (worker in [0, thread_count()), as for parallel_for): a pass over the G-buffer (shading)
  // can then read each tile while it is still in that core's cache. after_tile must touch no
  // pixel outside its tile.
  using TileCallback = std::function<void(int x0, int y0, int x1, int y1, int worker)>;
  RasterStats render(const RasterView& view, std::span<const RasterObject> objects, GBuffer& target,
                     const TileCallback& after_tile);

  // The same without a frame-sized G-buffer: each tile of pixels [x0, x1) x [y0, y1) is
  // resolved into a tile-sized G-buffer (kTileSize on a side) of the render thread's own and
  // handed at once to tile_done(tile, x0, y0, x1, y1, worker), where the frame's pixel (x, y)
  // is tile.index(x - x0, y - y0); the thread's next tile overwrites it. A tile no triangle
  // reaches is handed one shared, already empty G-buffer (read-only, like every tile). For a pass
  // that consumes each tile right away (shading): nothing frame-sized is written, read back, or
  // faulted in on the first frame. RasterOptions::count_coverage does not apply.
  static constexpr int kTileSize = 64;
  using TileGBufferCallback =
      std::function<void(const GBuffer& tile, int x0, int y0, int x1, int y1, int worker)>;
  RasterStats render_tiles(const RasterView& view, std::span<const RasterObject> objects,
                           const TileGBufferCallback& tile_done);

  // Edge anti-aliasing, from a render's tile callback (after_tile or tile_done), for the tile
  // just handed over and on the thread it names (`worker`), for a tile some triangle reached:
  // grid x grid samples (1..kMaxEdgeGrid per axis) of `pixels` (frame positions inside that
  // tile, each once) drawn again from the triangles nearest at the centres of each pixel and
  // its neighbours, and grouped by the surface they see (EdgeSurfaces). Throws
  // std::invalid_argument for a tile that is not the worker's last, a pixel outside it, or a
  // grid out of range.
  void sample_edges(int x0, int y0, std::span<const glm::ivec2> pixels, int grid, int worker,
                    EdgeSurfaces& out);

  // Runs task(index, worker) for every index in [0, count) on the render threads (the
  // caller's included; worker in [0, thread_count()) names the thread, for per-thread state),
  // handing indices out one at a time; returns when all are done. For the passes that follow a
  // render (shading the G-buffer), so that they reuse the same persistent threads. Not while a
  // render runs.
  void parallel_for(std::size_t count, const std::function<void(std::size_t, int)>& task);

 private:
  RasterStats draw(const RasterView& view, std::span<const RasterObject> objects,
                   GBuffer* frame_target, const TileCallback& after_tile,
                   const TileGBufferCallback& tile_done);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace soltex
