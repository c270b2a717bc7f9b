#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "raster_test_scenes.h"
#include "soltex/raster/rasterizer.h"

namespace soltex {
namespace {

using raster_test::Mesh;

constexpr int kWidth = 160;
constexpr int kHeight = 120;

RasterStats render_one(Rasterizer& rasterizer, const RasterView& view, const RasterObject& object,
                       GBuffer& g) {
  return rasterizer.render(view, std::span<const RasterObject>(&object, 1), g);
}

// Is (x, z) inside the triangle (a, b, c) of the xz plane by more than `margin`?
// Returns +1 inside, -1 outside, 0 within the margin of an edge.
int side_of_triangle_xz(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b,
                        const glm::dvec2& c, double margin) {
  const glm::dvec2 corners[3] = {a, b, c};
  double nearest = 1e300;
  int outside = 0;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2 u = corners[k], v = corners[(k + 1) % 3];
    const double side =
        ((v.x - u.x) * (p.y - u.y) - (v.y - u.y) * (p.x - u.x)) / glm::length(v - u);
    // The corners are counter-clockwise in (x, z): inside is side > 0.
    nearest = std::min(nearest, std::abs(side));
    outside += side < 0.0;
  }
  if (nearest < margin) return 0;
  return outside == 0 ? 1 : -1;
}

// --- Near plane -----------------------------------------------------------------------------

TEST(NearPlaneClipping, TriangleWithAVertexBehindTheCameraShowsItsVisiblePart) {
  Mesh floor;
  // In (x, z), counter-clockwise: the third vertex is 5 units behind the camera.
  floor.positions = {{-3.0f, -1.0f, -6.0f}, {0.0f, -1.0f, 5.0f}, {3.0f, -1.0f, -6.0f}};
  floor.add_triangle(0, 1, 2);
  RasterObject object;
  object.mesh = floor.view();
  const glm::mat4 view_projection =
      raster_test::perspective_look_at({0, 0, 0}, {0, 0, -1}, kWidth, kHeight);
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  const RasterStats stats =
      render_one(rasterizer, {kWidth, kHeight, view_projection, {}}, object, g);
  EXPECT_EQ(stats.triangles_clipped_near, 1u);
  EXPECT_GE(stats.triangles_rasterized, 1u);
  EXPECT_TRUE(raster_test::all_values_sane(g));

  int covered = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t i = g.index(x, y);
      const auto hit = raster_test::hit_plane(
          raster_test::pixel_ray(view_projection, kWidth, kHeight, x, y), {0, 1, 0, 1});
      const int side =
          hit ? side_of_triangle_xz({hit->x, hit->z}, {-3, -6}, {3, -6}, {0, 5}, 1e-3) : -1;
      if (side == 0) continue;
      ASSERT_EQ(g.covered(i), side > 0) << "pixel " << x << "," << y;
      if (!g.covered(i)) continue;
      ++covered;
      EXPECT_NEAR(g.texture_position[i].y, -1.0, 1e-5);
      EXPECT_LE(glm::length(g.texture_position[i] - *hit), 0.01 * g.footprint[i] + 1e-5);
    }
  }
  EXPECT_GT(covered, kWidth * kHeight / 4);
}

TEST(NearPlaneClipping, VerticesAtAndBehindTheEyeNeverBlowUp) {
  Mesh mesh;
  mesh.positions = {{0.0f, 0.0f, 0.0f},  // at the eye: w = 0
                    {1.0f, -1.0f, -3.0f},
                    {-1.0f, -1.0f, -3.0f},
                    {0.0f, 1.0f, 2.0f},      // behind
                    {0.0f, 1e-7f, -1e-7f}};  // just in front of the eye, inside the near plane
  mesh.add_triangle(0, 1, 2);
  mesh.add_triangle(3, 2, 1);
  mesh.add_triangle(4, 1, 2);
  RasterObject object;
  object.mesh = mesh.view();
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  const RasterStats stats =
      render_one(rasterizer,
                 {kWidth,
                  kHeight,
                  raster_test::perspective_look_at({0, 0, 0}, {0, 0, -1}, kWidth, kHeight),
                  {}},
                 object, g);
  EXPECT_EQ(stats.triangles_clipped_near, 3u);
  EXPECT_GT(stats.pixels_covered, 0u);
  EXPECT_TRUE(raster_test::all_values_sane(g));
}

