// TriangleSetup::setup_range(), whose common triangles are set up in vector lanes
// (client/raster/src/setup_kernels.cpp), against setup() one triangle at a time, on every
// Highway target the CPU runs.

#include "triangle_setup.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/ext/matrix_transform.hpp>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "../texture/dispatch_targets.h"
#include "object_frame.h"
#include "raster_test_scenes.h"
#include "setup_kernels.h"

namespace soltex::raster_internal {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 200;

// A mesh in front of the camera: small triangles over the view and past its edges (a few
// pixels to a hundred across, some between pixel centres, some off screen), some crossing the
// near plane or far past the guard band, degenerate ones, vertices that are not finite,
// indices out of range, and where it has normals some that transforming leaves without a
// direction (zero, NaN, or too long for float: then the triangle takes its face normal).
raster_test::Mesh awkward_mesh(std::size_t triangles, bool with_normals, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  raster_test::Mesh mesh;
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  for (uint32_t i = 0; i < triangles; ++i) {
    const glm::vec3 centre(unit(rng) * 5.0f - 2.5f, unit(rng) * 3.6f - 1.8f,
                           -1.0f - unit(rng) * 6.0f);
    const float size = 0.002f * std::pow(400.0f, unit(rng));
    const auto kind = rng() % 32;
    for (int k = 0; k < 3; ++k) {
      glm::vec3 p = centre + size * glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f);
      if (kind == 0 && k == 0) p.z = 0.5f;                     // behind the camera: clipped
      if (kind == 1 && k == 1) p.x = 3e4f;                     // past the guard band
      if (kind == 2 && k == 2) p.y = kNaN;                     // not finite
      if (kind == 3 && k == 2) p = mesh.positions[3 * i + 1];  // degenerate
      mesh.positions.push_back(p);
      if (with_normals) {
        const glm::vec3 n(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f);
        glm::vec3 normal = n;
        if (kind == 4) normal = glm::vec3(0.0f);
        if (kind == 5) normal = glm::vec3(kNaN, 0.0f, 1.0f);
        if (kind == 6) normal = n * 1e30f;
        mesh.normals.push_back(normal);
      }
    }
    // Both windings, and now and then an index past the mesh.
    const uint32_t last = kind == 7 ? 1u << 30 : 3 * i + 2;
    if (rng() % 2 == 0) {
      mesh.add_triangle(3 * i, 3 * i + 1, last);
    } else {
      mesh.add_triangle(3 * i, last, 3 * i + 1);
    }
  }
  return mesh;
}

void expect_same_bits(float a, float b, const std::string& what) {
  ASSERT_EQ(std::bit_cast<uint32_t>(a), std::bit_cast<uint32_t>(b))
      << what << ": " << a << ", " << b;
}

void expect_same_triangle(const ScreenTriangle& a, const ScreenTriangle& b, const std::string& at) {
  for (std::size_t k = 0; k < 3; ++k) {
    ASSERT_EQ(a.x[k], b.x[k]) << at;
    ASSERT_EQ(a.y[k], b.y[k]) << at;
    expect_same_bits(a.inv_w[k], b.inv_w[k], at + " inv_w");
    for (int c = 0; c < 3; ++c) {
      expect_same_bits(a.texture_offset[k][c], b.texture_offset[k][c], at + " texture offset");
      expect_same_bits(a.normal[k][c], b.normal[k][c], at + " normal");
      ASSERT_EQ(std::bit_cast<uint64_t>(a.texture_origin[c]),
                std::bit_cast<uint64_t>(b.texture_origin[c]))
          << at;
    }
  }
  ASSERT_EQ(a.double_area, b.double_area) << at;
  ASSERT_EQ(a.min_px, b.min_px) << at;
  ASSERT_EQ(a.min_py, b.min_py) << at;
  ASSERT_EQ(a.max_px, b.max_px) << at;
  ASSERT_EQ(a.max_py, b.max_py) << at;
  expect_same_bits(a.depth.at_vertex0, b.depth.at_vertex0, at + " depth");
  expect_same_bits(a.depth.per_x, b.depth.per_x, at + " depth per x");
  expect_same_bits(a.depth.per_y, b.depth.per_y, at + " depth per y");
  ASSERT_EQ(a.clip_mask, b.clip_mask) << at;
  ASSERT_EQ(a.first_clip_form, b.first_clip_form) << at;
  ASSERT_EQ(a.object, b.object) << at;
  ASSERT_EQ(a.back_face, b.back_face) << at;
}

void expect_same_stats(const RasterStats& a, const RasterStats& b) {
  EXPECT_EQ(a.triangles_in, b.triangles_in);
  EXPECT_EQ(a.triangles_invalid, b.triangles_invalid);
  EXPECT_EQ(a.triangles_degenerate, b.triangles_degenerate);
  EXPECT_EQ(a.triangles_culled, b.triangles_culled);
  EXPECT_EQ(a.triangles_back_face_culled, b.triangles_back_face_culled);
  EXPECT_EQ(a.triangles_clipped_near, b.triangles_clipped_near);
  EXPECT_EQ(a.triangles_clipped_guard_band, b.triangles_clipped_guard_band);
  EXPECT_EQ(a.triangles_rasterized, b.triangles_rasterized);
  EXPECT_EQ(a.triangles_clip_tested, b.triangles_clip_tested);
  EXPECT_EQ(a.triangles_clip_rejected, b.triangles_clip_rejected);
  EXPECT_EQ(a.triangles_clip_straddling, b.triangles_clip_straddling);
}

struct Output {
  ScreenTriangles triangles;
  std::vector<AffineForm> clip_forms;
  RasterStats stats;
};

