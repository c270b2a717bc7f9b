#pragma once

#include <cstddef>
#include <vector>

#include "soltex/scene/mesh.h"

// Coarser versions of a fine mesh, for views in which its triangles are smaller than pixels.
//
// A frame's raster cost grows with the triangles drawn as well as with the pixels covered: a
// million-triangle sphere costs several times a ten-thousand-triangle one on the same pixels,
// though most of its triangles cover no pixel centre at all. Simplified once when the scene
// is loaded (meshoptimizer's edge-collapse simplifier, meshopt_simplify), each level about
// half the triangles of the one before, with a bound on how far its surface strays from the
// original; a frame draws the coarsest level whose bound, seen from the camera, stays under a
// fraction of a pixel (FrameRenderer), so the picture is the same to within that.
namespace soltex {

struct MeshLevel {
  Mesh mesh;  // its own compact vertices (a subset of the original's, unchanged)
  // How far the level's surface may lie from the original mesh's, in the mesh's units:
  // meshoptimizer's error estimate (the distance its quadrics measure from the original
  // triangles' planes), summed over the steps from the original, each step's being against the
  // level before. An estimate, not a bound: where a coarse triangle spans a curve its middle
  // can stray further (on a UV sphere's poles, a few times further).
  float error = 0.0f;
  // How far the level's normals may turn from the original's, in radians: over a spread of the
  // original vertices, the largest angle between a vertex's normal and that of the level's
  // nearest vertex. A scanned surface keeps much of its shading in normals that vary faster
  // than its positions; a smooth one loses little. (meshoptimizer 0.18's simplifier weighs
  // positions only.)
  float normal_error = 0.0f;
};

struct MeshLodLimits {
  // Meshes with fewer triangles get no levels: drawing them costs little next to their pixels.
  static constexpr std::size_t kMinTriangles = 32768;
  // No level below this many triangles.
  static constexpr std::size_t kCoarsestTriangles = 2048;
  // The most a kept level's normals may turn from the original's (MeshLevel::normal_error), in
  // radians: about 3 degrees, a few percent of a light's diffuse term at most. The first level
  // past it ends the chain (coarser ones only turn more), so a scanned mesh, whose fine
  // shading lives in its normals, keeps none or few.
  static constexpr float kMaxNormalError = 0.05f;
  // Original vertices whose normals are compared with each level's (evenly spread).
  static constexpr std::size_t kNormalProbes = 65536;
};

// The simplified levels of `mesh`, finest first, each with at most about half the triangles of
// the one before; empty for a mesh below MeshLodLimits::kMinTriangles triangles. The
// simplification stops early where a step cannot remove a quarter of the triangles (the mesh
// is as simple as its borders allow) or turns normals by more than
// MeshLodLimits::kMaxNormalError. Normals are the original vertices' (simplification keeps
// a subset of the vertices), and each level is ordered for locality like the original.
std::vector<MeshLevel> simplified_levels(const Mesh& mesh);

}  // namespace soltex
