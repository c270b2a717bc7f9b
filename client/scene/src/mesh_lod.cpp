#include "soltex/scene/mesh_lod.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/geometric.hpp>
#include <limits>
#include <utility>
#include <vector>

#include "soltex/scene/mesh_order.h"

namespace soltex {
namespace {

// `indices` over `source`'s vertices as a mesh of its own: only the vertices they use, in
// order of first use.
Mesh compact(const Mesh& source, std::vector<uint32_t> indices) {
  std::vector<uint32_t> remap(source.positions.size());
  const std::size_t used =
      meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), indices.size(), remap.size());
  Mesh mesh;
  mesh.positions.resize(used);
  mesh.normals.resize(source.normals.size() == source.positions.size() ? used : 0);
  for (std::size_t v = 0; v < remap.size(); ++v) {
    if (remap[v] == ~0u) continue;
    mesh.positions[remap[v]] = source.positions[v];
    if (!mesh.normals.empty()) mesh.normals[remap[v]] = source.normals[v];
  }
  meshopt_remapIndexBuffer(indices.data(), indices.data(), indices.size(), remap.data());
  mesh.indices = std::move(indices);
  mesh.update_bounds();
  order_for_locality(mesh);
  return mesh;
}

// MeshLevel::normal_error of `level` against `original`: each probed original vertex against
// the level's nearest vertex, found in a uniform grid of cells about the level's vertex
// spacing (the 27 cells around the probe; a probe with none there counts as turned by pi).
float normal_error(const Mesh& original, const Mesh& level) {
  if (level.normals.size() != level.positions.size() ||
      original.normals.size() != original.positions.size() || level.positions.empty()) {
    return 0.0f;
  }
  const glm::vec3 low = level.bounds.min, extent = level.bounds.max - level.bounds.min;
  const float longest = std::max({extent.x, extent.y, extent.z});
  const auto per_axis = static_cast<int>(
      std::clamp(std::cbrt(static_cast<double>(level.positions.size())), 1.0, 256.0));
  const float cell = longest > 0.0f ? longest / static_cast<float>(per_axis) : 1.0f;
  const auto cell_of = [&](const glm::vec3& p, int axis) {
    return std::clamp(static_cast<int>((p[axis] - low[axis]) / cell), 0, per_axis - 1);
  };
  const auto key = [&](int x, int y, int z) {
    return (static_cast<std::size_t>(z) * per_axis + static_cast<std::size_t>(y)) * per_axis +
           static_cast<std::size_t>(x);
  };
  // The level's vertices sorted by cell: a cell's run found by binary search.
  std::vector<std::pair<std::size_t, uint32_t>> grid(level.positions.size());
  for (uint32_t v = 0; v < level.positions.size(); ++v) {
    const glm::vec3& p = level.positions[v];
    grid[v] = {key(cell_of(p, 0), cell_of(p, 1), cell_of(p, 2)), v};
  }
  std::sort(grid.begin(), grid.end());
  const std::size_t stride =
      std::max<std::size_t>(1, original.positions.size() / MeshLodLimits::kNormalProbes);
  float worst = 0.0f;
  for (std::size_t v = 0; v < original.positions.size(); v += stride) {
    const glm::vec3& p = original.positions[v];
    float nearest = std::numeric_limits<float>::infinity();
    uint32_t found = 0;
    const int cx = cell_of(p, 0), cy = cell_of(p, 1), cz = cell_of(p, 2);
    for (int z = std::max(cz - 1, 0); z <= std::min(cz + 1, per_axis - 1); ++z)
      for (int y = std::max(cy - 1, 0); y <= std::min(cy + 1, per_axis - 1); ++y)
        for (int x = std::max(cx - 1, 0); x <= std::min(cx + 1, per_axis - 1); ++x) {
          const std::size_t cell_key = key(x, y, z);
          auto at = std::lower_bound(grid.begin(), grid.end(), std::pair{cell_key, 0u});
          for (; at != grid.end() && at->first == cell_key; ++at) {
            const uint32_t candidate = at->second;
            const glm::vec3 d = level.positions[candidate] - p;
            const float distance = glm::dot(d, d);
            if (distance < nearest) nearest = distance, found = candidate;
          }
        }
    const float cosine =
        std::isfinite(nearest) ? glm::dot(original.normals[v], level.normals[found]) : -1.0f;
    worst = std::max(worst, std::acos(std::clamp(cosine, -1.0f, 1.0f)));
  }
  return worst;
}

}  // namespace

std::vector<MeshLevel> simplified_levels(const Mesh& mesh) {
  std::vector<MeshLevel> levels;
  if (mesh.triangle_count() < MeshLodLimits::kMinTriangles || mesh.indices.size() % 3 != 0) {
    return levels;
  }
  for (uint32_t index : mesh.indices) {
    if (index >= mesh.positions.size()) return levels;  // the rasterizer refuses it as it is
  }
  const Mesh* finer = &mesh;
  float error = 0.0f;
  while (finer->triangle_count() / 2 >= MeshLodLimits::kCoarsestTriangles) {
    const float* xyz = &finer->positions.front().x;
    const std::size_t vertices = finer->positions.size();
    // Absolute errors are relative ones times this (meshoptimizer's convention).
    const float scale = meshopt_simplifyScale(xyz, vertices, sizeof(glm::vec3));
    std::vector<uint32_t> indices(finer->indices.size());
    float step_error = 0.0f;
    // No bound on the error (1.0 is the whole mesh): the triangle count sets each step, and
    // the error it cost is what the frame weighs.
    const std::size_t kept = meshopt_simplify(
        indices.data(), finer->indices.data(), finer->indices.size(), xyz, vertices,
        sizeof(glm::vec3), finer->indices.size() / 2, 1.0f, 0, &step_error);
    if (kept == 0 || 4 * kept > 3 * finer->indices.size()) break;
    indices.resize(kept);
    error += step_error * scale;
    Mesh simplified = compact(*finer, std::move(indices));
    const float turned = normal_error(mesh, simplified);
    if (!(turned <= MeshLodLimits::kMaxNormalError)) break;
    levels.push_back({std::move(simplified), error, turned});
    finer = &levels.back().mesh;
  }
  return levels;
}

}  // namespace soltex
