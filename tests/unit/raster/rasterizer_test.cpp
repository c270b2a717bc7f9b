#include "soltex/raster/rasterizer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "raster_test_scenes.h"

namespace soltex {
namespace {

using raster_test::Mesh;

constexpr int kWidth = 160;
constexpr int kHeight = 120;

RasterStats render_one(Rasterizer& rasterizer, const RasterView& view, const RasterObject& object,
                       GBuffer& g) {
  return rasterizer.render(view, std::span<const RasterObject>(&object, 1), g);
}

// Fragments that passed the fill rule at each pixel: the exactly-once checks below read it.
std::vector<uint32_t> coverage_of(const Mesh& mesh, const glm::mat4& view_projection) {
  Rasterizer rasterizer({.threads = 2, .count_coverage = true});
  const RasterView view{kWidth, kHeight, view_projection, {}};
  RasterObject object;
  object.mesh = mesh.view();
  GBuffer g;
  render_one(rasterizer, view, object, g);
  return {g.coverage_count.begin(), g.coverage_count.end()};
}

// A square whose edges and diagonal run through pixel centres: the top-left rule decides all.
TEST(RasterizerFillRule, QuadWithEdgesThroughPixelCentresCoversEachPixelOnce) {
  Mesh quad;
  quad.positions = {
      {10.5f, 10.5f, 0.0f}, {50.5f, 10.5f, 0.0f}, {50.5f, 40.5f, 0.0f}, {10.5f, 40.5f, 0.0f}};
  quad.add_triangle(0, 1, 2);
  quad.add_triangle(0, 2, 3);
  const std::vector<uint32_t> coverage =
      coverage_of(quad, raster_test::pixel_ortho(kWidth, kHeight));
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      // Top and left edges are in, right and bottom edges out: [10, 49] x [10, 39].
      const uint32_t expected = (x >= 10 && x <= 49 && y >= 10 && y <= 39) ? 1 : 0;
      ASSERT_EQ(coverage[static_cast<std::size_t>(y * kWidth + x)], expected)
          << "pixel " << x << "," << y;
    }
  }
}

bool inside_convex_polygon(const std::vector<glm::dvec2>& polygon, glm::dvec2 p, double margin) {
  // Counter-clockwise or clockwise: inside when every edge has p on the same side by margin.
  int positive = 0, negative = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
    const double side =
        ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)) / glm::length(b - a);
    positive += side > margin;
    negative += side < -margin;
  }
  return positive == static_cast<int>(polygon.size()) ||
         negative == static_cast<int>(polygon.size());
}

// Fans around a vertex on a pixel centre and off it, with both windings.
TEST(RasterizerFillRule, TriangleFanCoversEachPixelOnce) {
  for (const glm::vec2 centre : {glm::vec2(60.5f, 50.5f), glm::vec2(61.3f, 49.7f)}) {
    for (const bool clockwise : {false, true}) {
      Mesh fan;
      fan.positions.push_back({centre, 0.0f});
      std::vector<glm::dvec2> rim;
      const int spokes = 13;
      for (int i = 0; i < spokes; ++i) {
        const double angle = 2.0 * std::numbers::pi * (i + 0.31 * (i % 3)) / spokes;
        const glm::dvec2 p(centre.x + 37.3 * std::cos(angle), centre.y + 37.3 * std::sin(angle));
        rim.push_back(glm::dvec2(glm::vec2(p)));
        fan.positions.push_back({glm::vec2(p), 0.0f});
      }
      for (int i = 0; i < spokes; ++i) {
        const auto a = static_cast<uint32_t>(1 + i);
        const auto b = static_cast<uint32_t>(1 + (i + 1) % spokes);
        if (clockwise) {
          fan.add_triangle(0, b, a);
        } else {
          fan.add_triangle(0, a, b);
        }
      }
      const std::vector<uint32_t> coverage =
          coverage_of(fan, raster_test::pixel_ortho(kWidth, kHeight));
      int covered = 0;
      for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
          const uint32_t count = coverage[static_cast<std::size_t>(y * kWidth + x)];
          ASSERT_LE(count, 1u) << "pixel " << x << "," << y;
          const glm::dvec2 p(x + 0.5, y + 0.5);
          if (inside_convex_polygon(rim, p, 1e-4)) {
            ASSERT_EQ(count, 1u) << "hole at " << x << "," << y;
          }
          covered += static_cast<int>(count);
        }
      }
      EXPECT_GT(covered, 3000);
    }
  }
}