TEST(NearPlaneClipping, ATinyTriangleJustPastATinyNearPlaneIsDrawn) {
  // A scene may put its near plane at 1e-6: a triangle 5e-6 ahead is in view and must not be
  // cut away by the guard that keeps w positive for degenerate projections.
  Mesh mesh;
  mesh.positions = {{-1e-5f, -1e-5f, -5e-6f}, {1e-5f, -1e-5f, -5e-6f}, {0.0f, 1e-5f, -5e-6f}};
  mesh.add_triangle(0, 1, 2);
  RasterObject object;
  object.mesh = mesh.view();
  Rasterizer rasterizer({.threads = 1});
  GBuffer g;
  const glm::mat4 view_projection =
      raster_test::perspective_look_at({0, 0, 0}, {0, 0, -1}, kWidth, kHeight, 60.0f, 1e-6f, 1e-3f);
  const RasterStats stats =
      render_one(rasterizer, {kWidth, kHeight, view_projection, {}}, object, g);
  EXPECT_GT(stats.pixels_covered, static_cast<uint64_t>(kWidth * kHeight / 4));
  EXPECT_TRUE(raster_test::all_values_sane(g));
}

TEST(NearPlaneClipping, TriangleWhollyBehindTheCameraIsCulled) {
  Mesh mesh;
  mesh.positions = {{-1.0f, -1.0f, 2.0f}, {1.0f, -1.0f, 2.0f}, {0.0f, 1.0f, 3.0f}};
  mesh.add_triangle(0, 1, 2);
  RasterObject object;
  object.mesh = mesh.view();
  Rasterizer rasterizer({.threads = 1});
  GBuffer g;
  const RasterStats stats =
      render_one(rasterizer,
                 {kWidth,
                  kHeight,
                  raster_test::perspective_look_at({0, 0, 0}, {0, 0, -1}, kWidth, kHeight),
                  {}},
                 object, g);
  EXPECT_EQ(stats.triangles_culled, 1u);
  EXPECT_EQ(stats.pixels_covered, 0u);
}

// A jittered floor grid running from far ahead to behind the camera: the near-plane cuts of
// shared edges must meet exactly, leaving no pixel twice and none out.
TEST(NearPlaneClipping, ClippedGridStaysWatertight) {
  std::mt19937 random(11);
  std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
  const int columns = 16, rows = 32;
  Mesh grid;
  for (int j = 0; j <= rows; ++j) {
    for (int i = 0; i <= columns; ++i) {
      const bool border = i == 0 || j == 0 || i == columns || j == rows;
      const float u = static_cast<float>(i) + (border ? 0.0f : jitter(random));
      const float v = static_cast<float>(j) + (border ? 0.0f : jitter(random));
      grid.positions.push_back({u / columns * 8.0f - 4.0f, -1.0f, v / rows * 16.0f - 10.0f});
    }
  }
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < columns; ++i) {
      const auto v = [columns](int a, int b) {
        return static_cast<uint32_t>(b * (columns + 1) + a);
      };
      grid.add_triangle(v(i, j), v(i, j + 1), v(i + 1, j + 1));
      grid.add_triangle(v(i, j), v(i + 1, j + 1), v(i + 1, j));
    }
  }
  // 0.2 above the floor, looking 30 degrees down, near plane at 0.5: the floor crosses the
  // near plane inside the view.
  const glm::mat4 view_projection = raster_test::perspective_look_at(
      {0.3f, -0.8f, 0.0f}, {0.1f, -1.377f, -1.0f}, kWidth, kHeight, 70.0f, 0.5f, 100.0f);
  Rasterizer rasterizer({.threads = 2, .count_coverage = true});
  GBuffer g;
  const RasterStats stats =
      render_one(rasterizer, {kWidth, kHeight, view_projection, {}}, RasterObject{grid.view()}, g);
  EXPECT_GT(stats.triangles_clipped_near, 0u);
  int checked = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const uint32_t count = g.coverage_count[g.index(x, y)];
      ASSERT_LE(count, 1u) << "pixel " << x << "," << y;
      const auto hit = raster_test::hit_plane(
          raster_test::pixel_ray(view_projection, kWidth, kHeight, x, y), {0, 1, 0, 1});
      if (hit && std::abs(hit->x) < 3.95 && hit->z > -9.95 && hit->z < 5.95) {
        ASSERT_EQ(count, 1u) << "hole at " << x << "," << y;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, kWidth * kHeight / 4);
  EXPECT_TRUE(raster_test::all_values_sane(g));
}

