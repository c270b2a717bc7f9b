#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "homogeneous_clipper.h"
#include "object_frame.h"
#include "screen_triangle.h"
#include "setup_kernels.h"
#include "soltex/raster/raster_stats.h"
#include "transformed_vertices.h"

// Triangle setup: from three transformed vertices to zero or more screen triangles.
//
// In order: skip invalid triangles (index out of range, non-finite vertex); cull a triangle
// wholly outside one side of the view volume; drop a back face of an object drawn front faces
// only (ObjectFrame::cull_back_faces); classify it against the user clip planes (wholly
// removed: dropped; straddling: its fragments will be tested); clip it in homogeneous space
// against the near plane (and the guard band, when a vertex is far outside the viewport);
// project, snap to fixed point, orient, and write the affine forms of depth and clip distance.
namespace soltex::raster_internal {

// Screen coordinates are kept within this many pixels outside the viewport (by clipping),
// so fixed-point coordinates stay below 2^23 in magnitude.
inline constexpr int kGuardBandPixels = 8192;

class TriangleSetup {
 public:
  // keep_between_centres: RasterView::edge_sampling.
  TriangleSetup(int width, int height, int clip_plane_count, bool keep_between_centres = false);

  // Projects vertices [begin, end) (indices into `vertices`) one at a time, for setup() to
  // reuse in every triangle that uses them and needs no clipping: the same values it would
  // compute. The definition that transform_and_project() computes in lanes.
  void project_vertices(TransformedVertices& vertices, std::size_t begin, std::size_t end) const;

  // transform_vertices() of the object's vertices [begin, end) (indices into its mesh), then
  // project_vertices() of them, in vector lanes (vertex_kernels.h): the same values. What a
  // frame runs.
  void transform_and_project(const ObjectFrame& object, std::size_t begin, std::size_t end,
                             TransformedVertices& vertices) const;

  // Appends the screen triangles of the object's triangle (i0, i1, i2) to `triangles`, their
  // clip-plane forms to `clip_forms`, and counts what it did: one triangle at a time, the
  // definition that setup_range(), what a frame runs, is checked against.
  void setup(const ObjectFrame& object, uint32_t object_index, const TransformedVertices& vertices,
             uint32_t i0, uint32_t i1, uint32_t i2, ScreenTriangles& triangles,
             std::vector<AffineForm>& clip_forms, RasterStats& stats) const;

  // setup() of the object's triangles [first, end) (triangle i: indices[3 i .. 3 i + 2]), the
  // same triangles in the same order with the same counts: those that need neither clipping
  // nor clip forms nor a face normal (most of a mesh's) set up together in `lanes`
  // (set_up_lanes()), the rest one at a time as setup() does, after what the lanes hold.
  // Returns how many went through the lanes. Whatever `lanes` held before is dropped.
  std::size_t setup_range(const ObjectFrame& object, uint32_t object_index,
                          const TransformedVertices& vertices, std::span<const uint32_t> indices,
                          std::size_t first, std::size_t end, SetupLanes& lanes,
                          ScreenTriangles& triangles, std::vector<AffineForm>& clip_forms,
                          RasterStats& stats) const;

 private:
  using ProjectedVertex = ScreenVertex;
  struct SourceTriangle;
  struct Classified;

  // setup()'s tests before any attribute work (indices, validity, the view volume, an early
  // back face, the user clip planes); false when they drop the triangle.
  bool classify(const ObjectFrame& object, uint32_t object_index,
                const TransformedVertices& vertices, const std::array<uint32_t, 3>& index,
                Classified& c, RasterStats& stats) const;
  // The rest of setup() for a triangle classify() kept: clipping, attributes, emit().
  void finish(const ObjectFrame& object, const TransformedVertices& vertices, Classified& c,
              ScreenTriangles& triangles, std::vector<AffineForm>& clip_forms,
              RasterStats& stats) const;
  // Sets up what `lanes` holds and appends its triangles, in order; empties it.
  void flush(SetupLanes& lanes, ScreenTriangles& triangles, RasterStats& stats) const;

  ProjectedVertex project(const glm::vec4& clip) const;
  void emit(const SourceTriangle& source, const ClipPolygon& polygon,
            const std::array<const ProjectedVertex*, ClipPolygon::kCapacity>& projected,
            std::array<int, 3> corners, bool cull_back_faces, ScreenTriangles& triangles,
            std::vector<AffineForm>& clip_forms, RasterStats& stats) const;

  int width_;
  int height_;
  int clip_plane_count_;
  bool keep_between_centres_;
  ClipPlanes clip_planes_;
};

}  // namespace soltex::raster_internal
