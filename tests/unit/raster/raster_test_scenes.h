#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>
#include <numbers>
#include <optional>
#include <vector>

#include "soltex/raster/gbuffer.h"
#include "soltex/raster/raster_mesh.h"
#include "soltex/raster/raster_object.h"

// Meshes, cameras and reference rays shared by the rasterizer tests.
namespace soltex::raster_test {

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<uint32_t> indices;

  RasterMesh view() const { return {positions, normals, indices}; }
  void add_triangle(uint32_t a, uint32_t b, uint32_t c) {
    indices.insert(indices.end(), {a, b, c});
  }
};

// A closed UV sphere, counter-clockwise seen from outside, no duplicated seam or pole vertices.
inline Mesh uv_sphere(int stacks, int slices, float radius = 1.0f) {
  Mesh mesh;
  const double pi = std::numbers::pi;
  mesh.positions.push_back({0.0f, radius, 0.0f});
  for (int i = 1; i < stacks; ++i) {
    const double theta = pi * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2.0 * pi * j / slices;
      mesh.positions.push_back(glm::vec3(radius * std::sin(theta) * std::cos(phi),
                                         radius * std::cos(theta),
                                         -radius * std::sin(theta) * std::sin(phi)));
    }
  }
  mesh.positions.push_back({0.0f, -radius, 0.0f});
  for (const glm::vec3& p : mesh.positions) mesh.normals.push_back(glm::normalize(p));
  const auto ring = [slices](int i, int j) {
    return static_cast<uint32_t>(1 + (i - 1) * slices + (j % slices));
  };
  const auto bottom = static_cast<uint32_t>(mesh.positions.size() - 1);
  for (int j = 0; j < slices; ++j) {
    mesh.add_triangle(0, ring(1, j), ring(1, j + 1));
    for (int i = 1; i + 1 < stacks; ++i) {
      mesh.add_triangle(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
      mesh.add_triangle(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
    }
    mesh.add_triangle(ring(stacks - 1, j), bottom, ring(stacks - 1, j + 1));
  }
  return mesh;
}

// The closed box [-h, h], counter-clockwise seen from outside, flat (no normals).
inline Mesh box(const glm::vec3& h) {
  Mesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.positions.push_back({(i & 1) ? h.x : -h.x, (i & 2) ? h.y : -h.y, (i & 4) ? h.z : -h.z});
  }
  const uint32_t faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces) {
    mesh.add_triangle(f[0], f[1], f[2]);
    mesh.add_triangle(f[0], f[2], f[3]);
  }
  return mesh;
}

// Maps world (x, y) to pixel (x, y) directly (y down), z in [-1, 1] to depth.
inline glm::mat4 pixel_ortho(int width, int height) {
  return glm::ortho(0.0f, static_cast<float>(width), static_cast<float>(height), 0.0f, -1.0f, 1.0f);
}

inline glm::mat4 perspective_look_at(const glm::vec3& eye, const glm::vec3& target, int width,
                                     int height, float fov_y_degrees = 60.0f, float near = 0.1f,
                                     float far = 100.0f) {
  return glm::perspective(glm::radians(fov_y_degrees),
                          static_cast<float>(width) / static_cast<float>(height), near, far) *
         glm::lookAt(eye, target, glm::vec3(0.0f, 1.0f, 0.0f));
}

struct Ray {
  glm::dvec3 origin;
  glm::dvec3 direction;
};

// The world-space view ray through the centre of pixel (x, y), in double.
inline Ray pixel_ray(const glm::mat4& view_projection, int width, int height, double x, double y) {
  const glm::dmat4 inverse = glm::inverse(glm::dmat4(view_projection));
  const double ndc_x = (x + 0.5) / width * 2.0 - 1.0;
  const double ndc_y = 1.0 - (y + 0.5) / height * 2.0;
  const glm::dvec4 near = inverse * glm::dvec4(ndc_x, ndc_y, -1.0, 1.0);
  const glm::dvec4 far = inverse * glm::dvec4(ndc_x, ndc_y, 1.0, 1.0);
  const glm::dvec3 origin = glm::dvec3(near) / near.w;
  return {origin, glm::dvec3(far) / far.w - origin};
}

// Where the ray meets the plane (a, b, c, d), at a parameter t >= 0.
inline std::optional<glm::dvec3> hit_plane(const Ray& ray, const glm::dvec4& plane) {
  const double along = glm::dot(glm::dvec3(plane), ray.direction);
  if (along == 0.0) return std::nullopt;
  const double t = -(glm::dot(glm::dvec3(plane), ray.origin) + plane.w) / along;
  if (t < 0.0) return std::nullopt;
  return ray.origin + t * ray.direction;
}

inline bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Every covered pixel has finite, in-range values and every plane is free of NaN.
inline bool all_values_sane(const GBuffer& g) {
  for (std::size_t i = 0; i < g.pixel_count(); ++i) {
    if (std::isnan(g.footprint[i]) || g.footprint[i] < 0.0f) return false;
    if (std::isnan(g.footprint_minor[i]) || g.footprint_minor[i] < 0.0f) return false;
    if (!finite(g.footprint_axis[i])) return false;
    if (!g.covered(i)) continue;
    if (!(g.depth[i] >= 0.0f && g.depth[i] <= 1.0f)) return false;
    if (!finite(g.texture_position[i]) || !finite(g.normal[i])) return false;
    if (std::abs(glm::length(g.normal[i]) - 1.0f) > 1e-4f) return false;
  }
  return true;
}

// Every plane of two G-buffers equal, bit for bit.
inline void expect_same_buffer(const GBuffer& a, const GBuffer& b) {
  ASSERT_EQ(a.pixel_count(), b.pixel_count());
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.flags, b.flags);
  EXPECT_EQ(a.object_id, b.object_id);
  EXPECT_EQ(a.texture_position, b.texture_position);
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_EQ(a.footprint, b.footprint);
  EXPECT_EQ(a.footprint_axis, b.footprint_axis);
  EXPECT_EQ(a.footprint_minor, b.footprint_minor);
}

}  // namespace soltex::raster_test