// A quad hundreds of thousands of pixels wide: clipped to the guard band, it still covers
// every pixel once.
TEST(GuardBandClipping, HugeQuadCoversTheScreenOnce) {
  Mesh quad;
  quad.positions = {
      {-1e4f, -1e4f, -1.0f}, {1e4f, -1e4f, -1.0f}, {1e4f, 1e4f, -1.0f}, {-1e4f, 1e4f, -1.0f}};
  quad.add_triangle(0, 1, 2);
  quad.add_triangle(0, 2, 3);
  Rasterizer rasterizer({.threads = 2, .count_coverage = true});
  GBuffer g;
  const RasterStats stats =
      render_one(rasterizer,
                 {kWidth,
                  kHeight,
                  raster_test::perspective_look_at({0, 0, 0}, {0, 0, -1}, kWidth, kHeight),
                  {}},
                 RasterObject{quad.view()}, g);
  EXPECT_EQ(stats.triangles_clipped_guard_band, 2u);
  for (std::size_t i = 0; i < g.pixel_count(); ++i) ASSERT_EQ(g.coverage_count[i], 1u) << i;
  EXPECT_TRUE(raster_test::all_values_sane(g));
}

// --- User clip planes and caps ---------------------------------------------------------------

const Mesh& unit_sphere() {
  static const Mesh sphere = raster_test::uv_sphere(64, 128);
  return sphere;
}

TEST(ClipPlanes, WithoutClipPlanesNoClipWorkIsDone) {
  RasterObject object{unit_sphere().view()};
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  // From outside, and from inside (where only back faces are seen).
  for (const glm::vec3 eye : {glm::vec3(0.5f, 1.0f, 3.0f), glm::vec3(0.1f, 0.0f, 0.2f)}) {
    const RasterStats stats = render_one(
        rasterizer,
        {kWidth, kHeight, raster_test::perspective_look_at(eye, {0, 0, -1}, kWidth, kHeight), {}},
        object, g);
    EXPECT_GT(stats.pixels_covered, 0u);
    EXPECT_EQ(stats.triangles_clip_tested, 0u);
    EXPECT_EQ(stats.fragments_clip_tested, 0u);
    EXPECT_EQ(stats.cap_rays, 0u);
    EXPECT_EQ(stats.cap_pixels, 0u);
    EXPECT_EQ(stats.clip_plane_work(), 0u);
    for (std::size_t i = 0; i < g.pixel_count(); ++i) EXPECT_FALSE(g.is_cap(i));
  }
}

// The plane z = 0 keeping z <= 0, seen from the front: the whole visible sphere is the cap.
TEST(ClipPlanes, SphereCutThroughItsCentreShowsTheCutFace) {
  RasterObject object{unit_sphere().view()};
  const std::vector<glm::dvec4> planes = {{0.0, 0.0, -1.0, 0.0}};
  const glm::mat4 view_projection =
      raster_test::perspective_look_at({0, 0, 3}, {0, 0, 0}, kWidth, kHeight);
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  const RasterStats stats =
      render_one(rasterizer, {kWidth, kHeight, view_projection, planes}, object, g);
  EXPECT_GT(stats.fragments_clip_discarded, 0u);
  EXPECT_EQ(stats.back_face_pixels, 0u);
  int caps = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t i = g.index(x, y);
      const auto hit = raster_test::hit_plane(
          raster_test::pixel_ray(view_projection, kWidth, kHeight, x, y), planes[0]);
      ASSERT_TRUE(hit.has_value());
      const double radius = glm::length(glm::dvec2(hit->x, hit->y));
      if (radius < 0.98) {
        ASSERT_TRUE(g.is_cap(i)) << "pixel " << x << "," << y;
      }
      if (radius > 1.01) {
        ASSERT_FALSE(g.covered(i)) << "pixel " << x << "," << y;
      }
      if (!g.is_cap(i)) continue;
      ++caps;
      EXPECT_TRUE(g.covered(i));
      EXPECT_FALSE(g.back_face(i));
      EXPECT_NEAR(g.texture_position[i].z, 0.0, 1e-12);
      EXPECT_LE(glm::length(g.texture_position[i] - *hit), 1e-9);
      EXPECT_EQ(g.normal[i], glm::vec3(0.0f, 0.0f, 1.0f));
      EXPECT_GT(g.footprint[i], 0.0f);
      EXPECT_TRUE(std::isfinite(g.footprint[i]));
    }
  }
  EXPECT_EQ(stats.cap_pixels, static_cast<uint64_t>(caps));
  EXPECT_GT(caps, 1500);
  EXPECT_TRUE(raster_test::all_values_sane(g));
}

