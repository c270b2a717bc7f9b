// RasterObject::cull_back_faces: back faces dropped at set-up, unless a clip plane cuts the
// object (its caps are found through back faces).
#include <gtest/gtest.h>

#include <vector>

#include "raster_test_scenes.h"
#include "soltex/raster/rasterizer.h"

namespace soltex {
namespace {

using raster_test::expect_same_buffer;
using raster_test::Mesh;

constexpr int kWidth = 160;
constexpr int kHeight = 120;

// Two triangles, counter-clockwise seen from +z, big enough to cross the near plane when the
// eye is close.
Mesh square(float half) {
  Mesh m;
  m.positions = {{-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
  m.add_triangle(0, 1, 2);
  m.add_triangle(0, 2, 3);
  return m;
}

const Mesh& sphere() {
  static const Mesh mesh = raster_test::uv_sphere(48, 96);
  return mesh;
}

RasterStats render(const RasterView& view, const RasterObject& object, GBuffer& g) {
  Rasterizer rasterizer({.threads = 2});
  return rasterizer.render(view, std::span<const RasterObject>(&object, 1), g);
}

RasterView looking_at(const glm::vec3& eye, std::vector<glm::dvec4> planes = {}) {
  return {kWidth, kHeight, raster_test::perspective_look_at(eye, {0, 0, 0}, kWidth, kHeight),
          std::move(planes)};
}

// An open sheet drawn front faces only.
RasterObject open_front_faces_only(const Mesh& mesh) {
  RasterObject object{mesh.view()};
  object.closed = false;
  object.cull_back_faces = true;
  return object;
}

TEST(FaceCulling, FrontFacesAreDrawnBackFacesAreDropped) {
  const Mesh mesh = square(1.0f);
  RasterObject object = open_front_faces_only(mesh);
  GBuffer g;
  const RasterStats front = render(looking_at({0, 0, 3}), object, g);
  EXPECT_EQ(front.triangles_back_face_culled, 0u);
  EXPECT_TRUE(g.covered(g.index(kWidth / 2, kHeight / 2)));
  const RasterStats back = render(looking_at({0, 0, -3}), object, g);
  EXPECT_EQ(back.triangles_back_face_culled, 2u);
  EXPECT_EQ(back.triangles_rasterized, 0u);
  EXPECT_EQ(back.pixels_covered, 0u);
  EXPECT_FALSE(g.covered(g.index(kWidth / 2, kHeight / 2)));
}

TEST(FaceCulling, BackFacesCutByTheNearPlaneAreDroppedToo) {
  // The eye close behind a large square: both triangles cross the near plane and are clipped
  // first; the pieces face away.
  const Mesh mesh = square(100.0f);
  RasterObject object = open_front_faces_only(mesh);
  GBuffer g;
  const RasterView view{
      kWidth,
      kHeight,
      raster_test::perspective_look_at({0.3f, 0.2f, -0.5f}, {0, 0, 5}, kWidth, kHeight),
      {}};
  const RasterStats culled = render(view, object, g);
  EXPECT_GT(culled.triangles_clipped_near, 0u);
  EXPECT_GT(culled.triangles_back_face_culled, 0u);
  EXPECT_EQ(culled.pixels_covered, 0u);
  object.cull_back_faces = false;
  const RasterStats drawn = render(view, object, g);
  EXPECT_GT(drawn.pixels_covered, 0u);
  EXPECT_EQ(drawn.back_face_pixels, drawn.pixels_covered);
}

TEST(FaceCulling, AClosedMeshSeenFromOutsideLooksTheSame) {
  RasterObject object{sphere().view()};
  GBuffer both, front;
  for (const glm::vec3 eye : {glm::vec3(0, 0, 3), glm::vec3(1.5f, 2.0f, -1.2f)}) {
    object.cull_back_faces = false;
    const RasterStats drawn = render(looking_at(eye), object, both);
    object.cull_back_faces = true;
    const RasterStats culled = render(looking_at(eye), object, front);
    // About half the triangles face away, and those cost no drawing.
    EXPECT_GT(culled.triangles_back_face_culled, drawn.triangles_rasterized / 3);
    EXPECT_LT(culled.fragments_rasterized, drawn.fragments_rasterized);
    EXPECT_EQ(drawn.back_face_pixels, 0u);
    expect_same_buffer(both, front);
  }
}

TEST(FaceCulling, ObjectsCutByAClipPlaneKeepBackFacesForTheirCaps) {
  const std::vector<glm::dvec4> planes = {{0.0, 0.0, -1.0, 0.0}};
  RasterObject object{sphere().view()};
  GBuffer both, front;
  object.cull_back_faces = false;
  const RasterStats drawn = render(looking_at({0, 0, 3}, planes), object, both);
  object.cull_back_faces = true;
  const RasterStats culled = render(looking_at({0, 0, 3}, planes), object, front);
  EXPECT_EQ(culled.triangles_back_face_culled, 0u);
  EXPECT_GT(culled.cap_pixels, 1000u);
  EXPECT_EQ(culled.cap_pixels, drawn.cap_pixels);
  expect_same_buffer(both, front);

  // The same plane in the view, but cutting nothing of this object: culling applies.
  object.clip_plane_mask = 0;
  const RasterStats uncut = render(looking_at({0, 0, 3}, planes), object, front);
  EXPECT_GT(uncut.triangles_back_face_culled, 0u);
  EXPECT_EQ(uncut.cap_pixels, 0u);
}

}  // namespace
}  // namespace soltex
