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
  ASSERT_EQ(obj.mesh.triangle_count(), 2u);
  // The first of the duplicates keeps its place, so both faces name the same three vertices.
  for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(obj.mesh.indices[k], obj.mesh.indices[3 + k]);
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

}  // namespace
}  // namespace soltex