// A box missing its +x face, cut at z = 0 and seen through the hole: the view meets the
// inside of the far walls, which a closed solid would show as a cap where the ray crossed the
// plane; here that crossing lies outside the box. Given the mesh's bounds, no cap is drawn
// outside them: those pixels show the back faces instead.
TEST(ClipPlanes, NoCapOutsideTheMeshsBounds) {
  raster_test::Mesh open_box = raster_test::box({1.0f, 1.0f, 1.0f});
  open_box.indices.erase(open_box.indices.begin() + 6, open_box.indices.begin() + 12);  // +x
  const std::vector<glm::dvec4> planes = {{0.0, 0.0, -1.0, 0.0}};
  const glm::mat4 view_projection =
      raster_test::perspective_look_at({3.0f, 0.6f, 2.5f}, {0, 0, 0}, kWidth, kHeight);
  Rasterizer rasterizer({.threads = 2});
  const auto outside_caps = [&](const RasterObject& object, uint64_t& caps) {
    GBuffer g;
    caps = render_one(rasterizer, {kWidth, kHeight, view_projection, planes}, object, g).cap_pixels;
    int outside = 0;
    for (std::size_t i = 0; i < g.pixel_count(); ++i) {
      const glm::dvec3 t = g.texture_position[i];
      outside += g.is_cap(i) && glm::any(glm::greaterThan(glm::abs(t), glm::dvec3(1.0 + 1e-4)));
    }
    return outside;
  };
  RasterObject unbounded{open_box.view()};
  uint64_t caps = 0;
  EXPECT_GT(outside_caps(unbounded, caps), 500) << "the view does not pass through the hole";
  RasterObject bounded = unbounded;
  bounded.bounds_min = glm::vec3(-1.0f);
  bounded.bounds_max = glm::vec3(1.0f);
  EXPECT_EQ(outside_caps(bounded, caps), 0);
  EXPECT_GT(caps, 500u) << "the caps inside the box stay";
}

// Seen from above, the cut sphere shows both the cap and the outside of what is left.
TEST(ClipPlanes, ObliqueViewShowsCapAndRemainingSurface) {
  RasterObject object{unit_sphere().view()};
  const std::vector<glm::dvec4> planes = {{0.0, 0.0, -1.0, 0.0}};
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  const RasterStats stats = render_one(
      rasterizer,
      {kWidth, kHeight, raster_test::perspective_look_at({0, 2.5f, 2}, {0, 0, 0}, kWidth, kHeight),
       planes},
      object, g);
  int caps = 0, surface = 0;
  for (std::size_t i = 0; i < g.pixel_count(); ++i) {
    if (!g.covered(i)) continue;
    const glm::dvec3 p = g.texture_position[i];
    if (g.is_cap(i)) {
      ++caps;
      EXPECT_NEAR(p.z, 0.0, 1e-12);
      EXPECT_LE(glm::length(p), 1.0 + 1e-9);
    } else {
      ++surface;
      EXPECT_FALSE(g.back_face(i));
      EXPECT_LE(p.z, 1e-3);  // on the kept side (up to a pixel's worth at the rim)
      EXPECT_NEAR(glm::length(p), 1.0, 2e-3);
    }
  }
  EXPECT_GT(caps, 500);
  EXPECT_GT(surface, 200);
  EXPECT_EQ(stats.back_face_pixels, 0u);
  EXPECT_TRUE(raster_test::all_values_sane(g));
}

