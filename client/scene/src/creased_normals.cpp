#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <span>
#include <unordered_map>
#include <vector>

#include "soltex/common/check.h"
#include "soltex/scene/mesh.h"

namespace soltex {
namespace {

constexpr uint32_t kMostTrianglesCreased = 64;

// Each vertex's corners (indices into mesh.indices; a corner's triangle is its index / 3), as
// a compressed row list: corners[first[v] .. first[v + 1]).
struct VertexCorners {
  std::vector<uint32_t> first;
  std::vector<uint32_t> corners;
};

VertexCorners corners_around_vertices(const Mesh& mesh) {
  VertexCorners around;
  around.first.assign(mesh.positions.size() + 1, 0);
  for (uint32_t index : mesh.indices) ++around.first[index + 1];
  for (std::size_t v = 1; v < around.first.size(); ++v) around.first[v] += around.first[v - 1];
  around.corners.resize(mesh.indices.size());
  std::vector<uint32_t> filled(around.first.begin(), around.first.end() - 1);
  for (std::size_t c = 0; c < mesh.indices.size(); ++c) {
    around.corners[filled[mesh.indices[c]]++] = static_cast<uint32_t>(c);
  }
  return around;
}

// Each corner's normal (three per triangle, in the mesh's index order).
std::vector<glm::vec3> normals_at_corners(const Mesh& mesh, double crease_degrees) {
  const std::size_t triangles = mesh.triangle_count();
  // Area-weighted face normals (|.| is twice the area) and their lengths.
  std::vector<glm::dvec3> weighted(triangles);
  std::vector<double> lengths(triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    const glm::dvec3 a(mesh.positions[mesh.indices[3 * t]]);
    const glm::dvec3 b(mesh.positions[mesh.indices[3 * t + 1]]);
    const glm::dvec3 c(mesh.positions[mesh.indices[3 * t + 2]]);
    weighted[t] = glm::cross(b - a, c - a);
    lengths[t] = glm::length(weighted[t]);
  }
  const double cos_crease = std::cos(crease_degrees * std::numbers::pi / 180.0);
  // Faces within half the crease of their vertex's smooth normal are within the crease of
  // each other (angles add along the sphere): every corner there gets the smooth normal, and
  // only vertices on or near a hard edge compare their faces pairwise.
  const double cos_half_crease = std::cos(crease_degrees * std::numbers::pi / 360.0);
  const VertexCorners around = corners_around_vertices(mesh);
  const auto normal_of = [&](glm::dvec3 sum, std::size_t own) {
    if (!(glm::length(sum) > 0.0)) sum = weighted[own];
    return glm::length(sum) > 0.0 ? glm::vec3(glm::normalize(sum)) : glm::vec3(0, 0, 1);
  };
  std::vector<glm::vec3> normals(mesh.indices.size());
  for (std::size_t v = 0; v + 1 < around.first.size(); ++v) {
    const std::span<const uint32_t> corners(around.corners.data() + around.first[v],
                                            around.first[v + 1] - around.first[v]);
    glm::dvec3 smooth(0.0);
    for (uint32_t c : corners) smooth += weighted[c / 3];
    const double smooth_length = glm::length(smooth);
    // A vertex of very many triangles (a fan's hub) is smooth: comparing its faces pairwise
    // would cost their count squared.
    const bool uniform = crease_degrees >= 180.0 || corners.size() > kMostTrianglesCreased ||
                         std::all_of(corners.begin(), corners.end(), [&](uint32_t c) {
                           return glm::dot(weighted[c / 3], smooth) >=
                                  cos_half_crease * lengths[c / 3] * smooth_length;
                         });
    for (uint32_t c : corners) {
      const std::size_t own = c / 3;
      glm::dvec3 sum(0.0);
      if (uniform) {
        sum = smooth;
      } else {
        for (uint32_t other : corners) {
          const std::size_t t = other / 3;
          // The angle between two faces' normals, without dividing: a . b >= |a| |b| cos.
          if (glm::dot(weighted[t], weighted[own]) >= cos_crease * lengths[t] * lengths[own]) {
            sum += weighted[t];
          }
        }
      }
      normals[c] = normal_of(sum, own);
    }
  }
  return normals;
}

}  // namespace

std::size_t compute_creased_normals(Mesh& mesh, double crease_degrees) {
  const std::vector<glm::vec3> corner_normals = normals_at_corners(mesh, crease_degrees);
  // One vertex per distinct normal at a position: the first keeps the vertex, each other
  // normal gets a copy of it.
  mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
  std::vector<bool> assigned(mesh.positions.size(), false);
  std::unordered_map<uint32_t, std::vector<uint32_t>> copies;  // only vertices on hard edges
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
