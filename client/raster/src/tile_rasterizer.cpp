#include "tile_rasterizer.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <glm/geometric.hpp>
#include <limits>

namespace soltex::raster_internal {

namespace {

constexpr float kFarDepth = 1.0f;

// Edge k is the edge opposite vertex k; its edge function, over the double area, is vertex
// k's barycentric weight.
struct Edge {
  int64_t ax, ay, bx, by;
};

std::array<Edge, 3> edges_of(const ScreenTriangle& t) {
  return {Edge{t.x[1], t.y[1], t.x[2], t.y[2]}, Edge{t.x[2], t.y[2], t.x[0], t.y[0]},
          Edge{t.x[0], t.y[0], t.x[1], t.y[1]}};
}

int64_t pixel_centre(int pixel) {
  return static_cast<int64_t>(pixel) * kSubpixelScale + kSubpixelScale / 2;
}

glm::vec3 unit_normal(const glm::vec3& sum, const glm::vec3& fallback) {
  const float length = glm::length(sum);
  if (length > 0.0f && std::isfinite(length)) return sum / length;
  const float fallback_length = glm::length(fallback);
  return fallback_length > 0.0f ? fallback / fallback_length : glm::vec3(0.0f, 0.0f, 1.0f);
}

// The G-buffer's planes as raw pointers, taken once per tile: a store through uint8_t* (the
// flags) may alias anything, so through the vectors every store would reload every data pointer.
struct GBufferPlanes {
  explicit GBufferPlanes(GBuffer& g)
      : depth(g.depth.data()),
        flags(g.flags.data()),
        object_id(g.object_id.data()),
        texture_position(g.texture_position.data()),
        normal(g.normal.data()),
        footprint(g.footprint.data()) {}

