#pragma once

#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <limits>

#include "soltex/raster/raster_mesh.h"

// One object to draw: a mesh, where it is, and where its texture space is.
namespace soltex {

struct RasterObject {
  RasterMesh mesh;
  glm::mat4 model{1.0f};  // object space -> world space
  // Object space -> texture space, in double: an object's texture space may sit far from the
  // origin (1e6, 1e9), where a float could not tell neighbouring samples apart. For a
  // world-space texture pass texture_from_world * model.
  glm::dmat4 texture_from_object{1.0};
  uint32_t object_id = 0;  // copied to every pixel the object wins
  // Which of the view's clip planes cut this object: bit j selects RasterView::clip_planes[j].
  // A scene's plane usually cuts one object and leaves the others whole.
  uint32_t clip_plane_mask = ~0u;
  // The mesh bounds a solid. Only then is a back face seen through a user clip plane the
  // inside of the solid, drawn as a cap; for a sheet (a ground plane, a terrain) it stays a
  // back face.
  bool closed = true;
  // The mesh's object-space bounds, or unbounded. A cap lies inside its solid, so one traced
  // outside them (through a hole, or a face wound the wrong way) is no cap.
  glm::vec3 bounds_min{-std::numeric_limits<float>::infinity()};
  glm::vec3 bounds_max{std::numeric_limits<float>::infinity()};
  // Draw front faces only (OpenGL's glCullFace(GL_BACK), glTF's doubleSided: false): back
  // faces are dropped at set-up, before they cost any drawing. For a closed mesh seen from
  // outside they are hidden anyway; an open mesh then shows nothing through its holes. Ignored
  // while clip_plane_mask names one of the view's clip planes: caps are drawn where back
  // faces show.
  bool cull_back_faces = false;
};

}  // namespace soltex