// A moved, turned box whose texture space is far away, cut obliquely through its centre: cap
// positions are the exact ray-plane points mapped into texture space.
TEST(ClipPlanes, CapPositionsAreRayPlaneIntersectionsInTextureSpace) {
  const glm::vec3 half(1.0f, 0.7f, 0.5f);
  const Mesh cube = raster_test::box(half);
  RasterObject object{cube.view()};
  const glm::vec3 centre(5.0f, 0.0f, -2.0f);
  object.model =
      glm::rotate(glm::translate(glm::mat4(1.0f), centre), glm::radians(30.0f), glm::vec3(0, 1, 0));
  object.texture_from_object =
      glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(1e6, 2e6, -3e6)), glm::dvec3(2.0));
  const glm::vec3 eye = centre + glm::vec3(0.5f, 1.5f, 4.0f);
  const glm::dvec3 normal = glm::normalize(-glm::dvec3(eye - centre) + glm::dvec3(0.3, -0.2, 0.1));
  const std::vector<glm::dvec4> planes = {
      glm::dvec4(normal, -glm::dot(normal, glm::dvec3(centre)))};
  const glm::mat4 view_projection = raster_test::perspective_look_at(eye, centre, kWidth, kHeight);
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  const RasterStats stats =
      render_one(rasterizer, {kWidth, kHeight, view_projection, planes}, object, g);

  const glm::dmat4 object_from_world = glm::inverse(glm::dmat4(object.model));
  int caps = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t i = g.index(x, y);
      if (!g.is_cap(i)) continue;
      ++caps;
      const auto hit = raster_test::hit_plane(
          raster_test::pixel_ray(view_projection, kWidth, kHeight, x, y), planes[0]);
      ASSERT_TRUE(hit.has_value());
      const glm::dvec3 in_object = glm::dvec3(object_from_world * glm::dvec4(*hit, 1.0));
      EXPECT_LE(std::abs(in_object.x), half.x + 1e-3);
      EXPECT_LE(std::abs(in_object.y), half.y + 1e-3);
      EXPECT_LE(std::abs(in_object.z), half.z + 1e-3);
      const glm::dvec3 expected =
          glm::dvec3(object.texture_from_object * glm::dvec4(in_object, 1.0));
      EXPECT_LE(glm::length(g.texture_position[i] - expected), 1e-6);
      EXPECT_LE(glm::length(glm::dvec3(g.normal[i]) + normal), 1e-6);
      EXPECT_GT(g.footprint[i], 0.0f);
    }
  }
  EXPECT_GT(caps, 1000);
  EXPECT_EQ(stats.cap_pixels, static_cast<uint64_t>(caps));
  EXPECT_EQ(stats.back_face_pixels, 0u);
  EXPECT_TRUE(raster_test::all_values_sane(g));
}

TEST(ClipPlanes, TwoPlanesCutAWedgeWithTwoCapFaces) {
  RasterObject object{unit_sphere().view()};
  const std::vector<glm::dvec4> planes = {{0.0, 0.0, -1.0, 0.0}, {-1.0, 0.0, 0.0, 0.0}};
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  const RasterStats stats = render_one(
      rasterizer,
      {kWidth, kHeight,
       raster_test::perspective_look_at({2.5f, 1.0f, 2.5f}, {0, 0, 0}, kWidth, kHeight), planes},
      object, g);
  int on_z = 0, on_x = 0;
  for (std::size_t i = 0; i < g.pixel_count(); ++i) {
    if (!g.is_cap(i)) continue;
    const glm::dvec3 p = g.texture_position[i];
    EXPECT_LE(p.x, 1e-12);
    EXPECT_LE(p.z, 1e-12);
    if (std::abs(p.z) < 1e-12) {
      ++on_z;
      EXPECT_EQ(g.normal[i], glm::vec3(0, 0, 1));
    } else {
      EXPECT_NEAR(p.x, 0.0, 1e-12);
      ++on_x;
      EXPECT_EQ(g.normal[i], glm::vec3(1, 0, 0));
    }
  }
  EXPECT_GT(on_z, 300);
  EXPECT_GT(on_x, 300);
  EXPECT_EQ(stats.back_face_pixels, 0u);
}