// A jittered grid with random diagonals, seen in perspective: no pixel twice, no holes.
TEST(RasterizerFillRule, JitteredGridIsWatertightInPerspective) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
  const int n = 24;
  Mesh grid;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const bool border = i == 0 || j == 0 || i == n || j == n;
      const float x = static_cast<float>(i) + (border ? 0.0f : jitter(random));
      const float y = static_cast<float>(j) + (border ? 0.0f : jitter(random));
      grid.positions.push_back({x / n * 2.0f - 1.0f, y / n * 2.0f - 1.0f, 0.0f});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const auto v = [n](int a, int b) { return static_cast<uint32_t>(b * (n + 1) + a); };
      if (random() % 2) {
        grid.add_triangle(v(i, j), v(i + 1, j), v(i + 1, j + 1));
        grid.add_triangle(v(i, j), v(i + 1, j + 1), v(i, j + 1));
      } else {
        grid.add_triangle(v(i, j), v(i + 1, j), v(i, j + 1));
        grid.add_triangle(v(i + 1, j), v(i + 1, j + 1), v(i, j + 1));
      }
    }
  }
  const glm::mat4 view_projection =
      raster_test::perspective_look_at({0.7f, -1.1f, 1.6f}, {0.0f, 0.0f, 0.0f}, kWidth, kHeight);
  const std::vector<uint32_t> coverage = coverage_of(grid, view_projection);
  int checked = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const uint32_t count = coverage[static_cast<std::size_t>(y * kWidth + x)];
      ASSERT_LE(count, 1u) << "pixel " << x << "," << y;
      const raster_test::Ray ray = raster_test::pixel_ray(view_projection, kWidth, kHeight, x, y);
      const auto hit = raster_test::hit_plane(ray, {0.0, 0.0, 1.0, 0.0});
      if (hit && std::abs(hit->x) < 0.97 && std::abs(hit->y) < 0.97) {
        ASSERT_EQ(count, 1u) << "hole at " << x << "," << y;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 4000);
}

Mesh square_at(float z, float half = 0.5f) {
  Mesh mesh;
  mesh.positions = {{-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}};
  mesh.add_triangle(0, 1, 2);
  mesh.add_triangle(0, 2, 3);
  return mesh;
}

TEST(RasterizerDepth, NearestWinsAndTiesKeepTheFirstTriangle) {
  const Mesh far = square_at(-3.0f, 1.0f);
  const Mesh near = square_at(-2.0f, 0.25f);
  const Mesh tie = square_at(-3.0f, 1.0f);
  std::vector<RasterObject> objects(3);
  objects[0].mesh = far.view();
  objects[0].object_id = 10;
  objects[1].mesh = near.view();
  objects[1].object_id = 20;
  objects[2].mesh = tie.view();
  objects[2].object_id = 30;
  const glm::mat4 view_projection =
      raster_test::perspective_look_at({0, 0, 0}, {0, 0, -1}, kWidth, kHeight);
  const RasterView view{kWidth, kHeight, view_projection, {}};

  GBuffer reference;
  for (const int threads : {1, 2, 3, 8}) {
    Rasterizer rasterizer({.threads = threads});
    GBuffer g;
    rasterizer.render(view, objects, g);
    const std::size_t centre = g.index(kWidth / 2, kHeight / 2);
    EXPECT_EQ(g.object_id[centre], 20u);
    const std::size_t side = g.index(kWidth / 2 + 25, kHeight / 2);
    ASSERT_TRUE(g.covered(side));
    EXPECT_EQ(g.object_id[side], 10u) << "a tie keeps the earlier object";
    for (std::size_t i = 0; i < g.pixel_count(); ++i) EXPECT_NE(g.object_id[i], 30u);
    if (threads == 1) {
      reference = g;
    } else {
      EXPECT_EQ(g.depth, reference.depth);
      EXPECT_EQ(g.object_id, reference.object_id);
    }
  }
}

TEST(RasterizerFaces, BothFacesDrawnAndTheWinnerRecorded) {
  const Mesh square = square_at(0.0f);  // counter-clockwise seen from +z
  RasterObject object;
  object.mesh = square.view();
  object.closed = false;
  Rasterizer rasterizer({.threads = 1});
  GBuffer g;
  for (const float eye_z : {2.0f, -2.0f}) {
    const RasterView view{
        kWidth,
        kHeight,
        raster_test::perspective_look_at({0, 0, eye_z}, {0, 0, 0}, kWidth, kHeight),
        {}};
    const RasterStats stats = render_one(rasterizer, view, object, g);
    const std::size_t centre = g.index(kWidth / 2, kHeight / 2);
    ASSERT_TRUE(g.covered(centre));
    EXPECT_EQ(g.back_face(centre), eye_z < 0.0f);
    EXPECT_EQ(stats.back_face_pixels > 0, eye_z < 0.0f);
    EXPECT_EQ(stats.clip_plane_work(), 0u);
  }
}

