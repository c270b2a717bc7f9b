// Edge anti-aliasing: which pixels are edge pixels, what their coverage samples see, and how
// their surfaces' colours are blended.
#include "edge_antialiasing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <glm/vec3.hpp>
#include <limits>
#include <stdexcept>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/raster/rasterizer.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/default_scene.h"
#include "soltex/scene/scene_loader.h"

namespace soltex::render {
namespace {

constexpr float kNear = 0.1f, kFar = 100.0f;

GBuffer empty_tile(int size) {
  GBuffer g;
  g.resize(size, size, false);
  for (std::size_t i = 0; i < g.pixel_count(); ++i) {
    g.flags[i] = 0;
    g.object_id[i] = GBuffer::kNoObject;
    g.depth[i] = 1.0f;
  }
  return g;
}

// One open triangle facing the view (object id 0), with the storage its mesh points at.
struct FlatTriangle {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  std::vector<glm::vec3> normals = std::vector<glm::vec3>(3, glm::vec3(0.0f, 0.0f, 1.0f));

  RasterObject object() const {
    RasterObject o;
    o.mesh = {positions, normals, indices};
    o.object_id = 0;
    o.closed = false;
    return o;
  }
};

void cover(GBuffer& g, int x, int y, uint32_t object, float depth) {
  const std::size_t i = g.index(x, y);
  g.flags[i] = GBuffer::kCovered;
  g.object_id[i] = object;
  g.depth[i] = depth;
}

TEST(EdgeAntialiasing, EdgePixelsAreBothSidesOfAChangeOfSurface) {
  GBuffer g = empty_tile(8);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 3; ++x) cover(g, x, y, 1, 0.5f);
  }
  std::vector<glm::ivec2> edges;
  find_edge_pixels(g, 0, 0, 0, 0, 8, 8, kNear, kFar, edges);
  ASSERT_EQ(edges.size(), 16u);
  for (std::size_t k = 0; k < edges.size(); ++k) {
    EXPECT_EQ(edges[k], glm::ivec2(2 + static_cast<int>(k % 2), static_cast<int>(k / 2)));
  }
}

TEST(EdgeAntialiasing, EdgePixelsFollowTheFrameOffsetOfATile) {
  // The same pixels, from a tile whose G-buffer starts at frame pixel (64, 128).
  GBuffer g = empty_tile(8);
  for (int y = 0; y < 8; ++y) cover(g, 5, y, 3, 0.5f);
  std::vector<glm::ivec2> edges;
  find_edge_pixels(g, 64, 128, 64, 128, 72, 136, kNear, kFar, edges);
  ASSERT_EQ(edges.size(), 24u);  // columns 4, 5, 6
  EXPECT_EQ(edges.front(), glm::ivec2(68, 128));
  EXPECT_EQ(edges.back(), glm::ivec2(70, 135));
}

TEST(EdgeAntialiasing, DepthBreaksAreEdgesButSlopesAreNot) {
  // One object: a plane sloping in depth (window depth affine on screen) left of x = 5, a far
  // surface from x = 5 on.
  GBuffer g = empty_tile(8);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x)
      cover(g, x, y, 1, x < 5 ? 0.1f + 0.05f * static_cast<float>(x) : 0.9f);
  }
  std::vector<glm::ivec2> edges;
  find_edge_pixels(g, 0, 0, 0, 0, 8, 8, kNear, kFar, edges);
  std::vector<glm::ivec2> expected;
  for (int y = 0; y < 8; ++y) {
    expected.emplace_back(4, y);
    expected.emplace_back(5, y);
  }
  EXPECT_EQ(edges, expected);
}

TEST(EdgeAntialiasing, BlendWeighsColoursBySamplesAndRoundsHalfUp) {
  EdgePixel pixel;
  pixel.centre = 8;
  pixel.background = 4;
  pixel.extra = {4, 0, 0};
  const std::array<uint8_t, 3> centre{200, 0, 255}, background{30, 30, 30}, first{100, 1, 0};
  const std::array<uint8_t, 3> unused{255, 255, 255};
  std::array<uint8_t, 3> out{};
  blend_edge_pixel(pixel, 16, centre.data(), background.data(),
                   {first.data(), unused.data(), unused.data()}, out.data());
  // (8 * 200 + 4 * 30 + 4 * 100) / 16 = 132.5 -> 133; (4 * 30 + 4) / 16 = 7.75 -> 8;
  // (8 * 255 + 4 * 30) / 16 = 135.
  EXPECT_EQ(out, (std::array<uint8_t, 3>{133, 8, 135}));
}

