#include "tile_rasterizer.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <glm/geometric.hpp>
#include <limits>

#include "tile_kernels.h"

namespace soltex::raster_internal {

namespace {

constexpr float kFarDepth = 1.0f;
// Triangles spanning at least this many pixel columns of a tile are drawn by the vectorised
// loop.
constexpr int kVectorColumns = 8;

// Pixels [i, i + count) of one row: nothing drawn.
void write_empty(const GBufferPlanes& target, std::size_t i, std::size_t count) {
  std::fill_n(target.depth + i, count, std::numeric_limits<float>::infinity());
  std::fill_n(target.flags + i, count, uint8_t{0});
  std::fill_n(target.object_id + i, count, GBuffer::kNoObject);
  std::fill_n(target.texture_position + i, count, glm::dvec3(0.0));
  std::fill_n(target.normal + i, count, glm::vec3(0.0f));
  std::fill_n(target.footprint + i, count, 0.0f);
  std::fill_n(target.footprint_axis + i, count, glm::vec3(0.0f));
  std::fill_n(target.footprint_minor + i, count, 0.0f);
}

// GBuffer::flags of a pixel that sees the triangle's surface.
uint8_t surface_flags(const ScreenTriangle& t) {
  return static_cast<uint8_t>(GBuffer::kCovered | (t.back_face ? GBuffer::kBackFace : 0));
}

uint32_t object_id_of(const TileFrame& frame, const ScreenTriangle& t) {
  return frame.objects[t.object].source->object_id;
}

// Pixels of short runs (a fine mesh's), each with its own triangle, resolved together in
// lanes (interpolate_surfaces()): one short run's arithmetic alone would wait on its own
// divisions. Each lane's triangle data is gathered into arrays first.
struct SurfaceBatch {
  static constexpr int kCapacity = SurfaceLanes::kCapacity;
  template <typename T>
  using Lanes = std::array<T, kCapacity>;

  int count = 0;
  uint64_t back_faces = 0;  // pixels written, seen from behind
  Lanes<const ScreenTriangle*> triangle;
  Lanes<int> x, y;
  Lanes<std::size_t> index;
  Lanes<float> depth;
  SurfaceLanes lanes;

  void add(const ScreenTriangle* t, int px, int py, std::size_t i, float z) {
    // The lines past the first (which drawing read) hold what write() gathers.
    __builtin_prefetch(reinterpret_cast<const char*>(t) + 64);
    __builtin_prefetch(reinterpret_cast<const char*>(t) + 128);
    const auto l = static_cast<std::size_t>(count++);
    triangle[l] = t;
    x[l] = px;
    y[l] = py;
    index[l] = i;
    depth[l] = z;
  }

  void write(const TileFrame& frame, const GBufferPlanes& target) {
    const auto n = static_cast<std::size_t>(count);
    if (n == 0) return;
    // Per lane: vertex k's barycentric numerator (the edge function opposite it at the pixel
    // centre) and edge k's steps, already in float, so that interpolating is float arithmetic
    // alone (no 64-bit products or conversions) and runs in vector lanes; then vertex k's 1/w,
    // texture offset and normal.
    gather_surface_lanes(triangle.data(), x.data(), y.data(), n, lanes);
    interpolate_surfaces(lanes, n);
    write_lanes(frame, target, n);
    count = 0;
  }

