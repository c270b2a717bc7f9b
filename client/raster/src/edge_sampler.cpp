#include "edge_sampler.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace soltex::raster_internal {

namespace {

constexpr float kFarDepth = 1.0f;

// Pixels [first, last] of a tile row (or rows of a column) as bits from the tile's edge.
uint64_t span_bits(int first, int last) {
  return (~uint64_t{0} >> (63 - (last - first))) << first;
}

bool finite(float v) {
  return std::fabs(v) <= std::numeric_limits<float>::max();
}

// The triangle's attributes at fixed-point point (px, py), perspective-correct, as
// TileRasterizer's resolve computes them at a pixel centre (the same formulas, one point at a
// time): P = sum(b q P) / sum(b q) with barycentric weights b and q = 1/w, the footprint from
// the analytic derivative per pixel step.
void write_triangle_surface(const ScreenTriangle& t, uint32_t object_id, int64_t px, int64_t py,
                            float depth, GBuffer& g, std::size_t i) {
  const float area = static_cast<float>(t.double_area);
  const float inv_area = 1.0f / area;
  const float step = static_cast<float>(kSubpixelScale) * inv_area;
  float sum_q = 0.0f, dq_dx = 0.0f, dq_dy = 0.0f;
  glm::vec3 s(0.0f), dx(0.0f), dy(0.0f), m(0.0f);
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t a = (k + 1) % 3, b = (k + 2) % 3;
    const int64_t ax = t.x[a], ay = t.y[a], bx = t.x[b], by = t.y[b];
    const float weight = static_cast<float>(edge_function(ax, ay, bx, by, px, py)) * inv_area;
    const float q = t.inv_w[k];
    const float weight_q = weight * q;
    const float weight_q_dx = -static_cast<float>(by - ay) * step * q;
    const float weight_q_dy = static_cast<float>(bx - ax) * step * q;
    sum_q += weight_q;
    dq_dx += weight_q_dx;
    dq_dy += weight_q_dy;
    s += weight_q * t.texture_offset[k];
    dx += weight_q_dx * t.texture_offset[k];
    dy += weight_q_dy * t.texture_offset[k];
    m += weight_q * t.normal[k];
  }
  const bool has_q = sum_q > 0.0f && finite(sum_q);
  const float inv_q = 1.0f / sum_q;
  const glm::vec3 c = s * inv_q;
  const glm::vec3 ddx = (dx - c * dq_dx) * inv_q;
  const glm::vec3 ddy = (dy - c * dq_dy) * inv_q;
  const float along_x = (ddx.x * ddx.x + ddx.y * ddx.y) + ddx.z * ddx.z;
  const float along_y = (ddy.x * ddy.x + ddy.y * ddy.y) + ddy.z * ddy.z;
  const bool y_longer = along_x < along_y;
  const float size = std::sqrt(y_longer ? along_y : along_x);
  const bool keep = has_q && finite(c.x) && finite(c.y) && finite(c.z);
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  const float kept_size = keep ? size : kInfinity;
  const float length = std::sqrt((m.x * m.x + m.y * m.y) + m.z * m.z);
  glm::vec3 normal(0.0f, 0.0f, 1.0f);
  if (length > 0.0f && finite(length)) {
    normal = m / length;
  } else if (const float first = std::sqrt(glm::dot(t.normal[0], t.normal[0])); first > 0.0f) {
    normal = t.normal[0] / first;
  }
  g.depth[i] = depth;
  g.flags[i] = GBuffer::kCovered | (t.back_face ? GBuffer::kBackFace : 0);
  g.object_id[i] = object_id;
  g.texture_position[i] = t.texture_origin + glm::dvec3(keep ? c : glm::vec3(0.0f));
  g.normal[i] = normal;
  const float footprint = std::isnan(kept_size) ? kInfinity : kept_size;
  g.footprint[i] = footprint;
  const float shorter = y_longer ? along_x : along_y;
  const bool directed = footprint < kInfinity && !std::isnan(shorter);
  g.footprint_axis[i] = directed ? (y_longer ? ddy : ddx) : glm::vec3(0.0f);
  g.footprint_minor[i] = directed ? std::sqrt(shorter) : footprint;
}

}  // namespace