// A slanted floor: each pixel's texture position must be the exact ray-plane intersection
// (mapped to texture space), which screen-affine interpolation would miss by far.
TEST(RasterizerInterpolation, TexturePositionIsPerspectiveCorrect) {
  Mesh floor;
  floor.positions = {
      {-4.0f, 0.0f, 1.0f}, {4.0f, 0.0f, 1.0f}, {4.0f, 0.0f, -40.0f}, {-4.0f, 0.0f, -40.0f}};
  floor.add_triangle(0, 1, 2);
  floor.add_triangle(0, 2, 3);
  RasterObject object;
  object.mesh = floor.view();
  object.model = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, -1.0f, 0.0f));
  object.texture_from_object =
      glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(3.0, -2.0, 5.0)), glm::dvec3(2.5));
  const glm::mat4 view_projection =
      raster_test::perspective_look_at({0, 0.5f, 2}, {0, -1, -6}, kWidth, kHeight);
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  render_one(rasterizer, {kWidth, kHeight, view_projection, {}}, object, g);

  const glm::dmat4 texture_from_world =
      object.texture_from_object * glm::inverse(glm::dmat4(object.model));
  double worst = 0.0;
  int checked = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t i = g.index(x, y);
      if (!g.covered(i)) continue;
      const auto hit = raster_test::hit_plane(
          raster_test::pixel_ray(view_projection, kWidth, kHeight, x, y), {0, 1, 0, 1});
      ASSERT_TRUE(hit.has_value());
      const glm::dvec3 expected = glm::dvec3(texture_from_world * glm::dvec4(*hit, 1.0));
      const double error = glm::length(g.texture_position[i] - expected);
      // Vertices snap to 1/256 pixel: the error stays a small fraction of a pixel's size.
      EXPECT_LE(error, 0.01 * g.footprint[i] + 1e-5) << "pixel " << x << "," << y;
      worst = std::max(worst, error / g.footprint[i]);
      ++checked;
    }
  }
  EXPECT_GT(checked, kWidth * kHeight / 3);
  EXPECT_LT(worst, 0.01);

  // Screen-affine interpolation would put the middle pixel of a column at the mean of its
  // ends; in perspective it is hundreds of pixel footprints away from that.
  const int x = kWidth / 2;
  int top = 0;
  while (!g.covered(g.index(x, top))) ++top;
  const int bottom = kHeight - 1 - ((kHeight - 1 - top) % 2);
  const glm::dvec3 mean =
      0.5 * (g.texture_position[g.index(x, top)] + g.texture_position[g.index(x, bottom)]);
  const std::size_t middle = g.index(x, (top + bottom) / 2);
  EXPECT_GT(glm::length(g.texture_position[middle] - mean), 100.0 * 0.01 * g.footprint[middle]);
}

// The centre pixel's footprint on a plane through the origin, tilted by `degrees` about x.
float centre_footprint(Rasterizer& rasterizer, double degrees, GBuffer& g) {
  const Mesh square = square_at(0.0f, 50.0f);
  RasterObject object;
  object.mesh = square.view();
  object.model =
      glm::rotate(glm::mat4(1.0f), static_cast<float>(glm::radians(degrees)), glm::vec3(1, 0, 0));
  const RasterView view{
      kWidth, kHeight, raster_test::perspective_look_at({0, 0, 4}, {0, 0, 0}, kWidth, kHeight), {}};
  render_one(rasterizer, view, object, g);
  return g.footprint[g.index(kWidth / 2, kHeight / 2)];
}

TEST(RasterizerFootprint, MatchesThePixelSizeFacingTheCamera) {
  Rasterizer rasterizer({.threads = 1});
  GBuffer g;
  const float footprint = centre_footprint(rasterizer, 0.0, g);
  const double pixel = 2.0 * 4.0 * std::tan(glm::radians(30.0)) / kHeight;
  EXPECT_NEAR(footprint, pixel, 1e-3 * pixel);
}

TEST(RasterizerFootprint, GrowsAtGrazingAnglesAndStaysFinite) {
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  float previous = 0.0f;
  for (const double degrees : {0.0, 30.0, 60.0, 75.0, 85.0, 88.0, 89.5}) {
    const float footprint = centre_footprint(rasterizer, degrees, g);
    EXPECT_GT(footprint, previous) << degrees << " degrees";
    EXPECT_TRUE(std::isfinite(footprint)) << degrees << " degrees";
    previous = footprint;
    EXPECT_TRUE(raster_test::all_values_sane(g)) << degrees << " degrees";
  }
  // About 1/cos: at 85 degrees more than ten times the facing footprint.
  EXPECT_GT(centre_footprint(rasterizer, 85.0, g), 10.0f * centre_footprint(rasterizer, 0.0, g));
}