 private:
  // The interpolated lanes to their pixels, through plane pointers of their own and with the
  // back faces counted in a register: a store through the flags' uint8_t* may alias the
  // target's pointers and the batch's back-face count, which would otherwise be loaded again
  // (and the count stored) for each pixel.
  void write_lanes(const TileFrame& frame, const GBufferPlanes& target, std::size_t n) {
    float* __restrict depth_plane = target.depth;
    uint8_t* __restrict flags = target.flags;
    uint32_t* __restrict object_id = target.object_id;
    glm::dvec3* __restrict position = target.texture_position;
    glm::vec3* __restrict normal = target.normal;
    float* __restrict footprint = target.footprint;
    glm::vec3* __restrict axis = target.footprint_axis;
    float* __restrict minor = target.footprint_minor;
    uint64_t back = 0;
    for (std::size_t l = 0; l < n; ++l) {
      const ScreenTriangle& t = *triangle[l];
      const std::size_t i = index[l];
      depth_plane[i] = depth[l];
      flags[i] = surface_flags(t);
      back += t.back_face ? 1 : 0;
      object_id[i] = object_id_of(frame, t);
      position[i] = t.texture_origin +
                    glm::dvec3(glm::vec3(lanes.offset_x[l], lanes.offset_y[l], lanes.offset_z[l]));
      normal[i] = glm::vec3(lanes.normal_x[l], lanes.normal_y[l], lanes.normal_z[l]);
      footprint[i] = lanes.footprint[l];
      const bool none = no_direction(lanes.minor[l]);
      axis[i] =
          none ? glm::vec3(0.0f) : glm::vec3(lanes.axis_x[l], lanes.axis_y[l], lanes.axis_z[l]);
      minor[i] = none ? lanes.footprint[l] : lanes.minor[l];
    }
    back_faces += back;
  }
};

// Runs shorter than this go pixel by pixel into SurfaceBatch: below it, a run's own set-up
// costs more than its pixels' share of a batch's gather.
constexpr int kLongRun = 4;

// Runs of pixels waiting to be resolved together (resolve_surface_runs(), dispatched once per
// batch rather than per run).
struct SurfaceRuns {
  static constexpr std::size_t kCapacity = 64;
  std::size_t count = 0;
  uint64_t back_faces = 0;  // pixels written, seen from behind
  std::array<SurfaceRun, kCapacity> runs;

  void add(const TileFrame& frame, const ScreenTriangle* t, int x, int y, int pixels, std::size_t i,
           const float* depth, const GBufferPlanes& target) {
    // Resolving reads all three of the triangle's lines; drawing's one may have left the cache.
    __builtin_prefetch(t);
    __builtin_prefetch(reinterpret_cast<const char*>(t) + 64);
    __builtin_prefetch(reinterpret_cast<const char*>(t) + 128);
    back_faces += t->back_face ? static_cast<uint64_t>(pixels) : 0;
    runs[count++] =
        SurfaceRun{t, x, y, pixels, i, depth, object_id_of(frame, *t), surface_flags(*t)};
    if (count == kCapacity) write(target);
  }

  void write(const GBufferPlanes& target) {
    if (count == 0) return;
    resolve_surface_runs({runs.data(), count}, target);
    count = 0;
  }
};

// One row of the drawn tile, from its first column.
struct TileRow {
  int y;
  std::ptrdiff_t start;  // where pixel (0, y) would be in the target
  const ScreenTriangle* const* winners;
  const float* depth;
  // TileRasterizer::beyond_winner_'s two slots' rows, or nulls.
  std::array<const ScreenTriangle* const*, 2> beyond;
};

// Resolving one tile, row by row: what its rows share (the batches of pixels waiting to be
// resolved, the cap rays of the current rows, the tracer's scratch) and its counts.
class TileResolve {
 public:
  // The tile's columns [x0, x1), from row y0 down. Not an aggregate: the batches and scratch
  // below stay uninitialised.
  TileResolve(const TileFrame& frame, GBuffer& gbuffer, int x0, int x1, int y0)
      : frame_(frame), target_(gbuffer), x0_(x0), x1_(x1), y0_(y0) {
    if (frame.caps != nullptr) rays_.begin(x0, y0);
  }

  // Rows in order, from y0 on.
  void resolve_row(const TileRow& row) {
    if (frame_.caps != nullptr && row.y > y0_) rays_.next_row();
    // Where runs start, found in vector lanes: a fine mesh's runs are a few pixels long, and
    // finding each run's end pixel by pixel mispredicted once per run.
    const uint64_t starts = run_starts(row.winners, x1_ - x0_);
    for (int x = x0_; x < x1_;) {
      // The run of pixels that see the same triangle, or none.
      const ScreenTriangle* winner = row.winners[x - x0_];
      const int offset = x - x0_ + 1;
      const uint64_t later = offset >= 64 ? 0 : starts >> offset << offset;
      const int end = later != 0 ? x0_ + std::countr_zero(later) : x1_;
      if (winner == nullptr) {
        if (row.beyond[0] != nullptr) {
          resolve_unkept_run(row, x, end);
        } else {
          // A run of empty pixels is written plane by plane (memset-like stores).
          write_empty(target_, static_cast<std::size_t>(row.start + x),
                      static_cast<std::size_t>(end - x));
        }
        x = end;
        continue;
      }
      // Only a frame with caps reads the winner here: its object and facing are on the
      // triangle's second cache line, which drawing did not load.
      const ObjectFrame* object =
          frame_.caps != nullptr ? &frame_.objects[winner->object] : nullptr;
      const bool own_cap = object != nullptr && winner->back_face && object->source->closed;
      if (row.beyond[0] != nullptr && any_beyond_solid(row, winner, x, end)) {
        resolve_beside_beyond_caps(row, winner, own_cap, x, end);
        x = end;
      } else if (own_cap) {
        x = resolve_cap_run(row, *object, winner, x, end);
      } else {
        resolve_surface_run(row, winner, x, end);
        x = end;
      }
    }
  }

