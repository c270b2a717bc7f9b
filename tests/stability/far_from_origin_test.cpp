// Objects far from the origin: the same small scene translated by 1e4, 1e6 and 1e9, with its
// texture in object space and in world space.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/matrix.hpp>
#include <limits>
#include <optional>
#include <string>

#include "soltex/raster/rasterizer.h"
#include "soltex/scene/builtin_meshes.h"
#include "soltex/scene/texture_volume.h"
#include "stability_scene.h"

namespace soltex {
namespace {

using stability::LocalRender;
using stability::make_object;
using stability::make_scene;

constexpr int kWidth = 96;
constexpr int kHeight = 64;
// Where the camera sits relative to the object: exactly representable, so that eye - offset
// is exact in double at every offset below and the relative geometry is the same.
const glm::dvec3 kEyeFromObject(0.0, 0.75, 3.5);
constexpr double kBoxHalfSide = 0.8;
constexpr double kInf = std::numeric_limits<double>::infinity();

// For RecordProperty: 3 significant digits in any magnitude (std::to_string prints 1e-7 as 0).
std::string short_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

TextureSpec marble() {
  TextureSpec spec;
  MarbleParams m;
  m.turbulence.octave_max = 6;
  spec.pattern = m;
  return spec;
}

Scene scene_at(double offset, const BuiltinShape& shape, TextureSpace space) {
  const glm::dvec3 shift(offset);
  SceneObject object = make_object("object", shape, marble(), space);
  object.transform.translate = shift;
  object.transform.rotate_degrees = glm::dvec3(25.0, 35.0, 0.0);
  return make_scene({object}, shift + kEyeFromObject, shift, kWidth, kHeight);
}

Image converged_image(const Scene& scene) {
  LocalRender render;
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{7, 16, {}}, render.source);
  const stability::ConvergedFrame result = stability::render_until_converged(
      render.renderer, prepared, scene.camera, kWidth, kHeight, render.source);
  EXPECT_TRUE(result.converged);
  EXPECT_GT(result.frame.stats.covered_pixels, 0u);
  return result.frame.image;
}

class FarFromOrigin : public ::testing::TestWithParam<double> {};

INSTANTIATE_TEST_SUITE_P(Offsets, FarFromOrigin, ::testing::Values(1e4, 1e6, 1e9));

// Object space: the texture moves with the object, and the camera moves with both, so
// nothing the viewer can see changes. Expected: the same image, bit for bit, because every
// quantity that reaches a pixel (camera-relative geometry, object-space texture positions)
// is the same at every offset; only a renderer that forms far-away positions in float can
// tell the offsets apart.
TEST_P(FarFromOrigin, ObjectSpaceImageIsBitIdenticalToTheUntranslatedOne) {
  const SphereShape sphere{1.0, 32, 16};
  const Image home = converged_image(scene_at(0.0, sphere, TextureSpace::object));
  const Image far = converged_image(scene_at(GetParam(), sphere, TextureSpace::object));
  std::size_t differing = 0;
  for (std::size_t i = 0; i < home.rgb.size(); ++i) differing += home.rgb[i] != far.rgb[i];
  EXPECT_EQ(differing, 0u) << "of " << home.rgb.size() << " bytes";
}

// The double-precision reference of what a pixel sees: the ray through its centre, from the
// camera, against the box in its object space (slab test), all relative to the object so that
// no far-away sum rounds before the last step.
struct ReferenceHit {
  glm::dvec3 texture_position;  // world space: offset + R * hit
  double footprint;             // the larger step of the hit point per pixel step on its face
};

class ReferenceCamera {
 public:
  ReferenceCamera(const Scene& scene, double offset)
      : offset_(offset), model_(scene.objects[0].transform.matrix()) {
    Camera relative = scene.camera;
    relative.position -= glm::dvec3(offset);
    relative.target -= glm::dvec3(offset);
    inverse_vp_ = glm::inverse(view_projection(relative, kWidth, kHeight));
    eye_ = relative.position;
    glm::dmat4 rotation = model_;
    rotation[3] = glm::dvec4(0.0, 0.0, 0.0, 1.0);
    object_from_relative_ = glm::inverse(rotation);
    relative_from_object_ = rotation;
  }

