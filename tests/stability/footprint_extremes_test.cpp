// The two ends of the footprint: grazing angles (footprint -> infinity) and the camera
// touching the surface (footprint -> 0).
#include <gtest/gtest.h>

#include <cmath>
#include <glm/matrix.hpp>
#include <limits>
#include <optional>

#include "soltex/common/texture_sampler.h"
#include "soltex/render/anisotropic_taps.h"
#include "soltex/scene/builtin_meshes.h"
#include "stability_scene.h"

namespace soltex {
namespace {

constexpr int kWidth = 64;
constexpr int kHeight = 48;

TextureSpec marble() {
  TextureSpec spec;
  spec.pattern = MarbleParams{};
  return spec;
}

// The double-precision reference: the ray through a pixel position against the plane y = 0
// (the plane mesh, untransformed, so object space is world space).
class PlaneReference {
 public:
  explicit PlaneReference(const Camera& camera)
      : inverse_vp_(glm::inverse(view_projection(camera, kWidth, kHeight))),
        eye_(camera.position) {}

  std::optional<glm::dvec3> hit(double px, double py) const {
    const glm::dvec4 h =
        inverse_vp_ * glm::dvec4(px / kWidth * 2.0 - 1.0, 1.0 - py / kHeight * 2.0, 1.0, 1.0);
    const glm::dvec3 direction = glm::dvec3(h) / h.w - eye_;
    const double t = -eye_.y / direction.y;
    if (!(t > 0.0) || !std::isfinite(t)) return std::nullopt;
    return eye_ + t * direction;
  }
  // The larger distance on the plane between the pixel's hit and its right and lower
  // neighbours' hits: the footprint; infinity where a neighbour's ray misses the plane.
  double footprint(int x, int y) const {
    const auto centre = hit(x + 0.5, y + 0.5);
    const auto right = hit(x + 1.5, y + 0.5);
    const auto below = hit(x + 0.5, y + 1.5);
    if (!centre || !right || !below) return std::numeric_limits<double>::infinity();
    return std::max(glm::length(*right - *centre), glm::length(*below - *centre));
  }

 private:
  glm::dmat4 inverse_vp_;
  glm::dvec3 eye_;
};

// ---- Grazing angles --------------------------------------------------------------------------

// A 200 x 200 floor seen from half a unit above it, looking along it: the rows just below the
// horizon meet it at under 1/100 radian, where one pixel covers several coarsest voxels.
// Expected: the G-buffer stays defined, its texture positions are the reference's within
// f / 20 (snapping to 1/256 pixel and float interpolation move a point by far less), every
// tap of every pixel is resident once converged, every pixel whose reference footprint's
// share per tap is at least twice the coarsest spacing draws from the coarsest level, and no
// pixel of the converged image is black (unlit: a pixel is its texture colour, which the ramp
// never makes black; a NaN would be written as 0). With one lookup per pixel (anisotropy 1)
// such pixels exist; with the default taps along the long side (up to 8) every share may be
// finer.
class GrazingFloor : public ::testing::TestWithParam<int> {};

TEST_P(GrazingFloor, ChoosesTheCoarsestLevelAndStaysFinite) {
  const int anisotropy = GetParam();
  SceneObject floor = stability::make_object("floor", PlaneShape{{200.0, 200.0}, 16}, marble(),
                                             TextureSpace::object, /*unlit=*/true);
  Scene scene =
      stability::make_scene({floor}, {0.0, 0.5, 8.0}, {0.0, 0.5, -100.0}, kWidth, kHeight);
  scene.camera.far = 1000.0;
  stability::LocalRender render(std::size_t{256} << 20, RenderOptions{.anisotropy = anisotropy});
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{8, 16, {}}, render.source);
  const stability::ConvergedFrame result = stability::render_until_converged(
      render.renderer, prepared, scene.camera, kWidth, kHeight, render.source);
  ASSERT_TRUE(result.converged);
  EXPECT_EQ(result.frame.stats.empty_pixels, 0u);

