#pragma once

#include "soltex/scene/mesh.h"

// Whether a mesh is the surface of a solid. A clip plane shows a solid's inside as a cap where
// the view passes through its back faces; a sheet (a ground plane, a terrain, a bowl) has no
// inside, and its back faces are only its other side.
namespace soltex {

// The area of the holes a mesh's boundary outlines, as a fraction of its triangles' area.
// Vertices are matched by position, so faces drawn with their own vertices (flat shading, UV
// seams) still close. An edge is open where the faces on its two sides do not pair up in
// opposite directions; the open edges are followed into loops, and each loop counts with the
// area it spans (the length of its vector area). 0 for a closed, consistently wound mesh;
// about 1 for a sheet, whose one outline spans all of it.
double opening_fraction(const Mesh& mesh);

// Openings up to this fraction leave a mesh a solid: scanned and modelled meshes often keep
// small holes (the Stanford bunny's base: 0.018; the Utah teapot's spout and lid rim: 0.24),
// while a hemisphere's opening is 0.5 of its area and a sheet's 1.
inline constexpr double kMostOpeningOfASolid = 1.0 / 3.0;

// Whether a mesh's openings leave it a solid (opening_fraction() at most kMostOpeningOfASolid).
inline bool openings_leave_a_solid(const Mesh& mesh) {
  return opening_fraction(mesh) <= kMostOpeningOfASolid;
}

}  // namespace soltex
