#include "soltex/scene/builtin_meshes.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <stdexcept>
#include <string>

#include "soltex/common/overloaded.h"

namespace soltex {
namespace {

void check_length(const char* shape, const char* field, double value) {
  if (!(value >= ShapeLimits::kMinLength && value <= ShapeLimits::kMaxLength)) {
    throw std::invalid_argument(std::string(shape) + "." + field + " = " + std::to_string(value) +
                                ": must be in [1e-6, 1e6]");
  }
}

void check_count(const char* shape, const char* field, int value, int lo, int hi) {
  if (value < lo || value > hi) {
    throw std::invalid_argument(std::string(shape) + "." + field + " = " + std::to_string(value) +
                                ": must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                "]");
  }
}

uint32_t index_of(std::size_t i) {
  return static_cast<uint32_t>(i);
}

// Two counter-clockwise triangles for the quad a-b-c-d (counter-clockwise seen from outside).
void add_quad(std::vector<uint32_t>& indices, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
  indices.insert(indices.end(), {a, b, c, a, c, d});
}

// One side of an axis-aligned box with half-size `half`: a (subdivisions + 1)^2 vertex grid
// in the plane where coordinate `normal_axis` is sign * half, facing that way. Grid axis u
// runs along `u_axis` (descending when u_descends), v likewise, and u x v is the outward
// normal. Coordinates are computed from the integer step counted from the low end, so
// the faces that share an edge compute its vertices bit for bit alike.
struct FaceAxes {
  int normal_axis;
  double sign;
  int u_axis;
  bool u_descends;
  int v_axis;
  bool v_descends;
};

void add_face(Mesh& mesh, const glm::dvec3& half, const FaceAxes& face, int subdivisions) {
  const int n = subdivisions;
  const auto coordinate = [&](int axis, int step) {
    return -half[axis] + (2.0 * half[axis]) * step / n;
  };
  glm::vec3 normal(0.0f);
  normal[face.normal_axis] = static_cast<float>(face.sign);
  const uint32_t first = index_of(mesh.positions.size());
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      glm::dvec3 p(0.0);
      p[face.normal_axis] = face.sign * half[face.normal_axis];
      p[face.u_axis] = coordinate(face.u_axis, face.u_descends ? n - i : i);
      p[face.v_axis] = coordinate(face.v_axis, face.v_descends ? n - j : j);
      mesh.positions.emplace_back(p);
      mesh.normals.push_back(normal);
    }
  }
  const auto at = [&](int i, int j) {
    return first + index_of(static_cast<std::size_t>(j * (n + 1) + i));
  };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      add_quad(mesh.indices, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
}

}  // namespace

const char* shape_name(const BuiltinShape& shape) {
  static constexpr const char* kNames[] = {"sphere", "torus", "box", "plane"};
  static_assert(std::size(kNames) == std::variant_size_v<BuiltinShape>);
  return kNames[shape.index()];
}

Mesh make_sphere(const SphereShape& shape) {
  check_length("sphere", "radius", shape.radius);
  check_count("sphere", "segments", shape.segments, ShapeLimits::kMinSegments,
              ShapeLimits::kMaxSegments);
  check_count("sphere", "rings", shape.rings, ShapeLimits::kMinRings, ShapeLimits::kMaxSegments);
  Mesh mesh;
  const int segments = shape.segments, rings = shape.rings;
  const auto add_vertex = [&](double polar, double azimuth) {
    const glm::dvec3 n(std::sin(polar) * std::cos(azimuth), std::cos(polar),
                       -std::sin(polar) * std::sin(azimuth));
    mesh.positions.emplace_back(shape.radius * n);
    mesh.normals.emplace_back(n);
  };
  add_vertex(0.0, 0.0);  // north pole, index 0
  for (int ring = 1; ring < rings; ++ring) {
    for (int s = 0; s < segments; ++s) {
      add_vertex(std::numbers::pi * ring / rings, 2.0 * std::numbers::pi * s / segments);
    }
  }
  add_vertex(std::numbers::pi, 0.0);  // south pole, the last index
  const uint32_t south = index_of(mesh.positions.size() - 1);
  // Ring r (1-based) segment s; segments wrap so the seam shares its vertices.
  const auto at = [&](int ring, int s) {
    return index_of(1 + static_cast<std::size_t>((ring - 1) * segments + (s % segments)));
  };
  for (int s = 0; s < segments; ++s) {
    mesh.indices.insert(mesh.indices.end(), {0u, at(1, s), at(1, s + 1)});
    for (int ring = 1; ring + 1 < rings; ++ring) {
      add_quad(mesh.indices, at(ring, s), at(ring + 1, s), at(ring + 1, s + 1), at(ring, s + 1));
    }
    mesh.indices.insert(mesh.indices.end(), {at(rings - 1, s), south, at(rings - 1, s + 1)});
  }
  mesh.update_bounds();
  return mesh;
}

