#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <vector>

#include "soltex/common/check.h"
#include "soltex/scene/mesh.h"

namespace soltex {
namespace {

constexpr uint32_t kMostTrianglesCreased = 64;

// Each vertex's triangles, as a compressed row list: triangles[first[v] .. first[v + 1]).
struct VertexTriangles {
  std::vector<uint32_t> first;
  std::vector<uint32_t> triangles;
};

VertexTriangles triangles_around_vertices(const Mesh& mesh) {
  VertexTriangles around;
  around.first.assign(mesh.positions.size() + 1, 0);
  for (uint32_t index : mesh.indices) ++around.first[index + 1];
  for (std::size_t v = 1; v < around.first.size(); ++v) around.first[v] += around.first[v - 1];
  around.triangles.resize(mesh.indices.size());
  std::vector<uint32_t> filled(around.first.begin(), around.first.end() - 1);
  for (std::size_t c = 0; c < mesh.indices.size(); ++c) {
    around.triangles[filled[mesh.indices[c]]++] = static_cast<uint32_t>(c / 3);
  }
  return around;
}

}  // namespace

std::size_t compute_creased_normals(Mesh& mesh, double crease_degrees) {
  const std::size_t triangles = mesh.triangle_count();
  // Area-weighted face normals (|.| is twice the area) and their directions.
  std::vector<glm::dvec3> weighted(triangles), unit(triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    const glm::dvec3 a(mesh.positions[mesh.indices[3 * t]]);
    const glm::dvec3 b(mesh.positions[mesh.indices[3 * t + 1]]);
    const glm::dvec3 c(mesh.positions[mesh.indices[3 * t + 2]]);
    weighted[t] = glm::cross(b - a, c - a);
    const double length = glm::length(weighted[t]);
    unit[t] = length > 0.0 ? weighted[t] / length : glm::dvec3(0.0);
  }
  const double cos_crease = std::cos(crease_degrees * std::numbers::pi / 180.0);
  const VertexTriangles around = triangles_around_vertices(mesh);
  std::vector<glm::dvec3> hub_sums;  // a hub's sum of all its triangles, made once
  std::vector<bool> hub_summed;
  const auto hub_sum = [&](uint32_t v) {
    if (hub_sums.empty()) {
      hub_sums.assign(mesh.positions.size(), glm::dvec3(0.0));
      hub_summed.assign(mesh.positions.size(), false);
    }
    if (!hub_summed[v]) {
      for (uint32_t k = around.first[v]; k < around.first[v + 1]; ++k) {
        hub_sums[v] += weighted[around.triangles[k]];
      }
      hub_summed[v] = true;
    }
    return hub_sums[v];
  };
  // A corner's normal: its vertex's triangles turned from its own by at most the crease. A
  // vertex of very many triangles (a fan's hub) is smooth: comparing each of its corners with
  // each of its triangles would cost their product.
  std::vector<glm::vec3> corner_normals(mesh.indices.size());
  for (std::size_t c = 0; c < mesh.indices.size(); ++c) {
    const uint32_t v = mesh.indices[c];
    const glm::dvec3& own = unit[c / 3];
    const bool hub = around.first[v + 1] - around.first[v] > kMostTrianglesCreased;
    glm::dvec3 sum(0.0);
    if (hub) {
      sum = hub_sum(v);
    } else {
      for (uint32_t k = around.first[v]; k < around.first[v + 1]; ++k) {
        const uint32_t t = around.triangles[k];
        if (glm::dot(unit[t], own) >= cos_crease) sum += weighted[t];
      }
    }
    if (!(glm::length(sum) > 0.0)) sum = weighted[c / 3];
    corner_normals[c] =
        glm::length(sum) > 0.0 ? glm::vec3(glm::normalize(sum)) : glm::vec3(0, 0, 1);
  }
  // One vertex per distinct normal at a position: the first keeps the vertex, each other
  // normal gets a copy of it.
  mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
  std::vector<bool> assigned(mesh.positions.size(), false);
  std::vector<std::vector<uint32_t>> copies(mesh.positions.size());
  const std::size_t vertices_before = mesh.positions.size();
  for (std::size_t c = 0; c < mesh.indices.size(); ++c) {
    const uint32_t v = mesh.indices[c];
    if (!assigned[v]) {
      assigned[v] = true;
      mesh.normals[v] = corner_normals[c];
      continue;
    }
    if (mesh.normals[v] == corner_normals[c]) continue;
    std::vector<uint32_t>& made = copies[v];
    const auto same = std::find_if(made.begin(), made.end(), [&](uint32_t copy) {
      return mesh.normals[copy] == corner_normals[c];
    });
    if (same != made.end()) {
      mesh.indices[c] = *same;
      continue;
    }
    mesh.indices[c] = static_cast<uint32_t>(mesh.positions.size());
    made.push_back(mesh.indices[c]);
    mesh.positions.push_back(mesh.positions[v]);
    mesh.normals.push_back(corner_normals[c]);
  }
  SOLTEX_DCHECK(mesh.normals.size() == mesh.positions.size());
  return mesh.positions.size() - vertices_before;
}

}  // namespace soltex