  float* depth;
  uint8_t* flags;
  uint32_t* object_id;
  glm::dvec3* texture_position;
  glm::vec3* normal;
  float* footprint;
};

// Pixels [i, i + count) of one row: nothing drawn.
void write_empty(const GBufferPlanes& target, std::size_t i, std::size_t count) {
  std::fill_n(target.depth + i, count, std::numeric_limits<float>::infinity());
  std::fill_n(target.flags + i, count, uint8_t{0});
  std::fill_n(target.object_id + i, count, GBuffer::kNoObject);
  std::fill_n(target.texture_position + i, count, glm::dvec3(0.0));
  std::fill_n(target.normal + i, count, glm::vec3(0.0f));
  std::fill_n(target.footprint + i, count, 0.0f);
}

// The winner's attributes at pixel (x, y), perspective-correct: with barycentric weights b
// (from the exact integer edge functions) and q = 1/w, P = sum(b q P) / sum(b q). Its
// derivative per pixel step is analytic: dP/dx = (d(sum b q P)/dx - P d(sum b q)/dx) / sum(b q),
// the weights' derivatives being constant over the triangle. Float suffices: P is an offset
// from the triangle's double origin, so float's error is relative to the triangle's size.
void write_surface(const ScreenTriangle& t, const ObjectFrame& object, float depth, int x, int y,
                   const GBufferPlanes& target, std::size_t i) {
  const std::array<Edge, 3> edges = edges_of(t);
  const int64_t px = pixel_centre(x);
  const int64_t py = pixel_centre(y);
  const float inv_area = 1.0f / static_cast<float>(t.double_area);
  const float step = static_cast<float>(kSubpixelScale) * inv_area;

  float q = 0.0f, dq_dx = 0.0f, dq_dy = 0.0f;
  glm::vec3 n(0.0f), dn_dx(0.0f), dn_dy(0.0f), normal_sum(0.0f);
  for (std::size_t k = 0; k < 3; ++k) {
    const Edge& e = edges[k];
    const float weight =
        static_cast<float>(edge_function(e.ax, e.ay, e.bx, e.by, px, py)) * inv_area;
    const float q_k = t.inv_w[k];
    const float weight_q = weight * q_k;
    const float weight_q_dx = -static_cast<float>(e.by - e.ay) * step * q_k;
    const float weight_q_dy = static_cast<float>(e.bx - e.ax) * step * q_k;
    q += weight_q;
    dq_dx += weight_q_dx;
    dq_dy += weight_q_dy;
    n += weight_q * t.texture_offset[k];
    dn_dx += weight_q_dx * t.texture_offset[k];
    dn_dy += weight_q_dy * t.texture_offset[k];
    normal_sum += weight_q * t.normal[k];
  }

  glm::vec3 offset(0.0f);
  float footprint = std::numeric_limits<float>::infinity();
  if (q > 0.0f && std::isfinite(q)) {
    const float inv_q = 1.0f / q;
    offset = n * inv_q;
    const glm::vec3 dp_dx = (dn_dx - offset * dq_dx) * inv_q;
    const glm::vec3 dp_dy = (dn_dy - offset * dq_dy) * inv_q;
    footprint = std::sqrt(std::max(glm::dot(dp_dx, dp_dx), glm::dot(dp_dy, dp_dy)));
    if (!std::isfinite(offset.x) || !std::isfinite(offset.y) || !std::isfinite(offset.z)) {
      offset = glm::vec3(0.0f);  // only with absurd inputs; stay at a vertex, never NaN
      footprint = std::numeric_limits<float>::infinity();
    }
  }

  target.depth[i] = depth;
  target.flags[i] = GBuffer::kCovered | (t.back_face ? GBuffer::kBackFace : 0);
  target.object_id[i] = object.source->object_id;
  target.texture_position[i] = t.texture_origin + glm::dvec3(offset);
  target.normal[i] = unit_normal(normal_sum, t.normal[0]);
  target.footprint[i] = std::isnan(footprint) ? std::numeric_limits<float>::infinity() : footprint;
}

}  // namespace

void TileRasterizer::begin(int x0, int y0, int x1, int y1) {
  x0_ = x0;
  y0_ = y0;
  x1_ = x1;
  y1_ = y1;
  depth_.fill(std::numeric_limits<float>::infinity());
  winner_.fill(nullptr);
}

void TileRasterizer::draw(const ScreenTriangle& t, std::span<const AffineForm> clip_forms,
                          uint32_t* coverage, int coverage_stride, RasterStats& stats) {
  const int first_x = std::max(t.min_px, x0_);
  const int last_x = std::min(t.max_px, x1_ - 1);
  const int first_y = std::max(t.min_py, y0_);
  const int last_y = std::min(t.max_py, y1_ - 1);
  if (first_x > last_x || first_y > last_y) return;

  // Edge functions at the first pixel centre, stepped exactly in integers. The top-left rule
  // as a bias: a centre on a top or left edge (value 0) is in, on any other edge it is out.
  const std::array<Edge, 3> edges = edges_of(t);
  std::array<int64_t, 3> row{}, step_x{}, step_y{};
  for (std::size_t k = 0; k < 3; ++k) {
    const Edge& e = edges[k];
    const int64_t bias = is_top_left(e.ax, e.ay, e.bx, e.by) ? 0 : -1;
    row[k] =
        edge_function(e.ax, e.ay, e.bx, e.by, pixel_centre(first_x), pixel_centre(first_y)) + bias;
    step_x[k] = -(e.by - e.ay) * kSubpixelScale;
    step_y[k] = (e.bx - e.ax) * kSubpixelScale;
  }

  const float x0 = t.x0_pixels();
  const float y0 = t.y0_pixels();
  const AffineForm* forms = t.clip_mask != 0 ? clip_forms.data() + t.first_clip_form : nullptr;
  if (forms == nullptr && coverage == nullptr) {
    draw_unclipped(t, first_x, last_x, first_y, last_y, row, step_x, step_y, stats);
    return;
  }
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
      if (!(depth < depth_row[x - x0_]) || depth > kFarDepth) continue;
      if (forms != nullptr) {
        ++clip_tested;
        bool kept = true;
        for (uint32_t mask = t.clip_mask; mask != 0; mask &= mask - 1) {
          const AffineForm& form = forms[std::countr_zero(mask)];
          if (form.at_vertex0 + form.per_x * dx + form.per_y * dy < 0.0f) {
            kept = false;
            break;
          }
        }
        if (!kept) {
          ++clip_discarded;
          continue;
        }
      }
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

void TileRasterizer::draw_unclipped(const ScreenTriangle& t, int first_x, int last_x, int first_y,
                                    int last_y, std::array<int64_t, 3> row,
                                    const std::array<int64_t, 3>& step_x,
                                    const std::array<int64_t, 3>& step_y, RasterStats& stats) {
  // The loop of draw() without clip forms and coverage counts, written with selects instead
  // of early exits so that it runs across the row in vector lanes: the same tests (edge
  // functions, depth, far plane) and the same float depth, so the same fragments win.
  const float x0 = t.x0_pixels();
  const float y0 = t.y0_pixels();
  const float at_vertex0 = t.depth.at_vertex0;
  const float per_x = t.depth.per_x;
  const float per_y = t.depth.per_y;
  const ScreenTriangle* const self = &t;
  const int count = last_x - first_x + 1;
  uint64_t rasterized = 0, depth_passed = 0;
  for (int y = first_y; y <= last_y; ++y) {
    const float dy = static_cast<float>(y) + 0.5f - y0;
    const float depth_y = per_y * dy;
    const auto row_start = static_cast<std::ptrdiff_t>((y - y0_) * kTileSize + (first_x - x0_));
    float* __restrict depth_row = depth_.data() + row_start;
    const ScreenTriangle** __restrict winner_row = winner_.data() + row_start;
    const int64_t r0 = row[0], r1 = row[1], r2 = row[2];
    const int64_t s0 = step_x[0], s1 = step_x[1], s2 = step_x[2];
    for (int k = 0; k < count; ++k) {
      const int64_t e0 = r0 + s0 * k, e1 = r1 + s1 * k, e2 = r2 + s2 * k;
      const bool inside = (e0 | e1 | e2) >= 0;
      const float dx = static_cast<float>(first_x + k) + 0.5f - x0;
      const float depth = (at_vertex0 + per_x * dx) + depth_y;
      const float old_depth = depth_row[k];
      const bool pass = inside & (depth < old_depth) & !(depth > kFarDepth);
      rasterized += inside ? 1 : 0;
      depth_passed += pass ? 1 : 0;
      depth_row[k] = pass ? depth : old_depth;
      winner_row[k] = pass ? self : winner_row[k];
    }
    row[0] += step_y[0];
    row[1] += step_y[1];
    row[2] += step_y[2];
  }
  stats.fragments_rasterized += rasterized;
  stats.fragments_depth_passed += depth_passed;
}

void TileRasterizer::resolve(const TileFrame& frame, GBuffer& gbuffer, RasterStats& stats) const {
  const GBufferPlanes target(gbuffer);
  const auto width = static_cast<std::size_t>(gbuffer.width);
  uint64_t covered = 0, back_faces = 0, cap_rays = 0, caps = 0;
  for (int y = y0_; y < y1_; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * width;
    const ScreenTriangle* const* winners = winner_.data() + (y - y0_) * kTileSize - x0_;
    for (int x = x0_; x < x1_; ++x) {
      const auto local = static_cast<std::size_t>((y - y0_) * kTileSize + (x - x0_));
      const std::size_t i = row + static_cast<std::size_t>(x);
      const ScreenTriangle* winner = winners[x];
      if (winner == nullptr) {
        // A run of empty pixels is written plane by plane (memset-like stores).
        int end = x + 1;
        while (end < x1_ && winners[end] == nullptr) ++end;
        write_empty(target, i, static_cast<std::size_t>(end - x));
        x = end - 1;
        continue;
      }
      ++covered;
      const ObjectFrame& object = frame.objects[winner->object];
      if (winner->back_face && frame.caps != nullptr && object.source->closed) {
        ++cap_rays;
        if (const std::optional<CapSample> cap = frame.caps->trace(
                x, y, object.texture_from_world, object.source->clip_plane_mask)) {
          ++caps;
          target.depth[i] = cap->depth;
          target.flags[i] = GBuffer::kCovered | GBuffer::kCap;
          target.object_id[i] = object.source->object_id;
          target.texture_position[i] = cap->texture_position;
          target.normal[i] = cap->normal;
          target.footprint[i] = cap->footprint;
          continue;
        }
      }
      if (winner->back_face) ++back_faces;
      write_surface(*winner, object, depth_[local], x, y, target, i);
    }
  }
  stats.pixels_covered += covered;
  stats.back_face_pixels += back_faces;
  stats.cap_rays += cap_rays;
  stats.cap_pixels += caps;
}

}  // namespace soltex::raster_internal