glm::ivec2 EdgeSampler::sample_offset(int s, int grid) {
  const int i = s % grid, j = s / grid;
  const auto at = [grid](int k) {
    return static_cast<int>((2 * k + 1) * kSubpixelScale / (2 * static_cast<int64_t>(grid)));
  };
  return {at(i), at(j)};
}

void EdgeSampler::begin(int x0, int y0, int x1, int y1, std::span<const glm::ivec2> pixels,
                        int grid, uint32_t beyond_planes) {
  if (grid < 1 || grid > kMaxGrid) {
    throw std::invalid_argument("edge samples: grid must be 1.." + std::to_string(kMaxGrid) +
                                " per axis, got " + std::to_string(grid));
  }
  x0_ = x0;
  y0_ = y0;
  x1_ = x1;
  y1_ = y1;
  if (grid != grid_ || offsets_.empty()) {
    grid_ = grid;
    samples_ = grid * grid + 1;
    offsets_.clear();
    offsets_px_.clear();
    for (int s = 0; s < grid * grid; ++s) offsets_.push_back(sample_offset(s, grid));
    offsets_.emplace_back(kSubpixelScale / 2, kSubpixelScale / 2);  // the centre
    for (const glm::ivec2& o : offsets_) {
      offsets_px_.emplace_back(static_cast<float>(o.x) / static_cast<float>(kSubpixelScale),
                               static_cast<float>(o.y) / static_cast<float>(kSubpixelScale));
    }
  }
  row_mask_.fill(0);
  rows_ = 0;
  columns_ = 0;
  pixels_.assign(pixels.begin(), pixels.end());
  for (std::size_t p = 0; p < pixels_.size(); ++p) {
    const glm::ivec2 at = pixels_[p];
    if (at.x < x0 || at.x >= x1 || at.y < y0 || at.y >= y1) {
      throw std::invalid_argument("edge samples: pixel (" + std::to_string(at.x) + ", " +
                                  std::to_string(at.y) + ") is outside its tile");
    }
    const int lx = at.x - x0, ly = at.y - y0;
    row_mask_[static_cast<std::size_t>(ly)] |= uint64_t{1} << lx;
    rows_ |= uint64_t{1} << ly;
    columns_ |= uint64_t{1} << lx;
    slot_[static_cast<std::size_t>(ly * kTileSize + lx)] = static_cast<int32_t>(p);
  }
  const std::size_t n = pixels_.size() * static_cast<std::size_t>(samples_);
  depth_.assign(n, std::numeric_limits<float>::infinity());
  winner_.assign(n, nullptr);
  beyond_planes_ = beyond_planes;
  if (beyond_planes != 0) {
    beyond_depth_.assign(n, std::numeric_limits<float>::infinity());
    beyond_winner_.assign(n, nullptr);
  }
}

void EdgeSampler::draw(const ScreenTriangle& t, std::span<const AffineForm> clip_forms) {
  // Every pixel whose square the triangle's bounds reach (not only those whose centre they
  // reach): a sample off the centre may be inside where the centre is not.
  const int first_x = std::max(x0_, std::min({t.x[0], t.x[1], t.x[2]}) >> kSubpixelBits);
  const int last_x = std::min(x1_ - 1, std::max({t.x[0], t.x[1], t.x[2]}) >> kSubpixelBits);
  const int first_y = std::max(y0_, std::min({t.y[0], t.y[1], t.y[2]}) >> kSubpixelBits);
  const int last_y = std::min(y1_ - 1, std::max({t.y[0], t.y[1], t.y[2]}) >> kSubpixelBits);
  if (first_x > last_x || first_y > last_y) return;
  const uint64_t columns = span_bits(first_x - x0_, last_x - x0_);
  if ((columns & columns_) == 0 || (span_bits(first_y - y0_, last_y - y0_) & rows_) == 0) return;
  const AffineForm* forms = t.clip_mask != 0 ? clip_forms.data() + t.first_clip_form : nullptr;
  for (int y = first_y; y <= last_y; ++y) {
    for (uint64_t mask = row_mask_[static_cast<std::size_t>(y - y0_)] & columns; mask != 0;
         mask &= mask - 1) {
      const int x = x0_ + std::countr_zero(mask);
      const auto slot = static_cast<std::size_t>(
          slot_[static_cast<std::size_t>((y - y0_) * kTileSize + (x - x0_))]);
      draw_at(t, forms, x, y, slot);
    }
  }
}