// A triangle inside pixel (3, 2) that covers no pixel centre (x and y from 3.1 to 3.45 pixels):
// culled before anything is drawn, unless the frame samples its edges, where its samples count.
TEST(EdgeAntialiasing, ATriangleBetweenPixelCentresIsSeenByTheSamples) {
  const auto ndc_x = [](float x) { return x / 4.0f - 1.0f; };
  const auto ndc_y = [](float y) { return 1.0f - y / 4.0f; };
  const FlatTriangle triangle{{{ndc_x(3.1f), ndc_y(2.1f), 0.0f},
                               {ndc_x(3.45f), ndc_y(2.1f), 0.0f},
                               {ndc_x(3.1f), ndc_y(2.45f), 0.0f}},
                              {0, 2, 1}};
  const RasterObject object = triangle.object();
  for (const bool edge_sampling : {false, true}) {
    Rasterizer rasterizer({.threads = 1});
    RasterView view{8, 8, glm::mat4(1.0f), {}};
    view.edge_sampling = edge_sampling;
    EdgeSurfaces surfaces;
    const std::vector<glm::ivec2> pixels{{3, 2}};
    rasterizer.render_tiles(view, std::span(&object, 1),
                            [&](const GBuffer&, int x0, int y0, int, int, int worker) {
                              rasterizer.sample_edges(x0, y0, pixels, 4, worker, surfaces);
                            });
    if (!edge_sampling) {
      EXPECT_TRUE(surfaces.pixels.empty()) << "culled: no sample can see it";
      continue;
    }
    // Samples at 3.125 and 3.375 on each axis; the triangle holds (3.125, 2.125),
    // (3.375, 2.125) and (3.125, 2.375), below its diagonal.
    ASSERT_EQ(surfaces.pixels.size(), 1u);
    EXPECT_EQ(surfaces.pixels.front().extra[0], 3);
  }
}

// A triangle whose right edge runs down x = 3.4 pixels of an 8 x 8 view: pixel (3, y) has its
// centre outside and the left two of its four sample columns (x = 3.125, 3.375) inside.
TEST(EdgeAntialiasing, SamplesCountTheCoverageOfAnEdgePixel) {
  const float edge_x = 3.4f / 4.0f - 1.0f;  // NDC of x = 3.4 pixels
  const FlatTriangle triangle{{{-3.0f, -3.0f, 0.0f}, {edge_x, -3.0f, 0.0f}, {edge_x, 3.0f, 0.0f}},
                              {0, 1, 2}};
  const RasterObject object = triangle.object();
  Rasterizer rasterizer({.threads = 1});
  const RasterView view{8, 8, glm::mat4(1.0f), {}};
  EdgeSurfaces surfaces;
  const std::vector<glm::ivec2> pixels{{3, 2}, {1, 1}, {5, 5}};
  rasterizer.render_tiles(view, std::span(&object, 1),
                          [&](const GBuffer&, int x0, int y0, int, int, int worker) {
                            rasterizer.sample_edges(x0, y0, pixels, 4, worker, surfaces);
                          });
  EXPECT_EQ(surfaces.sample_count, 16);
  // (1, 1) and (5, 5) are wholly inside and wholly outside: their centres speak for them.
  ASSERT_EQ(surfaces.pixels.size(), 1u);
  const EdgePixel& p = surfaces.pixels.front();
  EXPECT_EQ(p.x, 3);
  EXPECT_EQ(p.y, 2);
  EXPECT_EQ(p.centre, 8) << "the centre sees nothing, as do the right two sample columns";
  EXPECT_EQ(p.background, 0) << "counted with the centre, which sees the background";
  EXPECT_EQ(p.extra[0], 8);
  EXPECT_EQ(p.extra[1], 0);
  // Its surface, at the covered sample nearest the middle of the covered ones: (3.125, 2.375),
  // in NDC here; within snapping of the vertices to 1/256 pixel (a sample's neighbours are
  // 0.0625 away).
  const GBuffer& layer = surfaces.layers[0];
  const std::size_t i = layer.index(3, 2);
  ASSERT_TRUE(layer.covered(i));
  EXPECT_EQ(layer.object_id[i], 0u);
  EXPECT_NEAR(layer.texture_position[i].x, 3.125 / 4.0 - 1.0, 1e-3);
  EXPECT_NEAR(layer.texture_position[i].y, 1.0 - 2.375 / 4.0, 1e-3);
  EXPECT_NEAR(layer.depth[i], 0.5f, 1e-6f);
  EXPECT_FALSE(surfaces.layers[0].covered(surfaces.layers[0].index(1, 1)));
}