// Where a pixel's ray first enters the kept region of `planes` (each a, b, c, d keeping
// a x + b y + c z + d >= 0), if it enters and leaves it again later; the ray starts outside.
std::optional<glm::dvec3> entry_into(const raster_test::Ray& ray,
                                     const std::vector<glm::dvec4>& planes) {
  double entry = -std::numeric_limits<double>::infinity();
  double exit = std::numeric_limits<double>::infinity();
  for (const glm::dvec4& plane : planes) {
    const double start = glm::dot(glm::dvec3(plane), ray.origin) + plane.w;
    const double along = glm::dot(glm::dvec3(plane), ray.direction);
    if (along > 0.0) {
      entry = std::max(entry, -start / along);
    } else if (along < 0.0) {
      exit = std::min(exit, -start / along);
    } else if (start < 0.0) {
      return std::nullopt;
    }
  }
  if (!(entry < exit) || !(entry > 0.0)) return std::nullopt;
  return ray.origin + entry * ray.direction;
}

// Pixels whose ray enters the kept region at a point well inside the unit sphere see a cap
// there; pixels whose entry point lies well outside it, or whose ray misses the region, see
// nothing of the object. `planes` keep a region whose far side is cut away too, so the
// sphere's back faces behind the region are gone and tell the inside by being beyond it.
// `backdrop`: a second object, uncut, drawn too (behind the sphere); nullptr for none.
int expect_caps_where_rays_enter_inside(const std::vector<glm::dvec4>& planes, const glm::vec3& eye,
                                        const RasterObject* backdrop = nullptr) {
  std::vector<RasterObject> objects = {RasterObject{unit_sphere().view()}};
  if (backdrop != nullptr) objects.push_back(*backdrop);
  const glm::mat4 view_projection =
      raster_test::perspective_look_at(eye, {0, 0, 0}, kWidth, kHeight);
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  const RasterStats stats =
      rasterizer.render({kWidth, kHeight, view_projection, planes}, objects, g);
  int caps = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t i = g.index(x, y);
      const auto entry =
          entry_into(raster_test::pixel_ray(view_projection, kWidth, kHeight, x, y), planes);
      // The mesh is a polygon inscribed in the sphere: 0.98 keeps clear of its facets.
      if (entry && glm::length(*entry) < 0.98) {
        EXPECT_TRUE(g.is_cap(i)) << "pixel " << x << "," << y;
        EXPECT_LE(glm::length(g.texture_position[i] - *entry), 1e-9) << x << "," << y;
      }
      if (!entry || glm::length(*entry) > 1.01) {
        EXPECT_FALSE(g.is_cap(i)) << "pixel " << x << "," << y;
      }
      caps += g.is_cap(i) ? 1 : 0;
    }
  }
  EXPECT_EQ(stats.cap_pixels, static_cast<uint64_t>(caps));
  EXPECT_TRUE(raster_test::all_values_sane(g));
  return caps;
}

// The slab |z| <= 0.5 seen head-on: its near face is a disc of cap; no back face of the
// sphere is left behind the slab to say the slab's inside is the sphere's.
TEST(ClipPlanes, ASlabSeenHeadOnShowsItsNearFaceAsACap) {
  const int caps = expect_caps_where_rays_enter_inside(
      {{0.0, 0.0, -1.0, 0.5}, {0.0, 0.0, 1.0, 0.5}}, {0.0f, 0.0f, 3.0f});
  EXPECT_GT(caps, 1000);
}

// The same slab in front of a wall: where the slab's face is, the cap hides the wall.
TEST(ClipPlanes, ASlabsCapHidesAnUncutObjectBehindIt) {
  Mesh wall;
  wall.positions = {{-4, -4, -2}, {4, -4, -2}, {4, 4, -2}, {-4, 4, -2}};
  wall.add_triangle(0, 1, 2);
  wall.add_triangle(0, 2, 3);
  RasterObject backdrop{wall.view()};
  backdrop.closed = false;
  backdrop.clip_plane_mask = 0;
  const int caps = expect_caps_where_rays_enter_inside(
      {{0.0, 0.0, -1.0, 0.5}, {0.0, 0.0, 1.0, 0.5}}, {0.3f, 0.2f, 3.0f}, &backdrop);
  EXPECT_GT(caps, 1000);
}

// The same slab seen from inside a closed, uncut room: the room's back faces, which the
// pixels keep, lie behind the cap.
TEST(ClipPlanes, ASlabsCapShowsInsideAClosedRoom) {
  static const Mesh room = raster_test::box(glm::vec3(10.0f));
  RasterObject backdrop{room.view()};
  backdrop.clip_plane_mask = 0;
  const int caps = expect_caps_where_rays_enter_inside(
      {{0.0, 0.0, -1.0, 0.5}, {0.0, 0.0, 1.0, 0.5}}, {0.3f, 0.2f, 3.0f}, &backdrop);
  EXPECT_GT(caps, 1000);
}

