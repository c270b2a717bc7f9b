#include "triangle_setup.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <utility>

#include "saturating_cast.h"
#include "vertex_kernels.h"

namespace soltex::raster_internal {

// Left uninitialised but for what every triangle sets: setup() fills texture and normal, and
// plane_distance for the frame's clip planes (it is read for no others).
struct TriangleSetup::SourceTriangle {
  uint32_t object_index = 0;
  std::array<glm::dvec3, 3> texture;
  std::array<glm::vec3, 3> normal;
  std::array<std::array<float, RasterView::kMaxClipPlanes>, 3> plane_distance;
  uint32_t straddling_planes = 0;
};

// A triangle classify() kept, for finish(): its indices, vertices, the clip planes its
// vertices are outside of (ClipPlaneBit), and its source so far.
struct TriangleSetup::Classified {
  std::array<uint32_t, 3> index;
  std::array<const TransformedVertex*, 3> vertex;
  uint32_t outside = 0;
  SourceTriangle source;
};

namespace {

// Prefetches for writing the places of triangles appended to a chunk's storage, as far as its
// capacity goes (never past it: nothing is reserved here).
class WriteAhead {
 public:
  static constexpr std::size_t kTriangles = 4;  // ahead of the one being written

  WriteAhead(const ScreenTriangles& triangles, std::size_t count)
      : next_(triangles.data() + triangles.size()),
        count_(std::min(count, triangles.capacity() - triangles.size())) {
    for (std::size_t k = 0; k < kTriangles; ++k) prefetch(k);
  }

  // The place of the k-th triangle appended from here on.
  void prefetch(std::size_t k) const {
    if (k >= count_) return;
    const auto* lines = reinterpret_cast<const char*>(next_ + k);
    for (std::size_t line = 0; line < sizeof(ScreenTriangle); line += 64) {
      __builtin_prefetch(lines + line, 1);
    }
  }