  std::optional<ReferenceHit> hit(int x, int y) const {
    int axis = 0;
    const std::optional<glm::dvec3> centre = box_hit(x + 0.5, y + 0.5, &axis);
    if (!centre) return std::nullopt;
    const glm::dvec3 dx = face_hit(x + 1.5, y + 0.5, axis, (*centre)[axis]) - *centre;
    const glm::dvec3 dy = face_hit(x + 0.5, y + 1.5, axis, (*centre)[axis]) - *centre;
    const glm::dvec3 relative = glm::dvec3(relative_from_object_ * glm::dvec4(*centre, 1.0));
    return ReferenceHit{glm::dvec3(offset_) + relative, std::max(glm::length(dx), glm::length(dy))};
  }

 private:
  // The ray through pixel coordinate (px, py), in the box's object space.
  void ray(double px, double py, glm::dvec3& origin, glm::dvec3& direction) const {
    const double ndc_x = px / kWidth * 2.0 - 1.0;
    const double ndc_y = 1.0 - py / kHeight * 2.0;
    const glm::dvec4 far_h = inverse_vp_ * glm::dvec4(ndc_x, ndc_y, 1.0, 1.0);
    const glm::dvec3 far_point = glm::dvec3(far_h) / far_h.w;
    origin = glm::dvec3(object_from_relative_ * glm::dvec4(eye_, 1.0));
    direction = glm::dvec3(object_from_relative_ * glm::dvec4(far_point - eye_, 0.0));
  }

  std::optional<glm::dvec3> box_hit(double px, double py, int* axis) const {
    glm::dvec3 o, d;
    ray(px, py, o, d);
    double t_near = -kInf, t_far = kInf;
    for (int a = 0; a < 3; ++a) {
      const double t0 = (-kBoxHalfSide - o[a]) / d[a];
      const double t1 = (kBoxHalfSide - o[a]) / d[a];
      if (std::min(t0, t1) > t_near) {
        t_near = std::min(t0, t1);
        *axis = a;
      }
      t_far = std::min(t_far, std::max(t0, t1));
    }
    if (!(t_near <= t_far) || t_near <= 0.0) return std::nullopt;
    return o + t_near * d;
  }

  glm::dvec3 face_hit(double px, double py, int axis, double face) const {
    glm::dvec3 o, d;
    ray(px, py, o, d);
    return o + (face - o[axis]) / d[axis] * d;
  }

  double offset_;
  glm::dmat4 model_;
  glm::dmat4 inverse_vp_;
  glm::dvec3 eye_;
  glm::dmat4 object_from_relative_;
  glm::dmat4 relative_from_object_;
};

// Compares the G-buffer's texture positions with the reference at every pixel both call
// covered. Tolerance, relative to the pixel's footprint f (about 0.03 here): vertices are
// snapped to 1/256 pixel, which moves a surface point by at most about f / 256 along the
// surface, and interpolating float offsets from the triangle's double origin adds a few
// 2^-24 of its longest edge (0.57 for the 1.6 box cut 4 times per face: about 1e-7). f / 20
// leaves a wide margin for both and is far below what a texture lookup at that footprint can
// resolve.
void expect_positions_match_reference(const GBuffer& g, const ReferenceCamera& reference) {
  std::size_t compared = 0, coverage_disagrees = 0;
  double worst = 0.0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t i = g.index(x, y);
      const std::optional<ReferenceHit> hit = reference.hit(x, y);
      if (g.covered(i) != hit.has_value()) {
        ++coverage_disagrees;
        continue;
      }
      if (!hit) continue;
      ++compared;
      const double error = glm::length(g.texture_position[i] - hit->texture_position);
      worst = std::max(worst, error / hit->footprint);
      ASSERT_LE(error, hit->footprint / 20.0)
          << "pixel (" << x << ", " << y << "): " << g.texture_position[i].x << ", "
          << g.texture_position[i].y << ", " << g.texture_position[i].z << " vs "
          << hit->texture_position.x << ", " << hit->texture_position.y << ", "
          << hit->texture_position.z;
    }
  }
  EXPECT_GT(compared, static_cast<std::size_t>(kWidth * kHeight / 8));
  // Only pixel centres within a snapping step of the silhouette may disagree.
  EXPECT_LE(coverage_disagrees, 2u * (kWidth + kHeight));
  ::testing::Test::RecordProperty("worst_error_in_footprints", short_number(worst));
}

