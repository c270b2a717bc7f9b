#include "soltex/scene/mesh_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <tuple>
#include <vector>

#include "soltex/scene/builtin_meshes.h"

namespace soltex {
namespace {

// A triangle by what its corners hold, in its own vertex order: reordering may move and
// renumber triangles, never change one.
using Corner = std::tuple<float, float, float, float, float, float>;  // position, normal
using Triangle = std::array<Corner, 3>;

std::vector<Triangle> triangles_of(const Mesh& mesh) {
  std::vector<Triangle> triangles;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    Triangle triangle;
    for (std::size_t k = 0; k < 3; ++k) {
      const uint32_t v = mesh.indices[3 * t + k];
      const glm::vec3 p = mesh.positions[v], n = mesh.normals[v];
      triangle[k] = {p.x, p.y, p.z, n.x, n.y, n.z};
    }
    triangles.push_back(triangle);
  }
  std::sort(triangles.begin(), triangles.end());
  return triangles;
}

// The sphere with its triangles and vertices shuffled: what a scan's file order looks like.
Mesh shuffled_sphere() {
  Mesh mesh = make_sphere({.radius = 1.0, .segments = 96, .rings = 48});
  std::mt19937 random(7);
  std::vector<uint32_t> new_of_old(mesh.vertex_count());
  std::iota(new_of_old.begin(), new_of_old.end(), 0u);
  std::shuffle(new_of_old.begin(), new_of_old.end(), random);
  Mesh shuffled = mesh;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    shuffled.positions[new_of_old[v]] = mesh.positions[v];
    shuffled.normals[new_of_old[v]] = mesh.normals[v];
  }
  std::vector<uint32_t> order(mesh.triangle_count());
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), random);
  for (std::size_t t = 0; t < order.size(); ++t) {
    for (std::size_t k = 0; k < 3; ++k) {
      shuffled.indices[3 * t + k] = new_of_old[mesh.indices[3 * order[t] + k]];
    }
  }
  return shuffled;
}

// The median, over triangles, of how far apart in the vertex array its vertices lie.
uint32_t median_vertex_spread(const Mesh& mesh) {
  std::vector<uint32_t> spread;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const auto [low, high] =
        std::minmax({mesh.indices[3 * t], mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]});
    spread.push_back(high - low);
  }
  std::nth_element(spread.begin(), spread.begin() + spread.size() / 2, spread.end());
  return spread[spread.size() / 2];
}

TEST(OrderForLocality, KeepsEveryTriangleAndVertexAsItWas) {
  const Mesh before = shuffled_sphere();
  Mesh after = before;
  order_for_locality(after);
  EXPECT_EQ(after.vertex_count(), before.vertex_count());
  EXPECT_EQ(after.triangle_count(), before.triangle_count());
  EXPECT_EQ(triangles_of(after), triangles_of(before));
  EXPECT_EQ(after.bounds.min, before.bounds.min);
  EXPECT_EQ(after.bounds.max, before.bounds.max);
}

TEST(OrderForLocality, PutsNeighbouringTrianglesAndTheirVerticesClose) {
  Mesh mesh = shuffled_sphere();
  const uint32_t before = median_vertex_spread(mesh);
  order_for_locality(mesh);
  const uint32_t after = median_vertex_spread(mesh);
  EXPECT_GT(before, 500u);
  EXPECT_LT(after, 100u) << "before: " << before;
}

TEST(OrderForLocality, NumbersVerticesByFirstUseAndKeepsUnusedOnesAfter) {
  Mesh mesh = shuffled_sphere();
  mesh.positions.push_back({9.0f, 9.0f, 9.0f});  // used by no triangle
  mesh.normals.push_back({0.0f, 0.0f, 1.0f});
  order_for_locality(mesh);
  uint32_t next_new = 0;
  for (const uint32_t index : mesh.indices) {
    ASSERT_LE(index, next_new);  // either seen before, or the next number
    if (index == next_new) ++next_new;
  }
  EXPECT_EQ(next_new, mesh.vertex_count() - 1);
  EXPECT_EQ(mesh.positions.back(), glm::vec3(9.0f, 9.0f, 9.0f));
  EXPECT_EQ(mesh.normals.back(), glm::vec3(0.0f, 0.0f, 1.0f));
}