  const GBuffer g = stability::rasterize(prepared, scene.camera, kWidth, kHeight);
  EXPECT_TRUE(stability::gbuffer_defined(g));
  const PreparedObject& object = prepared.objects[0];
  const int coarsest = object.layout.coarsest_level();
  const double coarsest_spacing = object.layout.filter_width(coarsest);
  TextureSampler sampler(render.cache, object.texture_id, object.layout, object.channels);
  const PlaneReference reference(scene.camera);
  std::size_t grazing = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t i = g.index(x, y);
      if (!g.covered(i)) continue;
      const double f = reference.footprint(x, y);
      const auto hit = reference.hit(x + 0.5, y + 0.5);
      ASSERT_TRUE(hit.has_value()) << x << " " << y;
      EXPECT_LE(glm::length(g.texture_position[i] - *hit), f / 20.0) << x << " " << y;
      const int n = render::tap_count(g.footprint[i], g.footprint_minor[i], anisotropy);
      const double lod = sampler.level_of_detail(g.footprint[i] / static_cast<float>(n));
      for (int k = 0; k < n; ++k) {
        const glm::dvec3 tap =
            render::tap_position(g.texture_position[i], g.footprint_axis[i], k, n);
        const SampleResult sample =
            sampler.sample(n == 1 ? g.texture_position[i] : tap, lod, SampleFilter::trilinear);
        EXPECT_TRUE(sample.complete) << x << " " << y << " tap " << k << " of " << n;
        if (f / n >= 2.0 * coarsest_spacing) {
          EXPECT_EQ(sample.level, coarsest) << x << " " << y;
        }
      }
      if (f / n >= 2.0 * coarsest_spacing) {
        ++grazing;
        EXPECT_EQ(lod, coarsest) << x << " " << y << " footprint " << g.footprint[i];
      }
      const uint8_t* rgb = &result.frame.image.rgb[3 * i];
      EXPECT_GT(rgb[0] + rgb[1] + rgb[2], 0) << x << " " << y;
    }
  }
  if (anisotropy == 1) {
    EXPECT_GT(grazing, 0u);
  }
  RecordProperty("grazing_pixels", std::to_string(grazing));
}

INSTANTIATE_TEST_SUITE_P(FootprintExtremes, GrazingFloor, ::testing::Values(1, 8),
                         [](const auto& info) {
                           return "Anisotropy" + std::to_string(info.param);
                         });

// The camera exactly in the plane of a single sheet: every triangle is edge-on. Expected:
// nothing covered, no crash, the triangles counted as degenerate or culled.
TEST(FootprintExtremes, SheetSeenExactlyEdgeOnDrawsNothing) {
  SceneObject floor = stability::make_object("floor", PlaneShape{{20.0, 20.0}, 4}, marble());
  const Scene scene =
      stability::make_scene({floor}, {0.0, 0.0, 15.0}, {0.0, 0.0, 0.0}, kWidth, kHeight);
  stability::LocalRender render;
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{6, 16, {}}, render.source);
  RasterStats stats;
  const GBuffer g = stability::rasterize(prepared, scene.camera, kWidth, kHeight, &stats);
  EXPECT_EQ(stats.pixels_covered, 0u);
  EXPECT_EQ(stats.triangles_degenerate + stats.triangles_culled, stats.triangles_in);
  const Frame frame = render.renderer.render(prepared, scene.camera, kWidth, kHeight);
  EXPECT_EQ(frame.stats.covered_pixels, 0u);
  EXPECT_TRUE(frame.misses.empty());
}

// ---- The camera touching the surface ---------------------------------------------------------