// The footprint's shape: its long side is the longer derivative vector (as long as the
// footprint, across the tilt axis x: along the screen's y), its short side about the facing
// pixel's size whatever the tilt, so the ratio grows as about 1 / cos (within a tenth: the
// pixel's centre is half a pixel off the axis, which perspective weighs more at 85 degrees).
TEST(RasterizerFootprint, ItsLongSideLiesAlongTheTiltAndItsShortSideStays) {
  Rasterizer rasterizer({.threads = 1});
  GBuffer g;
  const double pixel = 2.0 * 4.0 * std::tan(glm::radians(30.0)) / kHeight;
  const std::size_t centre = static_cast<std::size_t>(kHeight / 2) * kWidth + kWidth / 2;
  for (const double degrees : {0.0, 45.0, 75.0, 85.0}) {
    const float footprint = centre_footprint(rasterizer, degrees, g);
    const glm::vec3 axis = g.footprint_axis[centre];
    const float minor = g.footprint_minor[centre];
    EXPECT_FLOAT_EQ(glm::length(axis), footprint) << degrees;
    EXPECT_LE(minor, footprint) << degrees;
    EXPECT_NEAR(minor, pixel, 0.1 * pixel) << degrees;
    if (degrees > 0.0) {
      // The plane is tilted about x: the long side has no x part.
      EXPECT_LT(std::abs(axis.x), 1e-2f * footprint) << degrees;
      EXPECT_NEAR(footprint / minor, 1.0 / std::cos(glm::radians(degrees)),
                  0.1 / std::cos(glm::radians(degrees)))
          << degrees;
    }
  }
}

TEST(RasterizerFootprint, ShrinksTowardsZeroAsTheSurfaceTouchesTheCamera) {
  Rasterizer rasterizer({.threads = 1});
  GBuffer g;
  const float near = 0.01f;
  float previous = std::numeric_limits<float>::infinity();
  for (const float distance : {10.0f, 1.0f, 0.1f, 0.0101f}) {
    const Mesh square = square_at(-distance, 5.0f);
    RasterObject object;
    object.mesh = square.view();
    const RasterView view{kWidth,
                          kHeight,
                          raster_test::perspective_look_at({0, 0, 0}, {0, 0, -1}, kWidth, kHeight,
                                                           60.0f, near, 100.0f),
                          {}};
    render_one(rasterizer, view, object, g);
    const float footprint = g.footprint[g.index(kWidth / 2, kHeight / 2)];
    EXPECT_GT(footprint, 0.0f) << distance;
    EXPECT_LT(footprint, previous) << distance;
    previous = footprint;
  }
  EXPECT_LT(previous, 2e-4f);
}

TEST(RasterizerInterpolation, NormalsAreInterpolatedAndUnit) {
  const Mesh sphere = raster_test::uv_sphere(48, 96);
  RasterObject object;
  object.mesh = sphere.view();
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  const RasterView view{kWidth,
                        kHeight,
                        raster_test::perspective_look_at({0.5f, 1, 3}, {0, 0, 0}, kWidth, kHeight),
                        {}};
  const RasterStats stats = render_one(rasterizer, view, object, g);
  EXPECT_TRUE(raster_test::all_values_sane(g));
  EXPECT_EQ(stats.back_face_pixels, 0u);
  EXPECT_EQ(stats.clip_plane_work(), 0u);
  int covered = 0;
  for (std::size_t i = 0; i < g.pixel_count(); ++i) {
    if (!g.covered(i)) continue;
    ++covered;
    // On a unit sphere the texture position (object space here) is the normal.
    const glm::dvec3 p = g.texture_position[i];
    EXPECT_NEAR(glm::length(p), 1.0, 2e-3);  // flat triangles inside the sphere
    EXPECT_GT(glm::dot(glm::dvec3(g.normal[i]), glm::normalize(p)), 0.9995);
    EXPECT_FALSE(g.back_face(i));
  }
  EXPECT_GT(covered, 3000);
  EXPECT_EQ(stats.pixels_covered, static_cast<uint64_t>(covered));
}

