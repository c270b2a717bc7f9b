// The OBJ clean-up as parse_obj runs it (client/scene/src/mesh_cleanup.cpp): duplicates merged
// by meshoptimizer's vertex remap over the positions' bits, with -0 folded into +0.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <numbers>
#include <string>

#include "soltex/scene/obj_loader.h"

namespace soltex {
namespace {

TEST(MeshCleanup, NegativeZeroIsTheSamePointAsZero) {
  const LoadedObj obj = parse_obj(R"(
v 0 0 0
v 1 0 0
v -0 -0 0
v 0 1 0
v 1 -0 -0
f 1 2 4
f 3 5 4
)",
                                  "zeros.obj");
  EXPECT_EQ(obj.stats.duplicate_vertices_merged, 2u);  // vertices 3 and 5
  EXPECT_EQ(obj.stats.degenerate_triangles_dropped, 0u);
  EXPECT_EQ(obj.mesh.vertex_count(), 3u);
  // Both faces then name the same three vertices: the second is a duplicate.
  EXPECT_EQ(obj.stats.duplicate_faces_dropped, 1u);
  EXPECT_EQ(obj.stats.reversed_faces_dropped, 0u);
  EXPECT_FALSE(obj.mesh.two_sided);
  EXPECT_EQ(obj.mesh.triangle_count(), 1u);
}

TEST(MeshCleanup, PointsApartInTheFileButEqualInFloatAreMerged) {
  // 1 + 1e-12 is a different double from 1 and the same float.
  const LoadedObj obj = parse_obj(R"(
v 0 0 0
v 1 0 0
v 0 1 0
v 1.000000000001 0 0
v 0 0 1
f 1 2 3
f 1 3 5
f 4 5 3
)",
                                  "close.obj", {.crease_degrees = 180.0});  // smooth: no splits
  EXPECT_EQ(obj.stats.duplicate_vertices_merged, 1u);
  EXPECT_EQ(obj.mesh.vertex_count(), 4u);
  EXPECT_EQ(obj.mesh.triangle_count(), 3u);
}

// A face written once each way (a common way to export a two-sided sheet) is one face: kept
// twice its vertex normals would cancel, and the two copies would fight for depth. The mesh
// is then two-sided, so back-face culling does not hide what the file showed from behind.
TEST(MeshCleanup, AFaceWrittenInBothWindingsIsKeptOnce) {
  const LoadedObj obj = parse_obj(R"(
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
f 1 2 3 4
f 4 3 2 1
f 1 2 3 4
)",
                                  "two-sided.obj");
  EXPECT_EQ(obj.stats.duplicate_faces_dropped, 2u);  // the quad again, each way
  EXPECT_EQ(obj.stats.reversed_faces_dropped, 1u);
  EXPECT_TRUE(obj.mesh.two_sided) << "seen from both sides, as the file meant";
  ASSERT_EQ(obj.mesh.triangle_count(), 2u);
  for (const glm::vec3& n : obj.mesh.normals) EXPECT_EQ(n, glm::vec3(0, 0, 1));
}

// A cube's faces meet at 90 degrees: past the default crease, so each corner of each face has
// its face's own normal (the cube is split into 24 vertices, three per corner), where smooth
// normals would shade each face with a diagonal gradient. At 180 degrees it stays smooth.
TEST(MeshCleanup, ACubeKeepsItsEdgesSharp) {
  const char* cube = R"(
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 3 4 8 7
f 2 3 7 6
f 1 5 8 4
)";
  const LoadedObj sharp = parse_obj(cube, "cube.obj");
  EXPECT_EQ(sharp.mesh.vertex_count(), 24u);
  EXPECT_EQ(sharp.stats.vertices_split_at_creases, 16u);
  for (std::size_t t = 0; t < sharp.mesh.triangle_count(); ++t) {
    const glm::vec3 a = sharp.mesh.positions[sharp.mesh.indices[3 * t]];
    const glm::vec3 b = sharp.mesh.positions[sharp.mesh.indices[3 * t + 1]];
    const glm::vec3 c = sharp.mesh.positions[sharp.mesh.indices[3 * t + 2]];
    const glm::vec3 face = glm::normalize(glm::cross(b - a, c - a));
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(sharp.mesh.normals[sharp.mesh.indices[3 * t + k]], face) << "triangle " << t;
    }
  }
  const LoadedObj smooth = parse_obj(cube, "cube.obj", {.crease_degrees = 180.0});
  EXPECT_EQ(smooth.mesh.vertex_count(), 8u);
  EXPECT_NEAR(std::abs(smooth.mesh.normals[0].x), 1.0f / std::sqrt(3.0f), 1e-6f);
}

// A finely tessellated curve (a 32-sided cylinder's side: 11.25 degrees between faces) stays
// smooth: no vertex is split.
TEST(MeshCleanup, AGentleCurveStaysSmooth) {
  std::string tube;
  for (int i = 0; i < 32; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 32;
    tube += "v " + std::to_string(std::cos(a)) + " 0 " + std::to_string(std::sin(a)) + "\n";
    tube += "v " + std::to_string(std::cos(a)) + " 1 " + std::to_string(std::sin(a)) + "\n";
  }
  for (int i = 0; i < 32; ++i) {
    const int j = (i + 1) % 32;
    tube += "f " + std::to_string(2 * i + 1) + " " + std::to_string(2 * i + 2) + " " +
            std::to_string(2 * j + 2) + " " + std::to_string(2 * j + 1) + "\n";
  }
  EXPECT_EQ(parse_obj(tube, "tube.obj").stats.vertices_split_at_creases, 0u);
}

}  // namespace
}  // namespace soltex
