#include "soltex/scene/mesh.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <glm/geometric.hpp>
#include <map>
#include <stdexcept>
#include <tuple>

#include "soltex/scene/builtin_meshes.h"

namespace soltex {
namespace {

using Edge = std::pair<uint32_t, uint32_t>;

// Vertex ids by position, so meshes with split vertices (the box's faces) can be checked for
// closure too.
std::vector<uint32_t> position_ids(const Mesh& mesh) {
  std::map<std::tuple<float, float, float>, uint32_t> ids;
  std::vector<uint32_t> result;
  for (const glm::vec3& p : mesh.positions) {
    result.push_back(
        ids.try_emplace({p.x, p.y, p.z}, static_cast<uint32_t>(ids.size())).first->second);
  }
  return result;
}

// Directed edges by position: in a closed, consistently wound mesh every edge (a, b)
// appears once and its reverse (b, a) once.
std::map<Edge, int> directed_edges(const Mesh& mesh) {
  const std::vector<uint32_t> id = position_ids(mesh);
  std::map<Edge, int> edges;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    for (int k = 0; k < 3; ++k) {
      ++edges[{id[mesh.indices[3 * t + k]], id[mesh.indices[3 * t + (k + 1) % 3]]}];
    }
  }
  return edges;
}

void expect_consistent(const Mesh& mesh) {
  ASSERT_EQ(mesh.indices.size() % 3, 0u);
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  ASSERT_GT(mesh.triangle_count(), 0u);
  for (uint32_t index : mesh.indices) ASSERT_LT(index, mesh.vertex_count());
  for (const glm::vec3& n : mesh.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f);
  const BoundingBox box = bounds_of(mesh.positions);
  EXPECT_EQ(box.min, mesh.bounds.min);
  EXPECT_EQ(box.max, mesh.bounds.max);
  // Winding agrees with the normals: every triangle's geometric normal points the way of
  // its vertex normals, and has area.
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const uint32_t a = mesh.indices[3 * t], b = mesh.indices[3 * t + 1],
                   c = mesh.indices[3 * t + 2];
    const glm::vec3 face =
        glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    ASSERT_GT(glm::length(face), 0.0f) << "triangle " << t;
    for (uint32_t v : {a, b, c}) ASSERT_GT(glm::dot(face, mesh.normals[v]), 0.0f) << t;
  }
}

void expect_closed(const Mesh& mesh) {
  const std::map<Edge, int> edges = directed_edges(mesh);
  for (const auto& [edge, count] : edges) {
    ASSERT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second << " used twice";
    const auto reverse = edges.find({edge.second, edge.first});
    ASSERT_NE(reverse, edges.end()) << "open edge " << edge.first << "-" << edge.second;
  }
}

TEST(BuiltinMeshes, SphereIsClosedWithOutwardUnitNormals) {
  const SphereShape shape{.radius = 1.5, .segments = 24, .rings = 12};
  const Mesh mesh = make_sphere(shape);
  expect_consistent(mesh);
  expect_closed(mesh);
  EXPECT_EQ(mesh.vertex_count(), 2u + 24u * 11u);  // poles plus the inner rings, seam shared
  EXPECT_EQ(mesh.triangle_count(), 2u * 24u * 11u);
  for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
    EXPECT_NEAR(glm::length(mesh.positions[i]), 1.5f, 1e-5f);
    EXPECT_GT(glm::dot(mesh.normals[i], mesh.positions[i]), 0.0f);  // outward
  }
  EXPECT_NEAR(mesh.bounds.max.y, 1.5f, 1e-6f);
  EXPECT_NEAR(mesh.bounds.min.y, -1.5f, 1e-6f);
}

TEST(BuiltinMeshes, TorusIsClosedWithNormalsAwayFromTheTube) {
  const TorusShape shape{
      .major_radius = 1.0, .minor_radius = 0.25, .major_segments = 20, .minor_segments = 12};
  const Mesh mesh = make_torus(shape);
  expect_consistent(mesh);
  expect_closed(mesh);
  EXPECT_EQ(mesh.triangle_count(), 2u * 20u * 12u);
  for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
    const glm::vec3 p = mesh.positions[i];
    // The nearest point of the tube's centre circle (radius 1 in the x-z plane).
    const glm::vec3 on_circle = glm::normalize(glm::vec3(p.x, 0.0f, p.z));
    EXPECT_NEAR(glm::length(p - on_circle), 0.25f, 1e-5f);
    EXPECT_GT(glm::dot(mesh.normals[i], p - on_circle), 0.0f);
  }
  EXPECT_NEAR(mesh.bounds.max.x, 1.25f, 1e-5f);
  EXPECT_NEAR(mesh.bounds.max.y, 0.25f, 1e-5f);
}