// A small sphere in front of the slab, cut by planes of its own: where its cut-away part
// lies along the ray, the slab's cap still shows (that part is past the small sphere's kept
// region, not in front of the slab).
TEST(ClipPlanes, AnotherSolidsCutAwayPartDoesNotHideACap) {
  static const Mesh small = raster_test::uv_sphere(32, 64, 0.3f);
  const std::vector<glm::dvec4> planes = {
      {0.0, 0.0, -1.0, 0.5},  // 0, 1: the unit sphere's slab |z| <= 0.5
      {0.0, 0.0, 1.0, 0.5},
      {1.0, 0.0, 0.0, 0.05},   // 2: the small sphere keeps x >= -0.05, the eye's side
      {0.0, 0.0, -1.0, 3.0}};  // 3: and z <= 3, which the eye is not on
  RasterObject slab{unit_sphere().view()};
  slab.clip_plane_mask = 0b0011;
  RasterObject cut{small.view()};
  cut.model = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 1.5f));
  cut.clip_plane_mask = 0b1100;
  cut.object_id = 1;
  const std::vector<RasterObject> objects = {slab, cut};
  const glm::vec3 eye(0.0f, 0.0f, 3.5f);
  const glm::mat4 view_projection =
      raster_test::perspective_look_at(eye, {0, 0, 0}, kWidth, kHeight);
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  rasterizer.render({kWidth, kHeight, view_projection, planes}, objects, g);
  const std::vector<glm::dvec4> slab_planes(planes.begin(), planes.begin() + 2);
  int behind_cut_away = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const raster_test::Ray ray = raster_test::pixel_ray(view_projection, kWidth, kHeight, x, y);
      const auto entry = entry_into(ray, slab_planes);
      if (!entry || glm::length(*entry) > 0.98) continue;
      // Where the ray meets the small sphere at all, by more than a facet's depth.
      const glm::dvec3 to_centre = glm::dvec3(0.0, 0.0, 1.5) - ray.origin;
      const glm::dvec3 unit = glm::normalize(ray.direction);
      const double along = glm::dot(to_centre, unit);
      const double miss = glm::length(to_centre - along * unit);
      if (miss < 0.31) {
        const glm::dvec3 front =
            ray.origin + (along - std::sqrt(std::max(0.0, 0.09 - miss * miss))) * unit;
        if (front.x > -0.06) continue;  // the small sphere's kept part, or too near its cut
        ++behind_cut_away;
      }
      const std::size_t i = g.index(x, y);
      EXPECT_TRUE(g.is_cap(i)) << "pixel " << x << "," << y;
      EXPECT_EQ(g.object_id[i], 0u) << "pixel " << x << "," << y;
    }
  }
  EXPECT_GT(behind_cut_away, 50);
}

// Six planes keep the cube |x|, |y|, |z| <= 0.5, wholly inside the sphere: seen from a
// corner, three of its faces are caps, and nothing else is drawn.
TEST(ClipPlanes, SixPlanesCutACubeOutOfTheSolid) {
  std::vector<glm::dvec4> planes;
  for (int axis = 0; axis < 3; ++axis) {
    for (const double side : {-1.0, 1.0}) {
      glm::dvec4 plane(0.0, 0.0, 0.0, 0.5);
      plane[axis] = side;
      planes.push_back(plane);
    }
  }
  const int caps = expect_caps_where_rays_enter_inside(planes, {2.0f, 1.6f, 2.4f});
  EXPECT_GT(caps, 1000);
}

TEST(ClipPlanes, OpenMeshesAndCamerasOnTheKeptSideGetNoCaps) {
  const std::vector<glm::dvec4> planes = {{0.0, 0.0, -1.0, 0.0}};
  const RasterView view{kWidth, kHeight,
                        raster_test::perspective_look_at({0, 0.5f, 3}, {0, 0, 0}, kWidth, kHeight),
                        planes};
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;

  RasterObject open{unit_sphere().view()};
  open.closed = false;
  RasterStats stats = render_one(rasterizer, view, open, g);
  EXPECT_EQ(stats.cap_rays, 0u);
  EXPECT_EQ(stats.cap_pixels, 0u);
  EXPECT_GT(stats.back_face_pixels, 1000u);

  // Keeping the half facing the camera: no back face ever wins, nothing to trace.
  const std::vector<glm::dvec4> keep_front = {{0.0, 0.0, 1.0, 0.0}};
  stats = render_one(rasterizer, {view.width, view.height, view.view_projection, keep_front},
                     RasterObject{unit_sphere().view()}, g);
  EXPECT_EQ(stats.cap_pixels, 0u);
  EXPECT_EQ(stats.back_face_pixels, 0u);
  EXPECT_GT(stats.pixels_covered, 1000u);
}