// The camera 1e-4 above the floor, looking straight down (near plane 1e-6): a pixel covers
// about 2e-6 units, 1/8000 of the finest spacing, so log2(f / h_0) is about -13. Expected:
// level 0 everywhere (the level of detail is clamped, never negative), positions as the
// reference's, and the converged frame asked for level-0 bricks only (besides the coarsest
// brick every first frame asks for).
//
// Position tolerance: f / 20 as for any view, plus what the two triangles' size brings here.
// Their vertices lie 50,000 pixels off screen, so they are clipped to the guard band, and a
// clipped vertex carries float barycentric weights (a few 2^-24 of error each) that multiply
// edges of up to 2 sqrt(2): 2^-22 times the longest edge, 6.7e-7, is a third of a pixel here
// and 1/25000 of a level-0 voxel, which is what the texture can show.
TEST(FootprintExtremes, CameraTouchingTheSurfaceUsesLevelZero) {
  SceneObject floor = stability::make_object("floor", PlaneShape{{2.0, 2.0}, 1}, marble());
  Scene scene = stability::make_scene({floor}, {0.1, 1e-4, 0.2}, {0.1, 0.0, 0.2}, kWidth, kHeight);
  scene.camera.up = {0.0, 0.0, -1.0};
  scene.camera.near = 1e-6;
  scene.camera.far = 10.0;
  stability::LocalRender render;
  const PreparedScene prepared = prepare_scene(scene, TextureResolution{7, 16, {}}, render.source);
  const stability::ConvergedFrame result = stability::render_until_converged(
      render.renderer, prepared, scene.camera, kWidth, kHeight, render.source);
  ASSERT_TRUE(result.converged);
  EXPECT_EQ(result.frame.stats.covered_pixels, static_cast<std::size_t>(kWidth * kHeight));
  const PreparedObject& object = prepared.objects[0];
  for (const BrickKey& key : result.requested) {
    EXPECT_TRUE(key.level == 0 || key.level == object.layout.coarsest_level()) << key.level;
  }

  const GBuffer g = stability::rasterize(prepared, scene.camera, kWidth, kHeight);
  EXPECT_TRUE(stability::gbuffer_defined(g));
  TextureSampler sampler(render.cache, object.texture_id, object.layout, object.channels);
  const PlaneReference reference(scene.camera);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t i = g.index(x, y);
      ASSERT_TRUE(g.covered(i));
      const auto hit = reference.hit(x + 0.5, y + 0.5);
      ASSERT_TRUE(hit.has_value());
      EXPECT_LE(glm::length(g.texture_position[i] - *hit),
                reference.footprint(x, y) / 20.0 + std::ldexp(2.0 * std::sqrt(2.0), -22))
          << x << " " << y;
      EXPECT_GT(g.footprint[i], 0.0f);
      const double lod = sampler.level_of_detail(g.footprint[i]);
      EXPECT_EQ(lod, 0.0);
      EXPECT_EQ(sampler.sample(g.texture_position[i], lod, SampleFilter::trilinear).level, 0);
    }
  }
}

// The limits themselves, through the sampler: footprint 0, negative, -inf and subnormal give
// level 0; +inf, NaN and 1e300 the coarsest. A negative or NaN level of detail handed to
// sample() is clamped the same way.
TEST(FootprintExtremes, LevelOfDetailLimits) {
  const BrickLayout layout(Volume{glm::dvec3(-1.0), glm::dvec3(1.0), 6}, 16);
  const int coarsest = layout.coarsest_level();
  const double inf = std::numeric_limits<double>::infinity();
  for (double f : {0.0, -0.0, -1.0, -inf, std::numeric_limits<double>::denorm_min(), 1e-300}) {
    EXPECT_EQ(level_of_detail(layout, f), 0.0) << f;
  }
  for (double f : {inf, std::numeric_limits<double>::quiet_NaN(), 1e300}) {
    EXPECT_EQ(level_of_detail(layout, f), coarsest) << f;
  }

  TextureSpec spec = validated(marble());
  BrickCache cache(std::size_t{64} << 20);
  net::LocalBrickSource source(cache);
  const uint64_t id = source.register_texture(spec, layout.volume(), 16, {});
  TextureSampler sampler(cache, id, layout, 3);
  const glm::dvec3 p(0.3, -0.2, 0.7);
  std::vector<net::BrickWant> wants;
  for (int level = 0; level <= coarsest; ++level) wants.push_back({sampler.brick_key(p, level), 1});
  source.want(wants);
  while (!source.wait_idle(std::chrono::milliseconds(100))) {
  }
  for (double lod : {-1.0, -inf, -0.0}) {
    EXPECT_EQ(sampler.sample(p, lod, SampleFilter::trilinear).level, 0) << lod;
  }
  for (double lod : {inf, std::numeric_limits<double>::quiet_NaN(), 1e9}) {
    EXPECT_EQ(sampler.sample(p, lod, SampleFilter::trilinear).level, coarsest) << lod;
    EXPECT_EQ(sampler.sample(p, lod, SampleFilter::quadrilinear).level, coarsest) << lod;
  }
  EXPECT_EQ(sampler.sample_footprint(p, inf, SampleFilter::nearest).level, coarsest);
  EXPECT_EQ(sampler.sample_footprint(p, 0.0, SampleFilter::nearest).level, 0);
}

}  // namespace
}  // namespace soltex