// Three objects (vertex normals and back faces culled; face normals, both sides drawn; vertex
// normals and texture positions near double's limit, whose offsets pass float's range and
// saturate), with and without a clip plane through the first, set up triangle by triangle and
// by ranges: the same screen triangles, clip forms and counts.
TEST(TriangleSetup, RangesInLanesSetUpWhatSetupDoes) {
  const std::vector<int64_t> targets = test::targets_to_run(setup_kernels_compiled_targets());
  ASSERT_FALSE(targets.empty());
  constexpr std::size_t kObjects = 3;
  const std::array<raster_test::Mesh, kObjects> meshes = {
      awkward_mesh(3000, true, 1), awkward_mesh(700, false, 2), awkward_mesh(700, true, 3)};
  std::array<RasterObject, kObjects> objects;
  for (std::size_t o = 0; o < kObjects; ++o) {
    objects[o].mesh = meshes[o].view();
    objects[o].model =
        glm::rotate(glm::mat4(1.0f), 0.1f * static_cast<float>(o), glm::vec3(0, 1, 0));
    objects[o].texture_from_object =
        o == 2 ? glm::dmat4(1e308)
               : glm::translate(glm::dmat4(1.0), glm::dvec3(1e9, -2.5e6, 0.125)) * glm::dmat4(3.0);
    objects[o].cull_back_faces = o == 0;
    objects[o].clip_plane_mask = o == 0 ? 1u : 0u;
  }
  const std::vector<glm::dvec4> plane = {{0.3, 0.0, 1.0, 3.0}};
  // With edge sampling too: triangles between pixel centres are kept, by the pixels they touch.
  for (const auto& [with_plane, edge_sampling] :
       {std::pair{false, false}, std::pair{true, false}, std::pair{false, true}}) {
    RasterView view{kWidth,
                    kHeight,
                    raster_test::perspective_look_at({0, 0, 0}, {0, 0, -1}, kWidth, kHeight),
                    {}};
    if (with_plane) view.clip_planes = plane;
    const auto plane_count = static_cast<int>(view.clip_planes.size());
    const TriangleSetup setup(kWidth, kHeight, plane_count, edge_sampling);
    std::array<ObjectFrame, kObjects> frames;
    TransformedVertices vertices;
    std::size_t vertex_count = 0;
    for (const raster_test::Mesh& mesh : meshes) vertex_count += mesh.positions.size();
    vertices.resize(vertex_count, plane_count);
    for (std::size_t o = 0, first = 0; o < kObjects; first += meshes[o].positions.size(), ++o) {
      frames[o] = make_object_frame(objects[o], view, first, planes_keeping_the_eye(view));
      transform_vertices(frames[o], 0, meshes[o].positions.size(), vertices);
      setup.project_vertices(vertices, first, first + meshes[o].positions.size());
      write_plane_distances(frames[o], 0, meshes[o].positions.size(), vertices);
    }
    Output one_by_one;
    for (uint32_t o = 0; o < kObjects; ++o) {
      const std::vector<uint32_t>& indices = meshes[o].indices;
      for (std::size_t i = 0; i < indices.size(); i += 3) {
        setup.setup(frames[o], o, vertices, indices[i], indices[i + 1], indices[i + 2],
                    one_by_one.triangles, one_by_one.clip_forms, one_by_one.stats);
      }
    }
    ASSERT_GT(one_by_one.stats.triangles_rasterized, 800u);
    ASSERT_GT(one_by_one.stats.triangles_clipped_near + one_by_one.stats.triangles_invalid +
                  one_by_one.stats.triangles_degenerate,
              0u);
    for (const int64_t target : targets) {
      const test::ForcedTarget forced(target);
      SCOPED_TRACE(std::string(hwy::TargetName(target)) + (with_plane ? ", clip plane" : "") +
                   (edge_sampling ? ", edge sampling" : ""));
      auto lanes = std::make_unique<SetupLanes>();
      Output ranges;
      std::size_t in_lanes = 0;
      for (uint32_t o = 0; o < kObjects; ++o) {
        // In ranges of every few lengths, so that the lanes are flushed part full.
        const std::size_t count = meshes[o].indices.size() / 3;
        for (std::size_t first = 0, step = 1; first < count; first += step, step = step * 3 % 97) {
          in_lanes += setup.setup_range(frames[o], o, vertices, meshes[o].indices, first,
                                        std::min(count, first + step), *lanes, ranges.triangles,
                                        ranges.clip_forms, ranges.stats);
        }
      }
      // A good part of what is emitted went through the lanes, not only the one-by-one path.
      EXPECT_GT(in_lanes, one_by_one.stats.triangles_rasterized / 3);
      expect_same_stats(ranges.stats, one_by_one.stats);
      ASSERT_EQ(ranges.triangles.size(), one_by_one.triangles.size());
      for (std::size_t t = 0; t < ranges.triangles.size(); ++t) {
        ASSERT_NO_FATAL_FAILURE(expect_same_triangle(ranges.triangles[t], one_by_one.triangles[t],
                                                     "triangle " + std::to_string(t)));
      }
      ASSERT_EQ(ranges.clip_forms.size(), one_by_one.clip_forms.size());
      for (std::size_t f = 0; f < ranges.clip_forms.size(); ++f) {
        expect_same_bits(ranges.clip_forms[f].at_vertex0, one_by_one.clip_forms[f].at_vertex0,
                         "clip form");
        expect_same_bits(ranges.clip_forms[f].per_x, one_by_one.clip_forms[f].per_x, "clip form");
        expect_same_bits(ranges.clip_forms[f].per_y, one_by_one.clip_forms[f].per_y, "clip form");
      }
    }
  }
}

}  // namespace
}  // namespace soltex::raster_internal