// Triangle-level classification: wholly kept and wholly removed triangles need no fragment
// tests; only straddling ones do.
TEST(ClipPlanes, OnlyStraddlingTrianglesAreTestedPerFragment) {
  Mesh quad;
  quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  quad.add_triangle(0, 1, 2);
  quad.add_triangle(0, 2, 3);
  RasterObject object{quad.view()};
  object.closed = false;
  const glm::mat4 view_projection =
      raster_test::perspective_look_at({0, 0, 3}, {0, 0, 0}, kWidth, kHeight);
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;

  const std::vector<glm::dvec4> keep_all = {{1.0, 0.0, 0.0, 5.0}};
  RasterStats stats =
      render_one(rasterizer, {kWidth, kHeight, view_projection, keep_all}, object, g);
  EXPECT_EQ(stats.triangles_clip_tested, 2u);
  EXPECT_EQ(stats.triangles_clip_straddling, 0u);
  EXPECT_EQ(stats.fragments_clip_tested, 0u);
  EXPECT_GT(stats.pixels_covered, 1000u);

  const std::vector<glm::dvec4> remove_all = {{1.0, 0.0, 0.0, -5.0}};
  stats = render_one(rasterizer, {kWidth, kHeight, view_projection, remove_all}, object, g);
  EXPECT_EQ(stats.triangles_clip_rejected, 2u);
  EXPECT_EQ(stats.fragments_clip_tested, 0u);
  EXPECT_EQ(stats.pixels_covered, 0u);

  const std::vector<glm::dvec4> keep_right = {{1.0, 0.0, 0.0, -0.1}};  // x >= 0.1
  stats = render_one(rasterizer, {kWidth, kHeight, view_projection, keep_right}, object, g);
  EXPECT_EQ(stats.triangles_clip_straddling, 2u);
  EXPECT_GT(stats.fragments_clip_discarded, 0u);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const auto hit = raster_test::hit_plane(
          raster_test::pixel_ray(view_projection, kWidth, kHeight, x, y), {0, 0, 1, 0});
      if (!hit || std::abs(hit->y) > 0.98 || hit->x > 0.98) continue;
      if (hit->x < 0.09) {
        EXPECT_FALSE(g.covered(g.index(x, y))) << x << "," << y;
      }
      if (hit->x > 0.11) {
        EXPECT_TRUE(g.covered(g.index(x, y))) << x << "," << y;
      }
    }
  }
}

TEST(ClipPlanes, CapFootprintIsFiniteAndGrowsAtGrazingAngles) {
  RasterObject object{unit_sphere().view()};
  Rasterizer rasterizer({.threads = 1});
  GBuffer g;
  float previous = 0.0f;
  for (const double degrees : {0.0, 45.0, 70.0, 80.0}) {
    // The camera turns about the cut face's centre, 3 units away.
    const double angle = glm::radians(degrees);
    const glm::vec3 eye(0.0f, static_cast<float>(3.0 * std::sin(angle)),
                        static_cast<float>(3.0 * std::cos(angle)));
    const std::vector<glm::dvec4> planes = {{0.0, 0.0, -1.0, 0.0}};
    render_one(rasterizer,
               {kWidth, kHeight, raster_test::perspective_look_at(eye, {0, 0, 0}, kWidth, kHeight),
                planes},
               object, g);
    const std::size_t centre = g.index(kWidth / 2, kHeight / 2);
    ASSERT_TRUE(g.is_cap(centre)) << degrees;
    EXPECT_TRUE(std::isfinite(g.footprint[centre]));
    EXPECT_GT(g.footprint[centre], previous) << degrees;
    previous = g.footprint[centre];
    EXPECT_TRUE(raster_test::all_values_sane(g));
  }
}

}  // namespace
}  // namespace soltex