TEST(OrderForLocality, TrianglesInOneCellKeepTheirOrder) {
  // 40 small triangles whose centroids share one Morton cell, after a large one whose centroid
  // is elsewhere: the order among them decides which wins a depth tie, so the sort must be
  // stable (an unstable sort of this many equal keys reorders them).
  Mesh mesh;
  mesh.positions = {{10, 10, 10}, {9, 10, 10}, {10, 9, 10}};
  mesh.indices = {0, 1, 2};
  constexpr int kTied = 40;
  for (int k = 0; k < kTied; ++k) {
    const float d = 1e-4f * static_cast<float>(k + 1);
    const auto first = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.push_back({d, 0, 0});
    mesh.positions.push_back({0, d, 0});
    mesh.positions.push_back({0, 0, d});
    // Alternate windings, so the triangles differ in more than size.
    if (k % 2 == 0) {
      mesh.indices.insert(mesh.indices.end(), {first, first + 1, first + 2});
    } else {
      mesh.indices.insert(mesh.indices.end(), {first, first + 2, first + 1});
    }
  }
  mesh.normals.assign(mesh.positions.size(), glm::vec3(0, 0, 1));
  mesh.update_bounds();
  order_for_locality(mesh);
  ASSERT_EQ(mesh.triangle_count(), static_cast<std::size_t>(kTied) + 1);
  const auto corner = [&](std::size_t t, std::size_t k) {
    return mesh.positions[mesh.indices[3 * t + k]];
  };
  for (int k = 0; k < kTied; ++k) {
    const float d = 1e-4f * static_cast<float>(k + 1);
    const auto t = static_cast<std::size_t>(k);
    EXPECT_EQ(corner(t, 0), glm::vec3(d, 0, 0)) << "triangle " << k;
    EXPECT_EQ(corner(t, 1), k % 2 == 0 ? glm::vec3(0, d, 0) : glm::vec3(0, 0, d)) << k;
  }
  EXPECT_EQ(corner(kTied, 0), glm::vec3(10, 10, 10));
}

TEST(OrderForLocality, OddMeshesAreLeftDrawable) {
  Mesh empty;
  order_for_locality(empty);
  EXPECT_TRUE(empty.indices.empty());

  // Flat along z, a NaN position and an index out of range: still a permutation, and the bad
  // index still points past the vertices (the rasterizer refuses that triangle).
  Mesh odd;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  odd.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {nan, 0, 0}};
  odd.normals.assign(4, glm::vec3(0, 0, 1));
  odd.indices = {0, 1, 2, 3, 1, 2, 0, 1, 7};
  order_for_locality(odd);
  ASSERT_EQ(odd.indices.size(), 9u);
  EXPECT_EQ(std::count(odd.indices.begin(), odd.indices.end(), 7u), 1);
  EXPECT_EQ(odd.positions.size(), 4u);
  EXPECT_EQ(std::count_if(odd.positions.begin(), odd.positions.end(),
                          [](const glm::vec3& p) { return std::isnan(p.x); }),
            1);
}

TEST(OrderForLocality, InfiniteAndHugeCoordinatesKeepEveryTriangle) {
  // meshoptimizer turns centroids into integers; these must neither overflow that nor lose a
  // triangle, and the positions themselves stay as they were.
  Mesh mesh;
  const float inf = std::numeric_limits<float>::infinity();
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {inf, 0, 0}, {3e38f, -3e38f, 0}, {0, 0, -inf}};
  mesh.normals.assign(mesh.positions.size(), glm::vec3(0, 0, 1));
  mesh.indices = {3, 4, 5, 0, 1, 2, 4, 1, 2, 5, 0, 3};
  const Mesh before = mesh;
  order_for_locality(mesh);
  EXPECT_EQ(triangles_of(mesh), triangles_of(before));
  EXPECT_EQ(mesh.vertex_count(), before.vertex_count());
}

}  // namespace
}  // namespace soltex