void EdgeSampler::draw_at(const ScreenTriangle& t, const AffineForm* forms, int x, int y,
                          std::size_t slot) {
  // Edge functions at the pixel's corner, exact, with the top-left rule as a bias as in
  // drawing; sample (i, j) of the grid adds edge k's steps times its offsets, one product per
  // row and per column of the grid (the centre, last, its own).
  std::array<int64_t, 3> corner{}, ex{}, ey{};
  const int64_t low = offsets_.front().x, high = offsets_[static_cast<std::size_t>(grid_ - 1)].x;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t a = (k + 1) % 3, b = (k + 2) % 3;
    ex[k] = int64_t{t.x[b]} - t.x[a];
    ey[k] = int64_t{t.y[b]} - t.y[a];
    const int64_t bias = is_top_left(t.x[a], t.y[a], t.x[b], t.y[b]) ? 0 : -1;
    corner[k] = ex[k] * (int64_t{y} * kSubpixelScale - t.y[a]) -
                ey[k] * (int64_t{x} * kSubpixelScale - t.x[a]) + bias;
    // The largest value the edge function takes over the samples' box (it is affine): below
    // zero, every sample (the centre inside the box too) is outside.
    const int64_t most =
        corner[k] + std::max(ex[k] * low, ex[k] * high) - std::min(ey[k] * low, ey[k] * high);
    if (most < 0) return;
  }
  std::array<std::array<int64_t, kMaxGrid + 1>, 3> along_y{}, along_x{};
  for (std::size_t k = 0; k < 3; ++k) {
    for (int i = 0; i < grid_; ++i) {
      const int64_t at = offsets_[static_cast<std::size_t>(i)].x;  // row 0: the x offsets
      along_y[k][static_cast<std::size_t>(i)] = ex[k] * at;
      along_x[k][static_cast<std::size_t>(i)] = ey[k] * at;
    }
    along_y[k][static_cast<std::size_t>(grid_)] = ex[k] * (kSubpixelScale / 2);
    along_x[k][static_cast<std::size_t>(grid_)] = ey[k] * (kSubpixelScale / 2);
  }
  // Which samples are inside, as a mask: compares without branches, then only those samples
  // go on to depth (most of a pixel's samples are outside most triangles that reach it).
  const int grid_samples = grid_ * grid_;
  uint64_t inside = grid_samples == 64 ? ~uint64_t{0} : (uint64_t{1} << grid_samples) - 1;
  for (std::size_t k = 0; k < 3; ++k) {
    uint64_t mask = 0;
    for (int j = 0; j < grid_; ++j) {
      const int64_t row = corner[k] + along_y[k][static_cast<std::size_t>(j)];
      for (int i = 0; i < grid_; ++i) {
        const auto in = static_cast<uint64_t>(row - along_x[k][static_cast<std::size_t>(i)] >= 0);
        mask |= in << (j * grid_ + i);
      }
    }
    inside &= mask;
  }
  const auto centre = static_cast<std::size_t>(grid_);
  bool centre_inside = true;
  for (std::size_t k = 0; k < 3; ++k) {
    centre_inside &= corner[k] + along_y[k][centre] - along_x[k][centre] >= 0;
  }
  for (; inside != 0; inside &= inside - 1)
    test_sample(t, forms, x, y, slot, std::countr_zero(inside));
  if (centre_inside) test_sample(t, forms, x, y, slot, samples_ - 1);
}