TEST(RasterizerRobustness, DegenerateAndInvalidTrianglesAreSkippedAndCounted) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  Mesh mesh;
  mesh.positions = {{-0.5f, -0.5f, 0.0f}, {0.5f, -0.5f, 0.0f}, {0.0f, 0.5f, 0.0f},
                    {0.0f, 0.0f, 0.0f},   {0.2f, 0.2f, 0.0f},  {0.4f, 0.4f, 0.0f},
                    {nan, 0.0f, 0.0f},    {0.0f, inf, 0.0f}};
  mesh.add_triangle(0, 1, 2);    // good
  mesh.add_triangle(0, 0, 1);    // repeated vertex
  mesh.add_triangle(3, 4, 5);    // collinear
  mesh.add_triangle(0, 1, 6);    // NaN
  mesh.add_triangle(7, 1, 2);    // inf
  mesh.add_triangle(0, 1, 999);  // index out of range
  RasterObject object;
  object.mesh = mesh.view();
  object.mesh.normals = {};  // flat
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  const RasterView view{
      kWidth, kHeight, raster_test::perspective_look_at({0, 0, 2}, {0, 0, 0}, kWidth, kHeight), {}};
  const RasterStats stats = render_one(rasterizer, view, object, g);
  EXPECT_EQ(stats.triangles_in, 6u);
  EXPECT_EQ(stats.triangles_rasterized, 1u);
  EXPECT_EQ(stats.triangles_degenerate, 2u);
  EXPECT_EQ(stats.triangles_invalid, 3u);
  EXPECT_TRUE(raster_test::all_values_sane(g));
  EXPECT_TRUE(g.covered(g.index(kWidth / 2, kHeight / 2)));
  EXPECT_NEAR(g.normal[g.index(kWidth / 2, kHeight / 2)].z, 1.0f, 1e-6f);  // face normal
}

TEST(RasterizerRobustness, SliversStayFinite) {
  Mesh mesh;
  std::mt19937 random(3);
  std::uniform_real_distribution<float> coordinate(-1.0f, 1.0f);
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 a(coordinate(random), coordinate(random), coordinate(random) * 0.5f);
    const glm::vec3 b(coordinate(random), coordinate(random), coordinate(random) * 0.5f);
    const float t = coordinate(random) * 0.5f + 0.5f;
    const glm::vec3 c = a + t * (b - a) + glm::vec3(1e-4f * coordinate(random), 0.0f, 0.0f);
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {a, b, c});
    mesh.add_triangle(base, base + 1, base + 2);
  }
  RasterObject object;
  object.mesh = mesh.view();
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  const RasterView view{
      kWidth, kHeight, raster_test::perspective_look_at({0, 0, 3}, {0, 0, 0}, kWidth, kHeight), {}};
  const RasterStats stats = render_one(rasterizer, view, object, g);
  EXPECT_EQ(stats.triangles_in, 2000u);
  EXPECT_GT(stats.pixels_covered, 0u);
  EXPECT_TRUE(raster_test::all_values_sane(g));
}

// Texture space far from the origin: positions keep the precision they have near it.
TEST(RasterizerPrecision, FarFromOriginTexturePositionsKeepTheirPrecision) {
  const Mesh sphere = raster_test::uv_sphere(32, 64);
  RasterObject object;
  object.mesh = sphere.view();
  const RasterView view{
      kWidth,
      kHeight,
      raster_test::perspective_look_at({0.3f, 0.8f, 3}, {0, 0, 0}, kWidth, kHeight),
      {}};
  Rasterizer rasterizer({.threads = 2});
  GBuffer near_origin;
  render_one(rasterizer, view, object, near_origin);
  for (const double offset : {1e6, 1e9}) {
    const glm::dvec3 translation(offset, -0.5 * offset, 0.25 * offset);
    object.texture_from_object = glm::translate(glm::dmat4(1.0), translation);
    GBuffer far;
    render_one(rasterizer, view, object, far);
    double worst = 0.0;
    for (std::size_t i = 0; i < far.pixel_count(); ++i) {
      ASSERT_EQ(far.covered(i), near_origin.covered(i));
      if (!far.covered(i)) continue;
      worst = std::max(worst, glm::length(far.texture_position[i] - translation -
                                          near_origin.texture_position[i]));
      EXPECT_NEAR(far.footprint[i], near_origin.footprint[i], 1e-5f * near_origin.footprint[i]);
    }
    // The object is 2 units across; relative to its distance from the origin this is below
    // 1e-15, and it is also below 1e-6 of the object's own size.
    EXPECT_LT(worst, 1e-6) << offset;
    EXPECT_LT(worst / offset, 1e-12) << offset;
  }
}

// A sphere and an overlapping cube, cut by an oblique plane (so with caps), in a view whose size
// is not a multiple of the tile size.
struct SphereAndCubeCut {
  Mesh sphere = raster_test::uv_sphere(40, 80);
  Mesh cube = raster_test::box({0.6f, 0.6f, 0.6f});
  std::vector<RasterObject> objects;
  std::vector<glm::dvec4> planes = {{0.3, 0.2, -1.0, 0.1}};
  RasterView view;  // its clip planes and the objects' meshes point into this scene

