// Degenerate and sliver triangles, and vertices behind the camera.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <optional>

#include "soltex/scene/builtin_meshes.h"
#include "stability_scene.h"

namespace soltex {
namespace {

constexpr int kWidth = 64;
constexpr int kHeight = 48;
const glm::dvec3 kEye(0.0, 0.0, 3.0);

// One mesh with every kind of awkward triangle, in view of a camera at kEye looking at the
// origin.
Mesh awkward_mesh() {
  Mesh mesh;
  mesh.positions = {
      // 0-2: a floor triangle at y = -1 reaching behind the camera (z = 12 > 3) and far ahead.
      {-6.0f, -1.0f, 12.0f},
      {6.0f, -1.0f, 12.0f},
      {0.0f, -1.0f, -30.0f},
      // 3-5: a sliver in z = 0, 3 units long and 0.004 (a tenth of a pixel) tall at one end.
      {-1.5f, 0.2f, 0.0f},
      {1.5f, 0.204f, 0.0f},
      {1.5f, 0.2f, 0.0f},
      // 6: a point; 7: on the line through 3 and 5.
      {0.5f, 0.5f, 0.0f},
      {0.0f, 0.2f, 0.0f},
      // 8-10: a triangle with a vertex in the camera's own plane (clip w = 0), off axis.
      {1.5f, -0.5f, 3.0f},
      {-0.5f, -0.6f, 0.0f},
      {0.5f, -0.3f, -1.0f},
      // 11-13: a sliver one millionth of a unit thick.
      {-1.0f, 0.6f, -0.5f},
      {1.0f, 0.6f, -0.5f},
      {1.0f, 0.600001f, -0.5f},
      // 14-16: entirely behind the camera.
      {-1.0f, 0.0f, 5.0f},
      {1.0f, 0.0f, 5.0f},
      {0.0f, 1.0f, 5.0f},
  };
  mesh.indices = {0, 1, 2, 3, 4, 5, 6, 6, 6, 3, 7, 5, 8, 9, 10, 11, 12, 13, 14, 15, 16};
  compute_vertex_normals(mesh);
  mesh.update_bounds();
  // Last, a triangle with an index past the positions: the rasterizer must skip it (the mesh
  // helpers above assume valid indices, so it is added after them).
  mesh.indices.insert(mesh.indices.end(), {0, 1, 999});
  return mesh;
}

TextureSpec rings() {
  TextureSpec spec;
  spec.pattern = RingsParams{0.05, 0.0, 1.0};
  return spec;
}

// The double-precision reference: the nearest triangle the ray through (px, py) meets in
// front of the near plane (Moller-Trumbore), and the hit point.
struct Hit {
  std::size_t triangle;
  glm::dvec3 point;
};

class MeshReference {
 public:
  MeshReference(const Mesh& mesh, const Camera& camera)
      : mesh_(mesh),
        inverse_vp_(glm::inverse(view_projection(camera, kWidth, kHeight))),
        eye_(camera.position),
        forward_(glm::normalize(camera.target - camera.position)),
        near_(camera.near) {}

  std::optional<Hit> hit(double px, double py) const {
    const glm::dvec4 h =
        inverse_vp_ * glm::dvec4(px / kWidth * 2.0 - 1.0, 1.0 - py / kHeight * 2.0, 1.0, 1.0);
    const glm::dvec3 d = glm::dvec3(h) / h.w - eye_;
    std::optional<Hit> nearest;
    double nearest_t = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < mesh_.triangle_count(); ++t) {
      const uint32_t* corner = &mesh_.indices[3 * t];
      if (std::max({corner[0], corner[1], corner[2]}) >= mesh_.positions.size()) continue;
      const glm::dvec3 a(mesh_.positions[mesh_.indices[3 * t]]);
      const glm::dvec3 b(mesh_.positions[mesh_.indices[3 * t + 1]]);
      const glm::dvec3 c(mesh_.positions[mesh_.indices[3 * t + 2]]);
      const glm::dvec3 e1 = b - a, e2 = c - a, q = glm::cross(d, e2);
      const double det = glm::dot(e1, q);
      if (det == 0.0) continue;
      const glm::dvec3 s = eye_ - a;
      const double u = glm::dot(s, q) / det;
      const glm::dvec3 r = glm::cross(s, e1);
      const double v = glm::dot(d, r) / det;
      const double distance = glm::dot(e2, r) / det;
      if (u < 0.0 || v < 0.0 || u + v > 1.0 || !(distance < nearest_t)) continue;
      const glm::dvec3 point = eye_ + distance * d;
      if (glm::dot(point - eye_, forward_) < near_) continue;  // clipped by the near plane
      nearest_t = distance;
      nearest = Hit{t, point};
    }
    return nearest;
  }