// World space: the object moves through the texture, so its texture positions are world
// positions, 1e9 and all. The G-buffer is made from the raster input prepare_scene() builds
// and the view FrameRenderer::render() builds; expected: every covered pixel's texture
// position within f / 20 of the double-precision ray-surface point.
TEST_P(FarFromOrigin, WorldSpaceTexturePositionsMatchTheDoubleReference) {
  const double offset = GetParam();
  const Scene scene =
      scene_at(offset, BoxShape{glm::dvec3(2.0 * kBoxHalfSide), 4}, TextureSpace::world);
  LocalRender render;
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{7, 16, {}}, render.source);
  const GBuffer g = stability::rasterize(prepared, scene.camera, kWidth, kHeight);
  expect_positions_match_reference(g, ReferenceCamera(scene, offset));
}

// The G-buffer's own contract, apart from how a renderer forms its matrices: geometry given
// relative to the camera (small numbers) with a texture space 1e9 away keeps the texture
// positions to the same f / 20.
TEST_P(FarFromOrigin, CameraRelativeGeometryKeepsFarTexturePositions) {
  const double offset = GetParam();
  const Scene home =
      scene_at(0.0, BoxShape{glm::dvec3(2.0 * kBoxHalfSide), 4}, TextureSpace::world);
  const Scene far =
      scene_at(offset, BoxShape{glm::dvec3(2.0 * kBoxHalfSide), 4}, TextureSpace::world);
  const Mesh& mesh = *home.objects[0].mesh;
  RasterObject object;
  object.mesh = {mesh.positions, mesh.normals, mesh.indices};
  object.model = glm::mat4(home.objects[0].transform.matrix());
  object.texture_from_object = far.objects[0].transform.matrix();
  RasterView view;
  view.width = kWidth;
  view.height = kHeight;
  view.view_projection = glm::mat4(view_projection(home.camera, kWidth, kHeight));
  Rasterizer rasterizer;
  GBuffer g;
  rasterizer.render(view, {&object, 1}, g);
  expect_positions_match_reference(g, ReferenceCamera(far, offset));
}

// The default cache cube of a world-space object is the box of its vertices' world
// positions, padded. Expected at every offset: it holds every vertex (computed in double),
// and its side is the object's size plus the padding (1/32 of it at each end), not the
// spacing of floats at 1e9 (64 units).
TEST_P(FarFromOrigin, WorldSpaceVolumeHoldsTheObject) {
  const double offset = GetParam();
  const Scene scene =
      scene_at(offset, BoxShape{glm::dvec3(2.0 * kBoxHalfSide), 4}, TextureSpace::world);
  const SceneObject& object = scene.objects[0];
  const Volume volume = texture_volume(object, 7);
  const glm::dmat4 model = object.transform.matrix();
  glm::dvec3 lo(kInf), hi(-kInf);
  for (const glm::vec3& p : object.mesh->positions) {
    const glm::dvec3 world(model * glm::dvec4(glm::dvec3(p), 1.0));
    lo = glm::min(lo, world);
    hi = glm::max(hi, world);
    for (int axis = 0; axis < 3; ++axis) {
      ASSERT_GE(world[axis], volume.min[axis]) << "axis " << axis;
      ASSERT_LE(world[axis], volume.max[axis]) << "axis " << axis;
    }
  }
  const glm::dvec3 size = hi - lo;
  const double expected_side = std::max({size.x, size.y, size.z}) * (1.0 + 2.0 / 32.0);
  // A cube 5 % too large or too small shifts every pixel's level of detail by under
  // log2(1.05) = 0.07 levels, which trilinear lookups round away. A side of float spacing at
  // 1e9 (64) would be 23 times too large; collapsed to the minimum (1e-3), it misses the object.
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(volume.max[axis] - volume.min[axis], expected_side, 0.05 * expected_side)
        << "axis " << axis;
  }
}

}  // namespace
}  // namespace soltex