TEST(EdgeAntialiasing, SampleEdgesRefusesAGridOutOfRange) {
  const std::vector<glm::vec3> positions{
      {-1.0f, -1.0f, 0.0f}, {1.0f, -1.0f, 0.0f}, {1.0f, 1.0f, 0.0f}};
  const std::vector<uint32_t> indices{0, 1, 2};
  RasterObject object;
  object.mesh = {positions, {}, indices};
  Rasterizer rasterizer({.threads = 1});
  const RasterView view{8, 8, glm::mat4(1.0f), {}};
  EdgeSurfaces surfaces;
  const std::vector<glm::ivec2> pixels{{3, 3}};
  bool refused = false;
  rasterizer.render_tiles(
      view, std::span(&object, 1), [&](const GBuffer&, int x0, int y0, int, int, int worker) {
        try {
          rasterizer.sample_edges(x0, y0, pixels, kMaxEdgeGrid + 1, worker, surfaces);
        } catch (const std::invalid_argument&) {
          refused = true;
        }
      });
  EXPECT_TRUE(refused);
}

// A scene prepared on an in-process source, and two renderers on its cache: plain, and with
// edge anti-aliasing at 4 x 4 samples. `scene` must outlive it.
struct PlainAndEdges {
  explicit PlainAndEdges(const Scene& scene)
      : source(cache), prepared(prepare_scene(scene, TextureResolution{6, 16, {}}, source)) {}
  BrickCache cache{256u << 20};
  net::LocalBrickSource source;
  PreparedScene prepared;
  FrameRenderer plain{cache, RenderOptions{.threads = 2}};
  FrameRenderer edges{cache, RenderOptions{.threads = 2, .edge_antialias = 4}};
};

// A closed box cut at an angle: its cut face reaches the box's bounds, and an edge sample's
// ray passes beside the face it samples, so its cap point may lie a little outside them. The
// bounds that reject caps traced through holes must keep every one of these: the frame is the
// same with the object unbounded.
TEST(EdgeAntialiasing, TheBoundsKeepEveryCapOfAClosedBox) {
  const Scene scene = parse_scene(R"({
    "camera": {"position": [2.5, 2, 3], "target": [0, 0, 0]},
    "objects": [{"name": "box", "mesh": {"box": {"size": 1.5}},
                 "material": {"texture": {"checker": {"size": [0.2, 0.2, 0.2], "three_d": true}}}}],
    "clip_planes": [{"normal": [0.3, 1, 0.5], "offset": 0.1}]})",
                                  "cut-box.json");
  PlainAndEdges r(scene);
  constexpr int kWidth = 320, kHeight = 240;
  const Frame bounded = r.edges.render(r.prepared, scene.camera, kWidth, kHeight);
  EXPECT_GT(bounded.stats.raster.cap_pixels, 5000u);
  PreparedScene unbounded = r.prepared;
  unbounded.objects[0].raster.bounds_min = glm::vec3(-std::numeric_limits<float>::infinity());
  unbounded.objects[0].raster.bounds_max = glm::vec3(std::numeric_limits<float>::infinity());
  const Frame anywhere = r.edges.render(unbounded, scene.camera, kWidth, kHeight);
  EXPECT_GT(anywhere.stats.edge_pixels, 500u);
  EXPECT_TRUE(bounded.image == anywhere.image);
}