void EdgeSampler::test_sample(const ScreenTriangle& t, const AffineForm* forms, int x, int y,
                              std::size_t slot, int s) {
  const glm::vec2 f = offsets_px_[static_cast<std::size_t>(s)];
  const float dx = static_cast<float>(x) + f.x - t.x0_pixels();
  const float dy = static_cast<float>(y) + f.y - t.y0_pixels();
  const float depth = t.depth.at_vertex0 + t.depth.per_x * dx + t.depth.per_y * dy;
  const std::size_t sample = slot_sample(slot, s);
  // As TileRasterizer::draw() (one slot past the kept region, not two).
  const bool tracked = (t.clip_mask & beyond_planes_) != 0;
  const bool nearer = depth < depth_[sample];
  const bool nearer_beyond = tracked && depth < beyond_depth_[sample];
  if (!(nearer || nearer_beyond) || !(depth <= kFarDepth)) return;
  if (forms != nullptr) {
    const uint32_t failed = failed_planes(t.clip_mask, forms, dx, dy);
    if (nearer_beyond && (failed & ~beyond_planes_) == 0) {
      beyond_depth_[sample] = depth;
      beyond_winner_[sample] = &t;
    }
    if (failed != 0) return;
  }
  if (!nearer) return;
  depth_[sample] = depth;
  winner_[sample] = &t;
}

const ScreenTriangle* EdgeSampler::seen(std::size_t slot, int s) const {
  const std::size_t sample = slot_sample(slot, s);
  if (winner_[sample] != nullptr || beyond_planes_ == 0) return winner_[sample];
  const ScreenTriangle* beyond = beyond_winner_[sample];
  return beyond != nullptr && beyond->back_face ? beyond : nullptr;
}

int EdgeSampler::group(std::size_t slot, std::array<Surface, EdgePixel::kExtraSurfaces>& extra,
                       EdgePixel& pixel) const {
  const ScreenTriangle* centre = seen(slot, samples_ - 1);
  int extra_count = 0;
  for (int s = 0; s + 1 < samples_; ++s) {
    const ScreenTriangle* w = seen(slot, s);
    if (w == centre) {
      ++pixel.centre;
      continue;
    }
    if (w == nullptr) {
      ++pixel.background;
      continue;
    }
    Surface* surface = nullptr;
    for (int j = 0; j < extra_count; ++j) {
      if (extra[static_cast<std::size_t>(j)].triangle == w)
        surface = &extra[static_cast<std::size_t>(j)];
    }
    if (surface == nullptr && extra_count < EdgePixel::kExtraSurfaces) {
      surface = &extra[static_cast<std::size_t>(extra_count++)];
      *surface = Surface{w};
    }
    if (surface == nullptr) {
      // More triangles than layers: the sample counts with a surface of the same object and
      // facing (most likely a neighbouring triangle of the same surface), else with the centre.
      for (int j = 0; j < extra_count && surface == nullptr; ++j) {
        const ScreenTriangle* other = extra[static_cast<std::size_t>(j)].triangle;
        if (other->object == w->object && other->back_face == w->back_face) {
          surface = &extra[static_cast<std::size_t>(j)];
        }
      }
      if (surface == nullptr) {
        ++pixel.centre;
        continue;
      }
      ++surface->count;  // its position stays out of the middle: another triangle's sample
      continue;
    }
    const glm::ivec2 o = offsets_[static_cast<std::size_t>(s)];
    ++surface->count;
    surface->sum_x += o.x;
    surface->sum_y += o.y;
  }
  return extra_count;
}

int EdgeSampler::nearest_sample(std::size_t slot, const Surface& surface) const {
  // The middle of the surface's own samples (count may include merged ones; the sums do not).
  int own = 0;
  for (int s = 0; s + 1 < samples_; ++s) own += seen(slot, s) == surface.triangle;
  const float mx = static_cast<float>(surface.sum_x) / static_cast<float>(own);
  const float my = static_cast<float>(surface.sum_y) / static_cast<float>(own);
  int best = -1;
  float best_distance = std::numeric_limits<float>::infinity();
  for (int s = 0; s + 1 < samples_; ++s) {
    if (seen(slot, s) != surface.triangle) continue;
    const glm::ivec2 o = offsets_[static_cast<std::size_t>(s)];
    const float ddx = static_cast<float>(o.x) - mx, ddy = static_cast<float>(o.y) - my;
    const float distance = ddx * ddx + ddy * ddy;
    if (distance < best_distance) {
      best_distance = distance;
      best = s;
    }
  }
  return best;
}