  SphereAndCubeCut(const SphereAndCubeCut&) = delete;
  SphereAndCubeCut& operator=(const SphereAndCubeCut&) = delete;
  SphereAndCubeCut() : objects(2) {
    objects[0].mesh = sphere.view();
    objects[0].object_id = 1;
    objects[1].mesh = cube.view();
    objects[1].model = glm::translate(glm::mat4(1.0f), glm::vec3(0.8f, 0.1f, 0.2f));
    objects[1].object_id = 2;
    view = {201, 133, raster_test::perspective_look_at({0.5f, 1, 3}, {0, 0, 0}, 201, 133), planes};
  }
};

// Each thread starts on its own share of the range and then helps with the others': every
// index still runs exactly once, for ranges shorter and longer than the thread count, and a
// thrown exception reaches the caller after the others stop.
TEST(RasterizerThreads, ParallelForRunsEachIndexOnce) {
  for (const int threads : {1, 2, 3, 5}) {
    Rasterizer rasterizer(RasterOptions{threads, false});
    for (const std::size_t count :
         {std::size_t{1}, std::size_t{2}, std::size_t{7}, std::size_t{1000}}) {
      std::vector<std::atomic<int>> runs(count);
      std::vector<std::atomic<int>> worker_of(count);
      rasterizer.parallel_for(count, [&](std::size_t i, int worker) {
        runs[i].fetch_add(1);
        worker_of[i].store(worker);
      });
      for (std::size_t i = 0; i < count; ++i) {
        ASSERT_EQ(runs[i].load(), 1) << threads << " threads, index " << i << " of " << count;
        ASSERT_GE(worker_of[i].load(), 0);
        ASSERT_LT(worker_of[i].load(), threads);
      }
    }
    EXPECT_THROW(rasterizer.parallel_for(100,
                                         [](std::size_t i, int) {
                                           if (i == 42) throw std::runtime_error("index 42");
                                         }),
                 std::runtime_error);
    std::atomic<int> after{0};  // the pool still works after an exception
    rasterizer.parallel_for(10, [&](std::size_t, int) { after.fetch_add(1); });
    EXPECT_EQ(after.load(), 10);
  }
}

TEST(RasterizerThreads, EveryThreadCountGivesTheSameBuffer) {
  const SphereAndCubeCut scene;
  const std::vector<RasterObject>& objects = scene.objects;
  const RasterView& view = scene.view;
  GBuffer reference;
  RasterStats reference_stats;
  for (const int threads : {1, 2, 5}) {
    Rasterizer rasterizer({.threads = threads});
    EXPECT_EQ(rasterizer.thread_count(), threads);
    GBuffer g;
    const RasterStats stats = rasterizer.render(view, objects, g);
    if (threads == 1) {
      reference = g;
      reference_stats = stats;
      EXPECT_GT(stats.cap_pixels, 0u);
      continue;
    }
    raster_test::expect_same_buffer(g, reference);
    EXPECT_EQ(stats.pixels_covered, reference_stats.pixels_covered);
    EXPECT_EQ(stats.cap_pixels, reference_stats.cap_pixels);
    EXPECT_EQ(stats.triangles_rasterized, reference_stats.triangles_rasterized);
  }
}

// Every pixel is handed to after_tile exactly once, on a valid worker, and by then its G-buffer
// values are final: copying the tile out in the callback gives the finished buffer.
TEST(RasterizerThreads, AfterTileSeesEachFinishedTileOnce) {
  const Mesh sphere = raster_test::uv_sphere(40, 80);
  RasterObject object;
  object.mesh = sphere.view();
  object.object_id = 3;
  const int width = 300, height = 170;  // not multiples of the tile size
  const RasterView view{
      width, height, raster_test::perspective_look_at({0.5f, 1, 3}, {0, 0, 0}, width, height), {}};
  for (const int threads : {1, 2, 3}) {
    Rasterizer rasterizer({.threads = threads});
    GBuffer g;
    std::vector<int> visits(static_cast<std::size_t>(width) * height, 0);
    GBufferPlane<float> depth_seen(visits.size(), -1.0f);
    GBufferPlane<glm::dvec3> position_seen(visits.size(), glm::dvec3(0.0));
    rasterizer.render(view, std::span<const RasterObject>(&object, 1), g,
                      [&](int x0, int y0, int x1, int y1, int worker) {
                        EXPECT_GE(worker, 0);
                        EXPECT_LT(worker, threads);
                        for (int y = y0; y < y1; ++y) {
                          for (int x = x0; x < x1; ++x) {
                            const std::size_t i = g.index(x, y);
                            ++visits[i];
                            depth_seen[i] = g.depth[i];
                            position_seen[i] = g.texture_position[i];
                          }
                        }
                      });
    EXPECT_TRUE(std::all_of(visits.begin(), visits.end(), [](int v) { return v == 1; }));
    EXPECT_EQ(depth_seen, g.depth);
    EXPECT_EQ(position_seen, g.texture_position);
  }
}

