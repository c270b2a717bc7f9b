#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <variant>

#include "soltex/scene/mesh.h"

// Shapes that need no files, with their tessellation. All are centred at the origin. The
// sphere and the torus share their seam and pole vertices, so they are closed by index and
// have exact analytic normals; the box has one flat-shaded vertex grid per face.
namespace soltex {

struct SphereShape {
  double radius = 1.0;
  int segments = 64;  // around the y axis
  int rings = 32;     // from pole to pole
};

// A ring about the y axis, lying in the x-z plane.
struct TorusShape {
  double major_radius = 0.75;  // centre of the tube to the centre of the torus
  double minor_radius = 0.3;   // radius of the tube; less than major_radius
  int major_segments = 64;
  int minor_segments = 32;
};

struct BoxShape {
  glm::dvec3 size{2.0, 2.0, 2.0};
  int subdivisions = 1;  // quads along each edge of each face
};

// A single-sided square in the x-z plane, facing +y.
struct PlaneShape {
  glm::dvec2 size{2.0, 2.0};  // along x and z
  int subdivisions = 1;
};

using BuiltinShape = std::variant<SphereShape, TorusShape, BoxShape, PlaneShape>;

// Bounds on the parameters; beyond them the builders throw std::invalid_argument and scene
// files are rejected. They keep a built-in mesh below about two million triangles.
struct ShapeLimits {
  static constexpr double kMinLength = 1e-6;
  static constexpr double kMaxLength = 1e6;
  static constexpr int kMinSegments = 3;
  static constexpr int kMinRings = 2;
  static constexpr int kMaxSegments = 1024;
  static constexpr int kMaxSubdivisions = 256;
};

// "sphere", "torus", "box", "plane".
const char* shape_name(const BuiltinShape& shape);

Mesh make_sphere(const SphereShape& shape);
Mesh make_torus(const TorusShape& shape);
Mesh make_box(const BoxShape& shape);
Mesh make_plane(const PlaneShape& shape);
Mesh make_mesh(const BuiltinShape& shape);

}  // namespace soltex