 private:
  const ScreenTriangle* next_;
  std::size_t count_;
};

// The sides of the view volume a clip-space point is outside of, for trivial rejection.
uint32_t frustum_outcode(const glm::vec4& c) {
  return (c.x < -c.w ? 1u : 0u) | (c.x > c.w ? 2u : 0u) | (c.y < -c.w ? 4u : 0u) |
         (c.y > c.w ? 8u : 0u) | (c.z < -c.w ? 16u : 0u) | (c.z > c.w ? 32u : 0u);
}

// floor(value / kSubpixelScale): an arithmetic shift, the scale being a power of two (no
// 64-bit division per triangle corner).
int64_t floor_subpixels(int64_t value) {
  static_assert(kSubpixelScale == int64_t{1} << kSubpixelBits);
  return value >> kSubpixelBits;
}

// The first and last pixel whose centre (at fixed-point k * scale + scale / 2) lies in
// [low, high].
std::pair<int64_t, int64_t> pixel_centre_span(int64_t low, int64_t high) {
  constexpr int64_t kHalf = kSubpixelScale / 2;
  return {-floor_subpixels(-(low - kHalf)), floor_subpixels(high - kHalf)};
}

// The affine form through three values at three fixed-point positions.
AffineForm affine_form(const std::array<int64_t, 3>& x, const std::array<int64_t, 3>& y,
                       int64_t double_area, const std::array<double, 3>& value) {
  // Multiplying by the inverse of a power of two is exact: the same values as dividing.
  constexpr double kInverseScale = 1.0 / static_cast<double>(kSubpixelScale);
  const double x1 = static_cast<double>(x[1] - x[0]) * kInverseScale;
  const double y1 = static_cast<double>(y[1] - y[0]) * kInverseScale;
  const double x2 = static_cast<double>(x[2] - x[0]) * kInverseScale;
  const double y2 = static_cast<double>(y[2] - y[0]) * kInverseScale;
  const double area = static_cast<double>(double_area) * (kInverseScale * kInverseScale);
  const double d1 = value[1] - value[0];
  const double d2 = value[2] - value[0];
  return {to_float_saturated(value[0]), to_float_saturated((d1 * y2 - d2 * y1) / area),
          to_float_saturated((d2 * x1 - d1 * x2) / area)};
}

// Whether all three vertices carry a normal (the mesh's, transformed); otherwise the
// triangle is shaded with its face normal.
bool has_vertex_normals(const TransformedVertex& v0, const TransformedVertex& v1,
                        const TransformedVertex& v2) {
  return glm::dot(v0.normal, v0.normal) > 0.0f && glm::dot(v1.normal, v1.normal) > 0.0f &&
         glm::dot(v2.normal, v2.normal) > 0.0f;
}

// In double throughout: the cross product of float differences can pass float's range.
glm::vec3 face_normal(const ObjectFrame& object, uint32_t i0, uint32_t i1, uint32_t i2) {
  const auto& positions = object.source->mesh.positions;
  const glm::dvec3 p0(positions[i0]);
  const glm::dvec3 n = glm::dmat3(object.world_normal_from_object) *
                       glm::cross(glm::dvec3(positions[i1]) - p0, glm::dvec3(positions[i2]) - p0);
  const double length = glm::length(n);
  return length > 0.0 && std::isfinite(length) ? glm::vec3(n / length)
                                               : glm::vec3(0.0f, 0.0f, 1.0f);
}

}  // namespace

TriangleSetup::TriangleSetup(int width, int height, int clip_plane_count, bool keep_between_centres)
    : width_(width),
      height_(height),
      clip_plane_count_(clip_plane_count),
      keep_between_centres_(keep_between_centres),
      clip_planes_(
          1.0f + 2.0f * static_cast<float>(kGuardBandPixels) / static_cast<float>(width),
          1.0f + 2.0f * static_cast<float>(kGuardBandPixels) / static_cast<float>(height)) {}

TriangleSetup::ProjectedVertex TriangleSetup::project(const glm::vec4& clip) const {
  // In double, and from the vertex alone: a vertex shared by two triangles lands on the same
  // fixed-point position in both.
  const double inv_w = 1.0 / static_cast<double>(clip.w);
  const double ndc_x = static_cast<double>(clip.x) * inv_w;
  const double ndc_y = static_cast<double>(clip.y) * inv_w;
  const double ndc_z = static_cast<double>(clip.z) * inv_w;
  const double screen_x = (ndc_x * 0.5 + 0.5) * static_cast<double>(width_);
  const double screen_y = (0.5 - ndc_y * 0.5) * static_cast<double>(height_);
  return {static_cast<int32_t>(subpixel_position(screen_x)),
          static_cast<int32_t>(subpixel_position(screen_y)), ndc_z * 0.5 + 0.5,
          static_cast<float>(inv_w)};
}

void TriangleSetup::project_vertices(TransformedVertices& vertices, std::size_t begin,
                                     std::size_t end) const {
  for (std::size_t i = begin; i < end; ++i) {
    TransformedVertex& v = vertices.vertex[i];
    if (v.valid == 0) continue;
    // Once per vertex rather than once per triangle that uses it (about six).
    const glm::vec4& clip = vertices.clip[i];
    v.frustum_outside = static_cast<uint8_t>(frustum_outcode(clip));
    v.clip_outside = static_cast<uint8_t>(clip_planes_.outside(clip));
    // Only where setup() would project the vertex itself: inside the guard band.
    if (v.clip_outside == 0) v.set_screen(project(clip));
  }
}

void TriangleSetup::transform_and_project(const ObjectFrame& object, std::size_t begin,
                                          std::size_t end, TransformedVertices& vertices) const {
  raster_internal::transform_and_project(object, VertexProjection{width_, height_, &clip_planes_},
                                         begin, end, vertices);
}

void TriangleSetup::setup(const ObjectFrame& object, uint32_t object_index,
                          const TransformedVertices& vertices, uint32_t i0, uint32_t i1,
                          uint32_t i2, ScreenTriangles& triangles,
                          std::vector<AffineForm>& clip_forms, RasterStats& stats) const {
  Classified c;
  if (!classify(object, object_index, vertices, {i0, i1, i2}, c, stats)) return;
  finish(object, vertices, c, triangles, clip_forms, stats);
}

std::size_t TriangleSetup::setup_range(
    const ObjectFrame& object, uint32_t object_index, const TransformedVertices& vertices,
    std::span<const uint32_t> indices, std::size_t first, std::size_t end, SetupLanes& lanes,
    ScreenTriangles& triangles, std::vector<AffineForm>& clip_forms, RasterStats& stats) const {
  // Left over only if an earlier call threw (an allocation): stale triangles, never emitted.
  lanes.count = 0;
  std::size_t in_lanes = 0;
  for (std::size_t i = first; i < end; ++i) {
    Classified c;
    if (!classify(object, object_index, vertices,
                  {indices[3 * i], indices[3 * i + 1], indices[3 * i + 2]}, c, stats)) {
      continue;
    }
    const TransformedVertex &v0 = *c.vertex[0], &v1 = *c.vertex[1], &v2 = *c.vertex[2];
    if (c.outside == 0 && c.source.straddling_planes == 0 && has_vertex_normals(v0, v1, v2)) {
      lanes.add(v0, v1, v2, object_index);
      ++in_lanes;
      if (lanes.count == SetupLanes::kCapacity) flush(lanes, triangles, stats);
      continue;
    }
    // In order: what the lanes hold comes first.
    flush(lanes, triangles, stats);
    finish(object, vertices, c, triangles, clip_forms, stats);
  }
  flush(lanes, triangles, stats);
  return in_lanes;
}

void TriangleSetup::flush(SetupLanes& lanes, ScreenTriangles& triangles, RasterStats& stats) const {
  if (lanes.count == 0) return;
  set_up_lanes(lanes, width_, height_, keep_between_centres_);
  // Where the lanes' triangles will go, asked for ahead of their stores (while the storage
  // kept from earlier frames has room): the stores write whole lines last touched a frame
  // ago, and each waited for its line to be fetched.
  const WriteAhead ahead(triangles, lanes.count);
  for (std::size_t l = 0; l < lanes.count; ++l) {
    ahead.prefetch(l + WriteAhead::kTriangles);
    switch (lanes.outcome[l]) {
      case SetupLanes::kDegenerate:
        ++stats.triangles_degenerate;
        continue;
      case SetupLanes::kOffScreen:
        ++stats.triangles_culled;
        continue;
      default:
        break;
    }
    ScreenTriangle& t = triangles.emplace_back();
    for (std::size_t k = 0; k < 3; ++k) {
      t.x[k] = lanes.screen_x[k][l];
      t.y[k] = lanes.screen_y[k][l];
    }
    t.double_area = static_cast<int64_t>(lanes.double_area[l]);
    t.min_px = lanes.min_px[l];
    t.min_py = lanes.min_py[l];
    t.max_px = lanes.max_px[l];
    t.max_py = lanes.max_py[l];
    t.depth = {lanes.depth_at_vertex0[l], lanes.depth_per_x[l], lanes.depth_per_y[l]};
    t.clip_mask = 0;
    t.first_clip_form = 0;
    t.object = lanes.object[l];
    t.back_face = lanes.back_face[l] != 0;
    for (std::size_t k = 0; k < 3; ++k) {
      t.inv_w[k] = lanes.corner_inv_w[k][l];
      t.texture_offset[k] =
          glm::vec3(lanes.offset_x[k][l], lanes.offset_y[k][l], lanes.offset_z[k][l]);
      t.normal[k] = glm::vec3(lanes.normal_x[k][l], lanes.normal_y[k][l], lanes.normal_z[k][l]);
    }
    t.texture_origin = glm::dvec3(lanes.tx[0][l], lanes.ty[0][l], lanes.tz[0][l]);
    ++stats.triangles_rasterized;
  }
  lanes.count = 0;
}

bool TriangleSetup::classify(const ObjectFrame& object, uint32_t object_index,
                             const TransformedVertices& vertices,
                             const std::array<uint32_t, 3>& index, Classified& c,
                             RasterStats& stats) const {
  ++stats.triangles_in;
  const std::size_t vertex_count = object.source->mesh.positions.size();
  if (index[0] >= vertex_count || index[1] >= vertex_count || index[2] >= vertex_count) {
    ++stats.triangles_invalid;
    return false;
  }
  c.index = index;
  for (std::size_t k = 0; k < 3; ++k) {
    c.vertex[k] = &vertices.vertex[object.first_vertex + index[k]];
  }
  const TransformedVertex &v0 = *c.vertex[0], &v1 = *c.vertex[1], &v2 = *c.vertex[2];
  if (!v0.valid || !v1.valid || !v2.valid) {
    ++stats.triangles_invalid;
    return false;
  }
  if ((v0.frustum_outside & v1.frustum_outside & v2.frustum_outside) != 0) {
    ++stats.triangles_culled;
    return false;
  }
  c.outside = v0.clip_outside | v1.clip_outside | v2.clip_outside;
  if (c.outside == 0 && object.cull_back_faces) {
    // Projected already: the same orientation emit() would find, before any attribute work.
    if (edge_function(v0.x, v0.y, v1.x, v1.y, v2.x, v2.y) > 0) {
      ++stats.triangles_back_face_culled;
      return false;
    }
  }
  c.source.object_index = object_index;
  if (clip_plane_count_ > 0) {
    ++stats.triangles_clip_tested;
    const auto planes = static_cast<std::size_t>(clip_plane_count_);
    for (std::size_t j = 0; j < planes; ++j) {
      int removed = 0;
      for (std::size_t k = 0; k < 3; ++k) {
        const float distance =
            vertices.plane_distance[(object.first_vertex + index[k]) * planes + j];
        c.source.plane_distance[k][j] = distance;
        removed += distance < 0.0f ? 1 : 0;
      }
      if (removed == 3 && ((object.beyond_planes >> j) & 1u) == 0) {
        ++stats.triangles_clip_rejected;
        return false;
      }
      if (removed > 0) c.source.straddling_planes |= 1u << j;
    }
    // Each fragment of such an object is tested, so that the tile knows the nearest one along
    // each ray, kept or past the kept region (ObjectFrame::beyond_planes).
    c.source.straddling_planes |= object.beyond_planes;
    if (c.source.straddling_planes != 0) ++stats.triangles_clip_straddling;
  }
  return true;
}

void TriangleSetup::finish(const ObjectFrame& object, const TransformedVertices& vertices,
                           Classified& c, ScreenTriangles& triangles,
                           std::vector<AffineForm>& clip_forms, RasterStats& stats) const {
  const TransformedVertex &v0 = *c.vertex[0], &v1 = *c.vertex[1], &v2 = *c.vertex[2];
  const uint32_t outside = c.outside;
  SourceTriangle& source = c.source;
  const std::array<std::size_t, 3> at = {object.first_vertex + c.index[0],
                                         object.first_vertex + c.index[1],
                                         object.first_vertex + c.index[2]};
  ClipPolygon polygon;
  if (outside == 0) {
    // emit() reads an unclipped corner's weights only.
    polygon.vertices[0].weights = {1.0f, 0.0f, 0.0f};
    polygon.vertices[1].weights = {0.0f, 1.0f, 0.0f};
    polygon.vertices[2].weights = {0.0f, 0.0f, 1.0f};
    polygon.size = 3;
  } else {
    if ((outside & (kClipNear | kClipPositiveW)) != 0) ++stats.triangles_clipped_near;
    if ((outside & ~(kClipNear | kClipPositiveW)) != 0) ++stats.triangles_clipped_guard_band;
    polygon = clip_triangle(clip_planes_, outside, vertices.clip[at[0]], vertices.clip[at[1]],
                            vertices.clip[at[2]]);
    if (polygon.size < 3) {
      ++stats.triangles_culled;
      return;
    }
  }

  for (std::size_t k = 0; k < 3; ++k) source.texture[k] = c.vertex[k]->texture;
  if (has_vertex_normals(v0, v1, v2)) {
    for (std::size_t k = 0; k < 3; ++k) source.normal[k] = c.vertex[k]->normal;
  } else {
    source.normal.fill(face_normal(object, c.index[0], c.index[1], c.index[2]));
  }

  // An unclipped triangle uses its vertices' projections as they are. Each array is made
  // where it is filled: a ProjectedVertex is zeroed when made, and zeroing the clipped
  // polygon's nine per triangle was a tenth of set-up's time for a fine mesh.
  std::array<const ProjectedVertex*, ClipPolygon::kCapacity> projected;
  if (outside == 0) {
    const std::array<ProjectedVertex, 3> corners = {v0.screen(), v1.screen(), v2.screen()};
    for (std::size_t k = 0; k < 3; ++k) projected[k] = &corners[k];
    emit(source, polygon, projected, {0, 1, 2}, object.cull_back_faces, triangles, clip_forms,
         stats);
    return;
  }
  std::array<ProjectedVertex, ClipPolygon::kCapacity> clipped;
  for (int k = 0; k < polygon.size; ++k) {
    const auto index = static_cast<std::size_t>(k);
    clipped[index] = project(polygon.vertices[index].clip);
    projected[index] = &clipped[index];
  }
  for (int k = 1; k + 1 < polygon.size; ++k) {
    emit(source, polygon, projected, {0, k, k + 1}, object.cull_back_faces, triangles, clip_forms,
         stats);
  }
}

void TriangleSetup::emit(
    const SourceTriangle& source, const ClipPolygon& polygon,
    const std::array<const ProjectedVertex*, ClipPolygon::kCapacity>& projected,
    std::array<int, 3> corners, bool cull_back_faces, ScreenTriangles& triangles,
    std::vector<AffineForm>& clip_forms, RasterStats& stats) const {
  const auto vertex = [&](int k) -> const ProjectedVertex& {
    return *projected[static_cast<std::size_t>(corners[static_cast<std::size_t>(k)])];
  };
  int64_t double_area =
      edge_function(vertex(0).x, vertex(0).y, vertex(1).x, vertex(1).y, vertex(2).x, vertex(2).y);
  if (double_area == 0) {
    ++stats.triangles_degenerate;
    return;
  }
  // Counter-clockwise in NDC (y up) is clockwise on screen (y down): negative area here.
  const bool back_face = double_area > 0;
  if (back_face && cull_back_faces) {
    ++stats.triangles_back_face_culled;
    return;
  }
  if (!back_face) {
    std::swap(corners[1], corners[2]);
    double_area = -double_area;
  }

  std::array<int64_t, 3> x{}, y{};
  for (std::size_t k = 0; k < 3; ++k) {
    x[k] = vertex(static_cast<int>(k)).x;
    y[k] = vertex(static_cast<int>(k)).y;
  }
  const int64_t low_x = *std::min_element(x.begin(), x.end());
  const int64_t high_x = *std::max_element(x.begin(), x.end());
  const int64_t low_y = *std::min_element(y.begin(), y.end());
  const int64_t high_y = *std::max_element(y.begin(), y.end());
  auto [min_px, max_px] = pixel_centre_span(low_x, high_x);
  auto [min_py, max_py] = pixel_centre_span(low_y, high_y);
  if (keep_between_centres_ && (min_px > max_px || min_py > max_py)) {
    // Between pixel centres: the pixels it touches, for the edge samples inside them.
    min_px = floor_subpixels(low_x);
    max_px = floor_subpixels(high_x);
    min_py = floor_subpixels(low_y);
    max_py = floor_subpixels(high_y);
  }
  const auto first_px = static_cast<int32_t>(std::max<int64_t>(min_px, 0));
  const auto first_py = static_cast<int32_t>(std::max<int64_t>(min_py, 0));
  const auto last_px = static_cast<int32_t>(std::min<int64_t>(max_px, width_ - 1));
  const auto last_py = static_cast<int32_t>(std::min<int64_t>(max_py, height_ - 1));
  if (first_px > last_px || first_py > last_py) {
    ++stats.triangles_culled;  // off screen, or between pixel centres
    return;
  }
  std::array<double, 3> depth{};
  std::array<float, 3> inv_w{};
  std::array<glm::vec3, 3> texture_offset, normal;
  for (std::size_t k = 0; k < 3; ++k) {
    const int corner = corners[k];
    const ClipVertex& clip_vertex = polygon.vertices[static_cast<std::size_t>(corner)];
    const glm::dvec3 weights(clip_vertex.weights);
    depth[k] = vertex(static_cast<int>(k)).depth;
    inv_w[k] = vertex(static_cast<int>(k)).inv_w;  // 1 / clip_vertex.clip.w
    // Offsets from vertex 0's texture position, combined in double, small enough for float.
    const glm::dvec3 offset = weights.y * (source.texture[1] - source.texture[0]) +
                              weights.z * (source.texture[2] - source.texture[0]);
    texture_offset[k] = glm::vec3(to_float_saturated(offset.x), to_float_saturated(offset.y),
                                  to_float_saturated(offset.z));
    normal[k] = clip_vertex.weights.x * source.normal[0] +
                clip_vertex.weights.y * source.normal[1] + clip_vertex.weights.z * source.normal[2];
  }

  const auto first_clip_form = static_cast<uint32_t>(clip_forms.size());
  if (source.straddling_planes != 0) {
    for (std::size_t j = 0; j < static_cast<std::size_t>(clip_plane_count_); ++j) {
      // Signed distance / w is affine on screen, and w > 0 here, so its sign is the
      // distance's sign: no division per fragment.
      std::array<double, 3> distance_over_w{};
      for (std::size_t k = 0; k < 3; ++k) {
        const glm::vec3& weights = polygon.vertices[static_cast<std::size_t>(corners[k])].weights;
        const double distance = static_cast<double>(weights.x) * source.plane_distance[0][j] +
                                static_cast<double>(weights.y) * source.plane_distance[1][j] +
                                static_cast<double>(weights.z) * source.plane_distance[2][j];
        distance_over_w[k] = distance * static_cast<double>(inv_w[k]);
      }
      clip_forms.push_back(affine_form(x, y, double_area, distance_over_w));
    }
  }
  // Written in place, every field once: built on the stack and copied, the triangle's narrow
  // stores were read back 16 bytes at a time, each read waiting for them to drain.
  ScreenTriangle& t = triangles.emplace_back();
  for (std::size_t k = 0; k < 3; ++k) {
    t.x[k] = static_cast<int32_t>(x[k]);
    t.y[k] = static_cast<int32_t>(y[k]);
  }
  t.double_area = double_area;
  t.min_px = first_px;
  t.min_py = first_py;
  t.max_px = last_px;
  t.max_py = last_py;
  t.depth = affine_form(x, y, double_area, depth);
  t.clip_mask = source.straddling_planes;
  t.first_clip_form = source.straddling_planes != 0 ? first_clip_form : 0u;
  t.object = source.object_index;
  t.back_face = back_face;
  t.inv_w = inv_w;
  t.texture_offset = texture_offset;
  t.normal = normal;
  t.texture_origin = source.texture[0];
  ++stats.triangles_rasterized;
}

}  // namespace soltex::raster_internal