// render_tiles() hands each tile over in a tile-sized G-buffer: pixel for pixel what render()
// writes into the frame's, caps included, whatever the thread count.
TEST(RasterizerThreads, TileBuffersHoldWhatTheFrameBufferHolds) {
  const SphereAndCubeCut scene;
  const std::vector<RasterObject>& objects = scene.objects;
  const RasterView& view = scene.view;
  Rasterizer full_frame({.threads = 1});
  GBuffer frame;
  const RasterStats frame_stats = full_frame.render(view, objects, frame);
  ASSERT_GT(frame_stats.cap_pixels, 0u);
  for (const int threads : {1, 2, 3}) {
    Rasterizer rasterizer({.threads = threads});
    std::vector<int> visits(frame.pixel_count(), 0);
    std::vector<int> mismatches(static_cast<std::size_t>(threads), 0);
    const RasterStats stats = rasterizer.render_tiles(
        view, objects, [&](const GBuffer& tile, int x0, int y0, int x1, int y1, int worker) {
          ASSERT_EQ(tile.width, Rasterizer::kTileSize);
          ASSERT_LE(x1 - x0, Rasterizer::kTileSize);
          ASSERT_LE(y1 - y0, Rasterizer::kTileSize);
          int& wrong = mismatches[static_cast<std::size_t>(worker)];
          for (int y = y0; y < y1; ++y) {
            for (int x = x0; x < x1; ++x) {
              const std::size_t f = frame.index(x, y);
              const std::size_t t = tile.index(x - x0, y - y0);
              ++visits[f];
              const bool same =
                  frame.flags[f] == tile.flags[t] && frame.object_id[f] == tile.object_id[t] &&
                  std::memcmp(&frame.depth[f], &tile.depth[t], sizeof(float)) == 0 &&
                  (!frame.covered(f) ||
                   (frame.texture_position[f] == tile.texture_position[t] &&
                    frame.normal[f] == tile.normal[t] && frame.footprint[f] == tile.footprint[t] &&
                    frame.footprint_axis[f] == tile.footprint_axis[t] &&
                    frame.footprint_minor[f] == tile.footprint_minor[t]));
              wrong += same ? 0 : 1;
            }
          }
        });
    EXPECT_TRUE(std::all_of(visits.begin(), visits.end(), [](int v) { return v == 1; }));
    for (const int wrong : mismatches) EXPECT_EQ(wrong, 0) << threads << " threads";
    EXPECT_EQ(stats.pixels_covered, frame_stats.pixels_covered);
    EXPECT_EQ(stats.cap_pixels, frame_stats.cap_pixels);
  }
}

TEST(RasterizerThreads, TilesNoTriangleReachesGetOneSharedEmptyBuffer) {
  // A small sphere in the top-left corner of a frame of many tiles: the others are empty.
  const raster_test::Mesh sphere = raster_test::uv_sphere(12, 24, 0.2f);
  RasterObject object;
  object.mesh = sphere.view();
  object.model = glm::translate(glm::mat4(1.0f), glm::vec3(-1.6f, 0.85f, 0.0f));
  RasterView view;
  view.width = 5 * Rasterizer::kTileSize;
  view.height = 3 * Rasterizer::kTileSize + 7;  // a partial row of tiles too
  view.view_projection =
      raster_test::perspective_look_at({0, 0, 3}, {0, 0, 0}, view.width, view.height);
  const std::vector<RasterObject> objects{object};
  Rasterizer full_frame({.threads = 1});
  GBuffer frame;
  const RasterStats frame_stats = full_frame.render(view, objects, frame);
  ASSERT_GT(frame_stats.pixels_covered, 0u);

  // One thread: its own tile buffer, and the shared empty one for every tile left undrawn.
  Rasterizer rasterizer({.threads = 1});
  std::vector<std::pair<const GBuffer*, bool>>
      tiles;  // buffer, and whether the frame's tile is empty
  int wrong = 0;
  const RasterStats stats = rasterizer.render_tiles(
      view, objects, [&](const GBuffer& tile, int x0, int y0, int x1, int y1, int) {
        bool frame_tile_empty = true;
        for (int y = y0; y < y1; ++y) {
          for (int x = x0; x < x1; ++x) {
            const std::size_t f = frame.index(x, y);
            const std::size_t t = tile.index(x - x0, y - y0);
            frame_tile_empty &= !frame.covered(f);
            const bool same = tile.flags[t] == frame.flags[f] &&
                              tile.object_id[t] == frame.object_id[f] &&
                              std::memcmp(&tile.depth[t], &frame.depth[f], sizeof(float)) == 0;
            wrong += same ? 0 : 1;
          }
        }
        tiles.emplace_back(&tile, frame_tile_empty);
      });
  EXPECT_EQ(wrong, 0);
  ASSERT_EQ(tiles.size(), 5u * 4u);
  std::map<const GBuffer*, int> tiles_by_buffer;
  for (const auto& [buffer, empty] : tiles) ++tiles_by_buffer[buffer];
  ASSERT_EQ(tiles_by_buffer.size(), 2u);
  const GBuffer* shared =
      std::max_element(tiles_by_buffer.begin(), tiles_by_buffer.end(),
                       [](const auto& a, const auto& b) { return a.second < b.second; })
          ->first;
  EXPECT_GE(tiles_by_buffer[shared], 15);  // the sphere's bounds reach a few tiles at most
  for (const auto& [buffer, empty] : tiles) {
    if (buffer == shared) {
      EXPECT_TRUE(empty);
    }
  }
  // The shared buffer is empty in every plane, as resolving an empty tile writes it.
  const GBuffer& empty = *shared;
  for (std::size_t i = 0; i < empty.pixel_count(); ++i) {
    ASSERT_EQ(empty.flags[i], 0u);
    ASSERT_EQ(empty.object_id[i], GBuffer::kNoObject);
    ASSERT_EQ(empty.depth[i], std::numeric_limits<float>::infinity());
    ASSERT_EQ(empty.texture_position[i], glm::dvec3(0.0));
    ASSERT_EQ(empty.normal[i], glm::vec3(0.0f));
    ASSERT_EQ(empty.footprint[i], 0.0f);
  }
  // Skipping tiles changes no count.
  EXPECT_EQ(stats.pixels_covered, frame_stats.pixels_covered);
  EXPECT_EQ(stats.back_face_pixels, frame_stats.back_face_pixels);
  EXPECT_EQ(stats.fragments_rasterized, frame_stats.fragments_rasterized);
  EXPECT_EQ(stats.fragments_depth_passed, frame_stats.fragments_depth_passed);
  EXPECT_EQ(stats.triangles_rasterized, frame_stats.triangles_rasterized);
}

