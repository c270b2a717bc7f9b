#include "soltex/scene/mesh_lod.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <set>
#include <tuple>

#include "soltex/scene/builtin_meshes.h"

namespace soltex {
namespace {

using Vertex = std::tuple<float, float, float, float, float, float>;  // position, normal

std::set<Vertex> vertices_of(const Mesh& mesh) {
  std::set<Vertex> vertices;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3 p = mesh.positions[v], n = mesh.normals[v];
    vertices.insert({p.x, p.y, p.z, n.x, n.y, n.z});
  }
  return vertices;
}

Mesh fine_sphere() {
  SphereShape shape;
  shape.segments = 400;
  shape.rings = 200;
  return make_sphere(shape);  // 159,200 triangles
}

TEST(MeshLod, SmallMeshesGetNoLevels) {
  const Mesh sphere = make_sphere(SphereShape{});  // 64 x 32: 4,032 triangles
  ASSERT_LT(sphere.triangle_count(), MeshLodLimits::kMinTriangles);
  EXPECT_TRUE(simplified_levels(sphere).empty());
}

TEST(MeshLod, LevelsHalveASmoothMeshOutOfItsOwnVertices) {
  const Mesh sphere = fine_sphere();
  const std::vector<MeshLevel> levels = simplified_levels(sphere);
  ASSERT_GE(levels.size(), 2u);
  const std::set<Vertex> original = vertices_of(sphere);
  std::size_t finer = sphere.triangle_count();
  float error = 0.0f;
  for (const MeshLevel& level : levels) {
    const Mesh& mesh = level.mesh;
    EXPECT_LE(4 * mesh.triangle_count(), 3 * finer);  // at least a quarter fewer each step
    EXPECT_GE(mesh.triangle_count(), MeshLodLimits::kCoarsestTriangles);
    finer = mesh.triangle_count();
    EXPECT_GE(level.error, error);  // the estimates add up level by level
    EXPECT_GT(level.error, 0.0f);
    error = level.error;
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
    for (uint32_t index : mesh.indices) ASSERT_LT(index, mesh.positions.size());
    // A subset of the original's vertices, each with its own normal, and no vertex unused.
    for (const Vertex& v : vertices_of(mesh)) EXPECT_TRUE(original.contains(v));
    std::vector<bool> used(mesh.positions.size(), false);
    for (uint32_t index : mesh.indices) used[index] = true;
    EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
    EXPECT_LE(level.normal_error, MeshLodLimits::kMaxNormalError);
    EXPECT_EQ(mesh.bounds.min, bounds_of(mesh.positions).min);
  }
}

TEST(MeshLod, NormalsThatVaryFasterThanTheSurfaceKeepTheMeshWhole) {
  // A scan's look: the same sphere, every other vertex's normal tipped by about 30 degrees.
  Mesh rough = fine_sphere();
  for (std::size_t v = 0; v < rough.normals.size(); v += 2) {
    const glm::vec3 n = rough.normals[v];
    const glm::vec3 side = std::fabs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    rough.normals[v] = glm::normalize(n + 0.58f * glm::normalize(glm::cross(n, side)));
  }
  // Every level would turn some normal by about 30 degrees: none is kept.
  EXPECT_TRUE(simplified_levels(rough).empty());
}

TEST(MeshLod, IndicesOutOfRangeAreLeftForTheRasterizer) {
  Mesh broken = fine_sphere();
  broken.indices.back() = static_cast<uint32_t>(broken.positions.size());
  EXPECT_TRUE(simplified_levels(broken).empty());
}

}  // namespace
}  // namespace soltex