  // Resolves what is still batched and adds the tile's counts to `stats`.
  void finish(RasterStats& stats) {
    surfaces_.write(target_);
    pixels_.write(frame_, target_);
    stats.pixels_covered += covered_;
    stats.back_face_pixels += surfaces_.back_faces + pixels_.back_faces;
    stats.cap_rays += cap_rays_;
    stats.cap_pixels += caps_;
  }

 private:
  // Pixels [x, end) of the row, which see `winner`'s surface.
  void resolve_surface_run(const TileRow& row, const ScreenTriangle* winner, int x, int end) {
    covered_ += static_cast<uint64_t>(end - x);
    if (end - x >= kLongRun) {
      surfaces_.add(frame_, winner, x, row.y, end - x, static_cast<std::size_t>(row.start + x),
                    row.depth + (x - x0_), target_);
      return;
    }
    for (; x < end; ++x) add_pixel(row, x);
  }

  void add_pixel(const TileRow& row, int x) {
    pixels_.add(row.winners[x - x0_], x, row.y, static_cast<std::size_t>(row.start + x),
                row.depth[x - x0_]);
    if (pixels_.count == SurfaceBatch::kCapacity) pixels_.write(frame_, target_);
  }

  // The back of a cut solid from pixel x on, whose winner is `winner`, a back face of
  // `object` (the same up to `end`): each pixel sees a cap, or (its ray entering no kept
  // region in front of the camera) the back face. A cap depends on the object alone, so the
  // run goes on over the object's other back faces and is traced in lanes. Returns its end.
  int resolve_cap_run(const TileRow& row, const ObjectFrame& object, const ScreenTriangle* winner,
                      int x, int end) {
    for (const ScreenTriangle* next = nullptr; end < x1_ &&
                                               (next = row.winners[end - x0_]) != nullptr &&
                                               next->back_face && next->object == winner->object;) {
      ++end;
    }
    covered_ += static_cast<uint64_t>(end - x);
    frame_.caps->trace_run(x, end, row.y, object.texture_from_world, object.source->clip_plane_mask,
                           rays_, ray_lanes_, cap_lanes_);
    cap_rays_ += static_cast<uint64_t>(end - x);
    const CapPixelLanes& cap = cap_lanes_;
    for (std::size_t k = 0; x < end; ++x, ++k) {
      if (cap.hit[k] == 0 ||
          !object.may_hold_cap(glm::dvec3(cap.texture_x[k], cap.texture_y[k], cap.texture_z[k]))) {
        add_pixel(row, x);
        continue;
      }
      ++caps_;
      const auto at = static_cast<std::size_t>(row.start + x);
      target_.depth[at] = cap.depth[k];
      target_.flags[at] = GBuffer::kCovered | GBuffer::kCap;
      target_.object_id[at] = object.source->object_id;
      target_.texture_position[at] =
          glm::dvec3(cap.texture_x[k], cap.texture_y[k], cap.texture_z[k]);
      target_.normal[at] = glm::vec3(cap.normal_x[k], cap.normal_y[k], cap.normal_z[k]);
      target_.footprint[at] = cap.footprint[k];
      target_.footprint_axis[at] = glm::vec3(0.0f);  // a cap's footprint has no direction
      target_.footprint_minor[at] = cap.footprint[k];
    }
    return end;
  }

  // A back face of a closed solid other than the pixel's kept fragment's, whose nearest
  // fragment along the ray it is among those kept or past the kept region (slot 0: the
  // nearest of all; slot 1: the nearest of another object): a cap of that solid may lie in
  // front of what the pixel keeps. Null when there is none.
  const ObjectFrame* beyond_solid(const TileRow& row, int slot, int x,
                                  const ScreenTriangle* kept) const {
    const ScreenTriangle* beyond = row.beyond[slot][x - x0_];
    if (beyond == nullptr || !beyond->back_face) return nullptr;
    if (kept != nullptr && beyond->object == kept->object) return nullptr;
    const ObjectFrame& object = frame_.objects[beyond->object];
    return object.source->closed ? &object : nullptr;
  }