// The default scene (silhouettes, a clip plane's caps, objects over one another), converged:
// with edge anti-aliasing the frame is nearer the 4 x 4 supersampled reference, and it differs
// from the plain frame at a few percent of the pixels only, all of them blended ones.
TEST(EdgeAntialiasing, FrameComesNearerTheSupersampledReference) {
  const Scene scene = default_scene();
  PlainAndEdges r(scene);
  auto& [cache, source, prepared, plain, edges] = r;
  constexpr int kWidth = 320, kHeight = 180;
  const auto converged = [&](FrameRenderer& renderer) {
    Frame frame = renderer.render(prepared, scene.camera, kWidth, kHeight);
    for (int i = 0; i < 50 && !(frame.complete() && source.idle()); ++i) {
      source.want(std::move(frame.misses));
      source.wait_idle(std::chrono::seconds(5));
      frame = renderer.render(prepared, scene.camera, kWidth, kHeight);
    }
    EXPECT_TRUE(frame.complete());
    return frame;
  };
  const Frame without = converged(plain);
  const Frame with = converged(edges);
  const Image reference = plain.render_reference(prepared, scene.camera, kWidth, kHeight, 4);
  EXPECT_EQ(without.stats.edge_pixels, 0u);
  EXPECT_GT(with.stats.edge_pixels, 0u);
  EXPECT_LT(with.stats.edge_pixels, static_cast<std::size_t>(kWidth * kHeight / 10));
  EXPECT_EQ(with.stats.covered_pixels, without.stats.covered_pixels)
      << "the extra surfaces are not counted as pixels";
  // Over the pixels it changed, the squared error against the reference; the rest of the
  // error (textures cached against evaluated) is the same in both.
  std::size_t differing = 0;
  double error_without = 0.0, error_with = 0.0;
  for (std::size_t p = 0; p < without.image.rgb.size(); p += 3) {
    double a = 0.0, b = 0.0;
    for (std::size_t c = p; c < p + 3; ++c) {
      const double d0 =
          static_cast<double>(without.image.rgb[c]) - static_cast<double>(reference.rgb[c]);
      const double d1 =
          static_cast<double>(with.image.rgb[c]) - static_cast<double>(reference.rgb[c]);
      a += d0 * d0;
      b += d1 * d1;
    }
    if (without.image.rgb[p] == with.image.rgb[p] &&
        without.image.rgb[p + 1] == with.image.rgb[p + 1] &&
        without.image.rgb[p + 2] == with.image.rgb[p + 2]) {
      continue;
    }
    ++differing;
    error_without += a;
    error_with += b;
  }
  EXPECT_GT(differing, 0u);
  EXPECT_LE(differing, with.stats.edge_pixels);
  EXPECT_LT(error_with, 0.8 * error_without);  // 0.68 when written
  EXPECT_GT(psnr(with.image, reference), psnr(without.image, reference));
}

// A sphere cut to a slab and seen from above: the slab's top face is a cap whose solid has no
// back face left behind it. Edge samples along its rim see that cap as the pixels do; a sample
// that saw nothing there would blend the background into the rim as a dotted dark line.
TEST(EdgeAntialiasing, SamplesSeeTheCapOfASlab) {
  const Scene scene = parse_scene(
      R"({"camera": {"position": [0, 2.5, 4], "target": [0, 0, 0], "fov_y_degrees": 40},
          "objects": [{"mesh": {"sphere": {"segments": 128, "rings": 64}},
                       "material": {"unlit": true, "texture": {"stripes": {"width": 0.2}}}}],
          "clip_planes": [{"normal": [0, 1, 0], "offset": 0.3},
                          {"normal": [0, -1, 0], "offset": 0.3}]})",
      "<slab>");
  PlainAndEdges r(scene);
  auto& [cache, source, prepared, plain, edges] = r;
  constexpr int kWidth = 200, kHeight = 200;
  const Frame without = plain.render(prepared, scene.camera, kWidth, kHeight);
  const Frame with = edges.render(prepared, scene.camera, kWidth, kHeight);
  ASSERT_TRUE(without.complete() && with.complete()) << "stripes are evaluated per pixel";
  const Image reference = plain.render_reference(prepared, scene.camera, kWidth, kHeight, 4);
  EXPECT_GT(with.stats.edge_pixels, 0u);
  const auto brightness = [](const Image& image, std::size_t p) {
    return int{image.rgb[p]} + int{image.rgb[p + 1]} + int{image.rgb[p + 2]};
  };
  int darker = 0;
  for (std::size_t p = 0; p < with.image.rgb.size(); p += 3) {
    const int b = brightness(with.image, p);
    darker += b < brightness(without.image, p) - 150 && b < brightness(reference, p) - 150;
  }
  EXPECT_LE(darker, 2);
}

TEST(EdgeAntialiasing, RendererRefusesAGridOutOfRange) {
  BrickCache cache(1u << 20);
  EXPECT_THROW(FrameRenderer(cache, RenderOptions{.edge_antialias = kMaxEdgeGrid + 1}),
               std::invalid_argument);
  EXPECT_THROW(FrameRenderer(cache, RenderOptions{.edge_antialias = -1}), std::invalid_argument);
}

}  // namespace
}  // namespace soltex::render
