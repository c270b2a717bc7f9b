#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>

// A borrowed, indexed triangle mesh: the rasterizer reads it during one render call and keeps
// nothing. Triangles are counter-clockwise when seen from the front (OpenGL's default).
namespace soltex {

struct RasterMesh {
  std::span<const glm::vec3> positions;  // object space
  // One per position, or empty: then every triangle is flat-shaded with its face normal.
  std::span<const glm::vec3> normals;
  // Three per triangle. A triangle with an index past the positions is skipped and counted
  // (RasterStats::triangles_invalid), like one with a non-finite vertex.
  std::span<const uint32_t> indices;

  std::size_t triangle_count() const { return indices.size() / 3; }
};

}  // namespace soltex