  // Whether a pixel of [x, end) may see a cap of another solid than `winner`'s in front of
  // what it keeps (beyond_solid()).
  bool any_beyond_solid(const TileRow& row, const ScreenTriangle* winner, int x, int end) const {
    for (; x < end; ++x) {
      if (beyond_solid(row, 0, x, winner) != nullptr) return true;
      if (beyond_solid(row, 1, x, winner) != nullptr) return true;
    }
    return false;
  }

  // The nearest cap in front of `limit` (a window depth) of the solids beyond_solid() finds
  // for pixel x, written to `cap`; null when there is none.
  const ObjectFrame* nearest_beyond_cap(const TileRow& row, int x, const ScreenTriangle* kept,
                                        float limit, CapSample& cap) {
    const ObjectFrame* nearest = nullptr;
    for (int slot = 0; slot < 2; ++slot) {
      const ObjectFrame* solid = beyond_solid(row, slot, x, kept);
      if (solid == nullptr) continue;
      CapSample candidate;
      ++cap_rays_;
      if (frame_.caps->trace_through(x, row.y, solid->texture_from_world,
                                     solid->source->clip_plane_mask, rays_, candidate) &&
          candidate.depth < limit && solid->may_hold_cap(candidate.texture_position)) {
        limit = candidate.depth;
        cap = candidate;
        nearest = solid;
      }
    }
    return nearest;
  }

  // Pixels [x, end) of the row, whose kept fragment is `winner`, one at a time: each shows
  // what it would alone (the surface, or where `own_cap` the cap of `winner`'s solid), unless a
  // cap of another solid (beyond_solid()) lies in front of that.
  void resolve_beside_beyond_caps(const TileRow& row, const ScreenTriangle* winner, bool own_cap,
                                  int x, int end) {
    const ObjectFrame& object = frame_.objects[winner->object];
    covered_ += static_cast<uint64_t>(end - x);
    for (; x < end; ++x) {
      const auto at = static_cast<std::size_t>(row.start + x);
      CapSample own;
      bool own_hit = false;
      if (own_cap) {
        ++cap_rays_;
        own_hit = frame_.caps->trace(x, row.y, object.texture_from_world,
                                     object.source->clip_plane_mask, rays_, own) &&
                  object.may_hold_cap(own.texture_position);
      }
      CapSample cap;
      const float depth = own_hit ? own.depth : row.depth[x - x0_];
      if (const ObjectFrame* solid = nearest_beyond_cap(row, x, winner, depth, cap)) {
        ++caps_;
        write_cap_pixel(target_, at, solid->source->object_id, cap);
      } else if (own_hit) {
        ++caps_;
        write_cap_pixel(target_, at, object.source->object_id, own);
      } else {
        add_pixel(row, x);
      }
    }
  }

  // Pixels [x, end) of the row, where no fragment was kept: each is empty, or sees a cap
  // where the nearest fragment past the kept region is a back face of a closed solid (the
  // ray crossed the kept region inside it) and the ray enters and leaves that region.
  void resolve_unkept_run(const TileRow& row, int x, int end) {
    if (std::all_of(row.beyond[0] + (x - x0_), row.beyond[0] + (end - x0_),
                    [](const ScreenTriangle* t) { return t == nullptr; })) {
      write_empty(target_, static_cast<std::size_t>(row.start + x),
                  static_cast<std::size_t>(end - x));
      return;
    }
    for (; x < end; ++x) {
      const auto at = static_cast<std::size_t>(row.start + x);
      CapSample cap;
      if (const ObjectFrame* solid =
              nearest_beyond_cap(row, x, nullptr, std::numeric_limits<float>::infinity(), cap)) {
        ++caps_;
        ++covered_;
        write_cap_pixel(target_, at, solid->source->object_id, cap);
        continue;
      }
      write_empty(target_, at, 1);
    }
  }

