// The OBJ clean-up as parse_obj runs it (client/scene/src/mesh_cleanup.cpp): duplicates merged
// by meshoptimizer's vertex remap over the positions' bits, with -0 folded into +0.
#include <gtest/gtest.h>

#include <glm/vec3.hpp>

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
                                  "close.obj");
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

}  // namespace
}  // namespace soltex