void EdgeSampler::resolve(const TileFrame& frame, EdgeSurfaces& out) const {
  for (GBuffer& layer : out.layers) {
    if (layer.width != kTileSize || layer.height != kTileSize) {
      layer.resize(kTileSize, kTileSize, false);
      std::fill(layer.flags.begin(), layer.flags.end(), uint8_t{0});
      std::fill(layer.object_id.begin(), layer.object_id.end(), GBuffer::kNoObject);
      continue;
    }
    // Only the last tile's edge pixels were written.
    for (const EdgePixel& p : out.pixels) {
      const std::size_t i = layer.index(p.x - out.x0, p.y - out.y0);
      layer.flags[i] = 0;
      layer.object_id[i] = GBuffer::kNoObject;
    }
  }
  out.pixels.clear();
  out.x0 = x0_;
  out.y0 = y0_;
  out.x1 = x1_;
  out.y1 = y1_;
  out.sample_count = samples_ - 1;
  CapRayRows cap_rays;  // one for the tile; each capped pixel starts it afresh
  for (std::size_t slot = 0; slot < pixels_.size(); ++slot) {
    EdgePixel pixel;
    pixel.x = pixels_[slot].x;
    pixel.y = pixels_[slot].y;
    std::array<Surface, EdgePixel::kExtraSurfaces> extra{};
    const int extra_count = group(slot, extra, pixel);
    if (pixel.centre == out.sample_count) continue;  // the centre speaks for the whole pixel
    for (int j = 0; j < extra_count; ++j) {
      const Surface& surface = extra[static_cast<std::size_t>(j)];
      pixel.extra[static_cast<std::size_t>(j)] = static_cast<uint16_t>(surface.count);
      GBuffer& layer = out.layers[static_cast<std::size_t>(j)];
      const std::size_t i = layer.index(pixel.x - x0_, pixel.y - y0_);
      const ScreenTriangle& t = *surface.triangle;
      const ObjectFrame& object = frame.objects[t.object];
      const int s = nearest_sample(slot, surface);
      // A back face seen past the kept region (seen()) is drawn only as its solid's cap.
      const bool past = depth_[slot_sample(slot, s)] == std::numeric_limits<float>::infinity();
      if (frame.caps != nullptr && t.back_face && object.source->closed) {
        cap_rays.begin(pixel.x, pixel.y);  // this pixel's ray and its neighbours', fresh
        CapSample cap;
        const bool traced =
            past ? frame.caps->trace_through(pixel.x, pixel.y, object.texture_from_world,
                                             object.source->clip_plane_mask, cap_rays, cap)
                 : frame.caps->trace(pixel.x, pixel.y, object.texture_from_world,
                                     object.source->clip_plane_mask, cap_rays, cap);
        // Two of the cap's footprints (its neighbours' distance) of slack: a pixel's width.
        const double slack = std::isfinite(cap.footprint) ? 2.0 * cap.footprint : 0.0;
        if (traced && object.may_hold_cap(cap.texture_position, slack)) {
          write_cap_pixel(layer, i, object.source->object_id, cap);
          continue;
        }
      }
      if (past) {
        pixel.background += pixel.extra[static_cast<std::size_t>(j)];
        pixel.extra[static_cast<std::size_t>(j)] = 0;
        continue;
      }
      const glm::ivec2 o = offsets_[static_cast<std::size_t>(s)];
      write_triangle_surface(t, object.source->object_id, int64_t{pixel.x} * kSubpixelScale + o.x,
                             int64_t{pixel.y} * kSubpixelScale + o.y, depth_[slot_sample(slot, s)],
                             layer, i);
    }
    out.pixels.push_back(pixel);
  }
}

}  // namespace soltex::raster_internal
