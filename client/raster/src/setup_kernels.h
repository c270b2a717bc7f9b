#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "transformed_vertices.h"

// Triangle set-up of the common case in vector lanes: a triangle whose three vertices are
// valid, inside the guard band and carry a normal, and which straddles no user clip plane,
// needs no clipping, no clip forms and no face normal, so what TriangleSetup::emit() computes
// for it is the same arithmetic for every such triangle. Runtime-dispatched to the widest
// vector target the CPU has (setup_kernels.cpp); every target gives emit()'s bits.
namespace soltex::raster_internal {

struct SetupLanes {
  // Sixteen: a block of 64 (about 21 KB of planes) crowded the screen triangles being written
  // and the vertices being read out of the 32 KB first-level cache, and set-up ran slower.
  static constexpr std::size_t kCapacity = 16;
  template <typename T>
  using Lanes = std::array<T, kCapacity>;

  // What emit() decides for a triangle.
  enum Outcome : uint32_t { kEmitted = 0, kDegenerate = 1, kOffScreen = 2 };

  // In, per vertex k in the triangle's index order: the projection and the attributes.
  alignas(64) std::array<Lanes<int32_t>, 3> x, y;
  alignas(64) std::array<Lanes<double>, 3> depth;
  alignas(64) std::array<Lanes<float>, 3> inv_w;
  alignas(64) std::array<Lanes<double>, 3> tx, ty, tz;  // texture positions
  alignas(64) std::array<Lanes<float>, 3> nx, ny, nz;   // world normals
  Lanes<uint32_t> object;                               // the object's index in the frame

  // Out, per vertex k in the screen triangle's order (clockwise on screen).
  alignas(64) Lanes<uint32_t> outcome;  // Outcome
  alignas(64) Lanes<uint32_t> back_face;
  alignas(64) std::array<Lanes<int32_t>, 3> screen_x, screen_y;
  alignas(64) Lanes<double> double_area;  // an integer below 2^51 in magnitude
  alignas(64) Lanes<int32_t> min_px, min_py, max_px, max_py;
  alignas(64) Lanes<float> depth_at_vertex0, depth_per_x, depth_per_y;
  alignas(64) std::array<Lanes<float>, 3> corner_inv_w, offset_x, offset_y, offset_z;
  alignas(64) std::array<Lanes<float>, 3> normal_x, normal_y, normal_z;

  std::size_t count = 0;

  // Lane `count` takes the triangle (v0, v1, v2) of object `object_index`.
  void add(const TransformedVertex& v0, const TransformedVertex& v1, const TransformedVertex& v2,
           uint32_t object_index) {
    const std::size_t l = count++;
    const std::array<const TransformedVertex*, 3> v = {&v0, &v1, &v2};
    for (std::size_t k = 0; k < 3; ++k) {
      x[k][l] = v[k]->x;
      y[k][l] = v[k]->y;
      depth[k][l] = v[k]->depth;
      inv_w[k][l] = v[k]->inv_w;
      tx[k][l] = v[k]->texture.x;
      ty[k][l] = v[k]->texture.y;
      tz[k][l] = v[k]->texture.z;
      nx[k][l] = v[k]->normal.x;
      ny[k][l] = v[k]->normal.y;
      nz[k][l] = v[k]->normal.z;
    }
    object[l] = object_index;
  }
};

// The outputs of lanes [0, lanes.count) for a viewport of width x height pixels;
// keep_between_centres as TriangleSetup's.
void set_up_lanes(SetupLanes& lanes, int width, int height, bool keep_between_centres);

// For tests: the Highway targets compiled into setup_kernels.cpp.
int64_t setup_kernels_compiled_targets();

}  // namespace soltex::raster_internal