  const TileFrame& frame_;
  const GBufferPlanes target_;
  const int x0_, x1_, y0_;
  uint64_t covered_ = 0, cap_rays_ = 0, caps_ = 0;
  CapRayRows rays_;          // of the current row and the next
  SurfaceRuns surfaces_;     // runs of kLongRun pixels or more
  SurfaceBatch pixels_;      // the pixels of shorter runs
  CapRayLanes ray_lanes_;    // scratch of trace_run(), uninitialised
  CapPixelLanes cap_lanes_;  // likewise
};

}  // namespace

void TileRasterizer::begin(int x0, int y0, int x1, int y1, uint32_t beyond_planes) {
  beyond_planes_ = beyond_planes;
  if (beyond_planes != 0) {
    for (int slot = 0; slot < 2; ++slot) {
      beyond_depth_[slot].fill(std::numeric_limits<float>::infinity());
      beyond_winner_[slot].fill(nullptr);
    }
  }
  x0_ = x0;
  y0_ = y0;
  x1_ = x1;
  y1_ = y1;
  depth_.fill(std::numeric_limits<float>::infinity());
  winner_.fill(nullptr);
}

void TileRasterizer::draw(const ScreenTriangle& t, std::span<const AffineForm> clip_forms,
                          uint32_t* coverage, int coverage_stride, RasterStats& stats) {
  // Edge functions at the first pixel centre, stepped exactly in integers. Written where the
  // kernels read them: copied into a SpanDraw, the 64-bit values were read back two to a
  // vector before their stores had landed, and waited for them.
  SpanDraw span;
  if (!span_of(t, x0_, y0_, x1_, y1_, span)) return;
  const int first_x = span.first_x, last_x = span.last_x;
  const int first_y = span.first_y, last_y = span.last_y;

  const float x0 = t.x0_pixels();
  const float y0 = t.y0_pixels();
  const AffineForm* forms = t.clip_mask != 0 ? clip_forms.data() + t.first_clip_form : nullptr;
  // A triangle of an object with beyond planes (all of whose triangles test their fragments).
  const bool tracked = (t.clip_mask & beyond_planes_) != 0;
  if (forms == nullptr && coverage == nullptr) {
    // A triangle at most 64 pixels across (most of a mesh's) is drawn in 32-bit lanes, a
    // larger one in 64-bit lanes where it spans enough of the tile's columns.
    if (fits_int32(t)) {
      raster_internal::draw_small(t, span, depth_.data(), winner_.data(), stats);
      return;
    }
    // A narrow one stays with the loop below: a vector loop's set-up per row would cost more
    // than the few pixels it covers.
    if (last_x - first_x + 1 >= kVectorColumns) {
      raster_internal::draw_unclipped(t, span, depth_.data(), winner_.data(), stats);
      return;
    }
  }
  std::array<int64_t, 3> row = span.row;
  const std::array<int64_t, 3> step_x = span.step_x, step_y = span.step_y;
  // Counted locally, added once: the counters must not cost a store per fragment.
  uint64_t rasterized = 0, depth_passed = 0, clip_tested = 0, clip_discarded = 0;
  for (int y = first_y; y <= last_y; ++y) {
    int64_t e0 = row[0], e1 = row[1], e2 = row[2];
    const float dy = static_cast<float>(y) + 0.5f - y0;
    const auto row_start = static_cast<std::ptrdiff_t>((y - y0_) * kTileSize);
    float* depth_row = depth_.data() + row_start;
    const ScreenTriangle** winner_row = winner_.data() + row_start;
    for (int x = first_x; x <= last_x; ++x, e0 += step_x[0], e1 += step_x[1], e2 += step_x[2]) {
      if ((e0 | e1 | e2) < 0) continue;
      ++rasterized;
      if (coverage != nullptr) {
        ++coverage[static_cast<std::size_t>(y) * static_cast<std::size_t>(coverage_stride) +
                   static_cast<std::size_t>(x)];
      }
      const float dx = static_cast<float>(x) + 0.5f - x0;
      const float depth = t.depth.at_vertex0 + t.depth.per_x * dx + t.depth.per_y * dy;
      const auto pixel = static_cast<std::size_t>(row_start + x - x0_);
      const bool nearer = depth < depth_row[x - x0_];
      const bool nearer_beyond = tracked && beyond_nearer(pixel, depth, t);
      if (!(nearer || nearer_beyond) || !(depth <= kFarDepth)) continue;
      if (forms != nullptr) {
        ++clip_tested;
        const uint32_t failed = failed_planes(t.clip_mask, forms, dx, dy);
        // Kept, or cut away past the kept region only: the nearest such fragment tells
        // whether the ray crossed the region inside the solid.
        if (nearer_beyond && (failed & ~beyond_planes_) == 0) keep_beyond(pixel, depth, t);
        if (failed != 0) {
          ++clip_discarded;
          continue;
        }
      }
      if (!nearer) continue;
      ++depth_passed;
      depth_row[x - x0_] = depth;
      winner_row[x - x0_] = &t;
    }
    row[0] += step_y[0];
    row[1] += step_y[1];
    row[2] += step_y[2];
  }
  stats.fragments_rasterized += rasterized;
  stats.fragments_depth_passed += depth_passed;
  stats.fragments_clip_tested += clip_tested;
  stats.fragments_clip_discarded += clip_discarded;
}

bool TileRasterizer::beyond_nearer(std::size_t pixel, float depth, const ScreenTriangle& t) const {
  if (depth < beyond_depth_[0][pixel]) return true;
  const ScreenTriangle* first = beyond_winner_[0][pixel];
  return first != nullptr && first->object != t.object && depth < beyond_depth_[1][pixel];
}

void TileRasterizer::keep_beyond(std::size_t pixel, float depth, const ScreenTriangle& t) {
  assert(beyond_nearer(pixel, depth, t));
  const ScreenTriangle* first = beyond_winner_[0][pixel];
  if (depth < beyond_depth_[0][pixel]) {
    // The nearest of another object than the new nearest: the old nearest, nearer than all
    // else, unless it is of the same object (slot 1 then stays as it is).
    if (first != nullptr && first->object != t.object) {
      beyond_depth_[1][pixel] = beyond_depth_[0][pixel];
      beyond_winner_[1][pixel] = first;
    }
    beyond_depth_[0][pixel] = depth;
    beyond_winner_[0][pixel] = &t;
    return;
  }
  beyond_depth_[1][pixel] = depth;
  beyond_winner_[1][pixel] = &t;
}

const ScreenTriangle* const* TileRasterizer::beyond_row(int slot, std::ptrdiff_t from) const {
  return beyond_planes_ != 0 ? beyond_winner_[static_cast<std::size_t>(slot)].data() + from
                             : nullptr;
}

void TileRasterizer::draw_bin(const ScreenTriangle* triangles, std::span<const uint32_t> items,
                              std::span<const AffineForm> clip_forms, uint32_t* coverage,
                              int coverage_stride, RasterStats& stats) {
  if (coverage != nullptr) {
    for (const uint32_t item : items) {
      draw(triangles[item], clip_forms, coverage, coverage_stride, stats);
    }
    return;
  }
  struct Other {
    TileRasterizer& tiles;
    std::span<const AffineForm> clip_forms;
    RasterStats& stats;
  } other{*this, clip_forms, stats};
  const BinDraw bin{triangles,
                    items.data(),
                    items.size(),
                    x0_,
                    y0_,
                    x1_,
                    y1_,
                    [](void* context, const ScreenTriangle& t) {
                      auto& o = *static_cast<Other*>(context);
                      o.tiles.draw(t, o.clip_forms, nullptr, 0, o.stats);
                    },
                    &other};
  raster_internal::draw_bin(bin, depth_.data(), winner_.data(), stats);
}

void TileRasterizer::resolve(const TileFrame& frame, GBuffer& gbuffer, int origin_x, int origin_y,
                             RasterStats& stats) const {
  const auto width = static_cast<std::ptrdiff_t>(gbuffer.width);
  static_assert(CapRayRows::kColumns >= kTileSize + 1);
  TileResolve tile(frame, gbuffer, x0_, x1_, y0_);
  for (int y = y0_; y < y1_; ++y) {
    const auto from = static_cast<std::ptrdiff_t>((y - y0_) * kTileSize);  // pixel (x0_, y)
    // Where pixel (0, y) would be in the target: x is added to it (x >= origin_x).
    const std::ptrdiff_t start = static_cast<std::ptrdiff_t>(y - origin_y) * width - origin_x;
    tile.resolve_row(TileRow{y, start, winner_.data() + from, depth_.data() + from,
                             beyond_row(0, from), beyond_row(1, from)});
  }
  tile.finish(stats);
}

}  // namespace soltex::raster_internal