Mesh make_torus(const TorusShape& shape) {
  check_length("torus", "major_radius", shape.major_radius);
  check_length("torus", "minor_radius", shape.minor_radius);
  if (!(shape.minor_radius < shape.major_radius)) {
    throw std::invalid_argument(
        "torus.minor_radius = " + std::to_string(shape.minor_radius) +
        ": must be less than major_radius = " + std::to_string(shape.major_radius));
  }
  check_count("torus", "major_segments", shape.major_segments, ShapeLimits::kMinSegments,
              ShapeLimits::kMaxSegments);
  check_count("torus", "minor_segments", shape.minor_segments, ShapeLimits::kMinSegments,
              ShapeLimits::kMaxSegments);
  Mesh mesh;
  const int nu = shape.major_segments, nv = shape.minor_segments;
  for (int i = 0; i < nu; ++i) {
    const double u = 2.0 * std::numbers::pi * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double v = 2.0 * std::numbers::pi * j / nv;
      const glm::dvec3 n(std::cos(v) * std::cos(u), std::sin(v), -std::cos(v) * std::sin(u));
      const glm::dvec3 centre(shape.major_radius * std::cos(u), 0.0,
                              -shape.major_radius * std::sin(u));
      mesh.positions.emplace_back(centre + shape.minor_radius * n);
      mesh.normals.emplace_back(n);
    }
  }
  const auto at = [&](int i, int j) {
    return index_of(static_cast<std::size_t>((i % nu) * nv + (j % nv)));
  };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j)
      add_quad(mesh.indices, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
  }
  mesh.update_bounds();
  return mesh;
}

Mesh make_box(const BoxShape& shape) {
  check_length("box", "size.x", shape.size.x);
  check_length("box", "size.y", shape.size.y);
  check_length("box", "size.z", shape.size.z);
  check_count("box", "subdivisions", shape.subdivisions, 1, ShapeLimits::kMaxSubdivisions);
  Mesh mesh;
  const glm::dvec3 half = 0.5 * shape.size;
  constexpr int x = 0, y = 1, z = 2;
  constexpr FaceAxes kFaces[] = {
      {x, +1.0, z, true, y, false},  {x, -1.0, z, false, y, false}, {y, +1.0, x, false, z, true},
      {y, -1.0, x, false, z, false}, {z, +1.0, x, false, y, false}, {z, -1.0, x, true, y, false},
  };
  for (const FaceAxes& face : kFaces) add_face(mesh, half, face, shape.subdivisions);
  mesh.update_bounds();
  return mesh;
}

Mesh make_plane(const PlaneShape& shape) {
  check_length("plane", "size.x", shape.size.x);
  check_length("plane", "size.z", shape.size.y);
  check_count("plane", "subdivisions", shape.subdivisions, 1, ShapeLimits::kMaxSubdivisions);
  Mesh mesh;
  const glm::dvec3 half(0.5 * shape.size.x, 0.0, 0.5 * shape.size.y);
  add_face(mesh, half, FaceAxes{1, +1.0, 0, false, 2, true}, shape.subdivisions);
  mesh.update_bounds();
  return mesh;
}

Mesh make_mesh(const BuiltinShape& shape) {
  return std::visit(Overloaded{[](const SphereShape& s) { return make_sphere(s); },
                               [](const TorusShape& s) { return make_torus(s); },
                               [](const BoxShape& s) { return make_box(s); },
                               [](const PlaneShape& s) { return make_plane(s); }},
                    shape);
}

}  // namespace soltex