TEST(BuiltinMeshes, BoxIsClosedByPositionWithFlatOutwardNormals) {
  for (int subdivisions : {1, 3}) {
    const Mesh mesh = make_box({.size = {2.0, 1.0, 0.5}, .subdivisions = subdivisions});
    expect_consistent(mesh);
    expect_closed(mesh);
    EXPECT_EQ(mesh.triangle_count(), 6u * 2u * subdivisions * subdivisions);
    EXPECT_EQ(mesh.bounds.min, glm::vec3(-1.0f, -0.5f, -0.25f));
    EXPECT_EQ(mesh.bounds.max, glm::vec3(1.0f, 0.5f, 0.25f));
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
      // The normal is the axis whose face the vertex lies on.
      const glm::vec3 n = mesh.normals[i], p = mesh.positions[i];
      const int axis = n.x != 0.0f ? 0 : n.y != 0.0f ? 1 : 2;
      EXPECT_EQ(p[axis], n[axis] > 0 ? mesh.bounds.max[axis] : mesh.bounds.min[axis]);
    }
  }
}

TEST(BuiltinMeshes, PlaneFacesUpAndHasOneBoundaryLoop) {
  const Mesh mesh = make_plane({.size = {4.0, 2.0}, .subdivisions = 4});
  expect_consistent(mesh);
  EXPECT_EQ(mesh.triangle_count(), 2u * 16u);
  for (const glm::vec3& n : mesh.normals) EXPECT_EQ(n, glm::vec3(0, 1, 0));
  EXPECT_EQ(mesh.bounds.min, glm::vec3(-2.0f, 0.0f, -1.0f));
  EXPECT_EQ(mesh.bounds.max, glm::vec3(2.0f, 0.0f, 1.0f));
  int boundary = 0;
  const std::map<Edge, int> edges = directed_edges(mesh);
  for (const auto& [edge, count] : edges) {
    EXPECT_EQ(count, 1);
    if (!edges.contains({edge.second, edge.first})) ++boundary;
  }
  EXPECT_EQ(boundary, 4 * 4);
}

TEST(BuiltinMeshes, MakeMeshDispatchesAndNamesShapes) {
  EXPECT_EQ(make_mesh(TorusShape{}).triangle_count(), make_torus({}).triangle_count());
  EXPECT_STREQ(shape_name(BoxShape{}), "box");
  EXPECT_STREQ(shape_name(PlaneShape{}), "plane");
}

TEST(BuiltinMeshes, ParametersOutOfBoundsAreRefused) {
  EXPECT_THROW(make_sphere({.radius = 0.0}), std::invalid_argument);
  EXPECT_THROW(make_sphere({.segments = 2}), std::invalid_argument);
  EXPECT_THROW(make_sphere({.rings = ShapeLimits::kMaxSegments + 1}), std::invalid_argument);
  EXPECT_THROW(make_torus({.major_radius = 0.2, .minor_radius = 0.3}), std::invalid_argument);
  EXPECT_THROW(make_box({.subdivisions = 0}), std::invalid_argument);
  EXPECT_THROW(make_plane({.size = {1.0, -1.0}}), std::invalid_argument);
}

TEST(ComputeVertexNormals, WeightsByArea) {
  // Two triangles meet at vertex 0: a big one in the x-y plane (normal +z) and a small one
  // in the x-z plane (normal -y). The shared normal leans towards the big one.
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 1}, {1, 0, 0}};
  mesh.indices = {0, 1, 2, 0, 4, 3};
  compute_vertex_normals(mesh);
  const glm::vec3 expected = glm::normalize(glm::vec3(0.0f, -1.0f, 100.0f));
  EXPECT_NEAR(mesh.normals[0].y, expected.y, 1e-6f);
  EXPECT_NEAR(mesh.normals[0].z, expected.z, 1e-6f);
  EXPECT_EQ(mesh.normals[2], glm::vec3(0, 0, 1));
  EXPECT_EQ(mesh.normals[3], glm::vec3(0, -1, 0));
}

TEST(ComputeVertexNormals, IsolatedOrCancellingVerticesStillGetUnitNormals) {
  Mesh mesh;
  // Two coincident triangles of opposite winding cancel at every vertex.
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}};
  mesh.indices = {0, 1, 2, 0, 2, 1};
  compute_vertex_normals(mesh);
  for (const glm::vec3& n : mesh.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
  EXPECT_EQ(mesh.normals[3], glm::vec3(0, 0, 1));
}

TEST(NormalizeToUnitBox, CentresAndScalesTheLongestSideToTwo) {
  Mesh mesh = make_box({.size = {4.0, 2.0, 1.0}});
  for (glm::vec3& p : mesh.positions) p += glm::vec3(10.0f, -3.0f, 7.0f);
  const std::vector<glm::vec3> normals = mesh.normals;
  normalize_to_unit_box(mesh);
  EXPECT_EQ(mesh.bounds.min, glm::vec3(-1.0f, -0.5f, -0.25f));
  EXPECT_EQ(mesh.bounds.max, glm::vec3(1.0f, 0.5f, 0.25f));
  EXPECT_EQ(mesh.normals, normals);
}

}  // namespace
}  // namespace soltex