bool refused(const RasterView& view, const RasterObject& object) {
  Rasterizer rasterizer({.threads = 1});
  GBuffer g;
  try {
    render_one(rasterizer, view, object, g);
  } catch (const std::invalid_argument&) {
    return true;
  }
  return false;
}

TEST(RasterizerArguments, BadViewsAndMeshesAreRefused) {
  const Mesh square = square_at(0.0f);
  RasterObject object;
  object.mesh = square.view();
  const glm::mat4 view_projection(1.0f);
  EXPECT_FALSE(refused({10, 10, view_projection, {}}, object));
  EXPECT_TRUE(refused({0, 10, view_projection, {}}, object));
  EXPECT_TRUE(refused({10, RasterView::kMaxSize + 1, view_projection, {}}, object));
  const std::vector<glm::dvec4> too_many(RasterView::kMaxClipPlanes + 1, {1, 0, 0, 0});
  EXPECT_TRUE(refused({10, 10, view_projection, too_many}, object));
  const std::vector<glm::dvec4> no_normal = {{0, 0, 0, 1}};
  EXPECT_TRUE(refused({10, 10, view_projection, no_normal}, object));
  const std::vector<glm::dvec4> not_finite = {{std::nan(""), 0, 1, 1}};
  EXPECT_TRUE(refused({10, 10, view_projection, not_finite}, object));

  RasterObject ragged = object;
  ragged.mesh.indices = ragged.mesh.indices.first(4);
  EXPECT_TRUE(refused({10, 10, view_projection, {}}, ragged));
  RasterObject short_normals = object;
  const std::vector<glm::vec3> one_normal = {{0, 0, 1}};
  short_normals.mesh.normals = one_normal;
  EXPECT_TRUE(refused({10, 10, view_projection, {}}, short_normals));
  EXPECT_THROW(Rasterizer({.threads = -1}), std::invalid_argument);
}

TEST(RasterizerArguments, EmptySceneClearsTheBuffer) {
  Rasterizer rasterizer({.threads = 2});
  GBuffer g;
  const RasterStats stats =
      rasterizer.render({70, 50, glm::mat4(1.0f), {}}, std::span<const RasterObject>(), g);
  EXPECT_EQ(g.width, 70);
  EXPECT_EQ(g.height, 50);
  EXPECT_EQ(stats.pixels_covered, 0u);
  for (std::size_t i = 0; i < g.pixel_count(); ++i) {
    EXPECT_FALSE(g.covered(i));
    EXPECT_EQ(g.object_id[i], GBuffer::kNoObject);
    EXPECT_EQ(g.depth[i], std::numeric_limits<float>::infinity());
  }
}

}  // namespace
}  // namespace soltex