  // The hit when rays a sixteenth of a pixel around the centre all meet the same triangle (so
  // neither snapping nor the fill rule can change which triangle wins), with the footprint.
  std::optional<std::pair<Hit, double>> stable_hit(int x, int y) const {
    const auto centre = hit(x + 0.5, y + 0.5);
    if (!centre) return std::nullopt;
    for (double dx : {-1.0 / 16, 1.0 / 16}) {
      for (double dy : {-1.0 / 16, 1.0 / 16}) {
        const auto near = hit(x + 0.5 + dx, y + 0.5 + dy);
        if (!near || near->triangle != centre->triangle) return std::nullopt;
      }
    }
    const auto right = hit(x + 1.5, y + 0.5);
    const auto below = hit(x + 0.5, y + 1.5);
    double footprint = std::numeric_limits<double>::infinity();
    if (right && below && right->triangle == centre->triangle &&
        below->triangle == centre->triangle) {
      footprint = std::max(glm::length(right->point - centre->point),
                           glm::length(below->point - centre->point));
    }
    return std::make_pair(*centre, footprint);
  }

 private:
  const Mesh& mesh_;
  glm::dmat4 inverse_vp_;
  glm::dvec3 eye_;
  glm::dvec3 forward_;
  double near_;
};

// Expected: no crash; the zero-area, collinear and sub-pixel triangles skipped or drawn
// without harm; the bad index counted as invalid; the triangles through the camera's plane
// clipped at the near plane; a converged frame with no empty pixel; a defined G-buffer; and at
// every pixel whose triangle is unambiguous, the texture position within f / 20 + 2^-22 times
// the longest edge (43 units here: clipped vertices carry float barycentric weights) of the
// double-precision ray-triangle hit.
TEST(DegenerateTriangles, SliversAndVerticesBehindTheCameraStayDefined) {
  SceneObject object;
  object.name = "awkward";
  object.source = BoxShape{};
  object.mesh = std::make_shared<const Mesh>(awkward_mesh());
  object.material.texture = validated(rings());
  Scene scene = stability::make_scene({object}, kEye, {0.0, 0.0, 0.0}, kWidth, kHeight);
  scene.camera.far = 100.0;

  stability::LocalRender render;
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{7, 16, {}}, render.source);
  const stability::ConvergedFrame result = stability::render_until_converged(
      render.renderer, prepared, scene.camera, kWidth, kHeight, render.source);
  ASSERT_TRUE(result.converged);
  EXPECT_GT(result.frame.stats.covered_pixels, 0u);
  EXPECT_EQ(result.frame.stats.empty_pixels, 0u);

  RasterStats stats;
  const GBuffer g = stability::rasterize(prepared, scene.camera, kWidth, kHeight, &stats);
  EXPECT_TRUE(stability::gbuffer_defined(g));
  EXPECT_EQ(stats.triangles_in, 8u);
  EXPECT_EQ(stats.triangles_invalid, 1u);     // the index past the positions
  EXPECT_GE(stats.triangles_degenerate, 2u);  // the point and the collinear triple at least
  EXPECT_GE(stats.triangles_clipped_near, 2u);

  const MeshReference reference(*object.mesh, scene.camera);
  const double longest_edge = glm::length(glm::dvec3(0.0, 0.0, -30.0) - glm::dvec3(6.0, 0.0, 12.0));
  std::size_t compared = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t i = g.index(x, y);
      const auto hit = reference.stable_hit(x, y);
      if (!hit) continue;
      ASSERT_TRUE(g.covered(i)) << x << " " << y;
      ++compared;
      EXPECT_LE(glm::length(g.texture_position[i] - hit->first.point),
                hit->second / 20.0 + std::ldexp(longest_edge, -22))
          << x << " " << y << " triangle " << hit->first.triangle;
    }
  }
  EXPECT_GT(compared, static_cast<std::size_t>(kWidth * kHeight / 4));
}

// A vertex at 1e30 (finite in float) and one at 1e38 (whose clip coordinates overflow to
// infinity). Expected: the first triangle is clipped to the guard band and drawn with finite
// positions (their accuracy is float's relative to a 1e30-unit triangle, so it is not
// checked), the second is refused as invalid, and nothing crashes.
TEST(DegenerateTriangles, HugeFiniteVerticesAreClippedOrRefused) {
  Mesh mesh;
  mesh.positions = {{1e30f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, -1.0f, 0.0f},
                    {3e38f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.5f}, {0.0f, -1.0f, 0.5f}};
  mesh.indices = {0, 1, 2, 3, 4, 5};
  compute_vertex_normals(mesh);
  mesh.update_bounds();
  SceneObject object;
  object.name = "huge";
  object.source = BoxShape{};
  object.mesh = std::make_shared<const Mesh>(mesh);
  object.material.texture = validated(rings());
  object.material.volume.box = VolumeRequest::Box{glm::dvec3(-2.0), glm::dvec3(2.0)};
  const Scene scene = stability::make_scene({object}, kEye, {0.0, 0.0, 0.0}, kWidth, kHeight);
  stability::LocalRender render;
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{6, 16, {}}, render.source);
  const stability::ConvergedFrame result = stability::render_until_converged(
      render.renderer, prepared, scene.camera, kWidth, kHeight, render.source);
  ASSERT_TRUE(result.converged);
  RasterStats stats;
  const GBuffer g = stability::rasterize(prepared, scene.camera, kWidth, kHeight, &stats);
  EXPECT_TRUE(stability::gbuffer_defined(g));
  EXPECT_EQ(stats.triangles_invalid, 1u);
  EXPECT_GT(stats.pixels_covered, 0u);
}

}  // namespace
}  // namespace soltex
