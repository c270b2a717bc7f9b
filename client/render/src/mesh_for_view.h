#pragma once

#include "soltex/raster/raster_mesh.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/camera.h"

// Which of an object's meshes a frame draws: its own, or a simplified level (mesh_lod.h) whose
// error no pixel can show.
namespace soltex::render {

// The most a drawn level's surface may stray from the object's mesh, in pixels at the object's
// nearest point to the eye: a silhouette moves by less than half a pixel, the most a pixel
// centre already lies from an edge it is drawn by, and the texture position moves less still.
inline constexpr double kMaxLevelErrorPixels = 0.5;

// The coarsest level of `object` (whose levels turn normals by at most
// MeshLodLimits::kMaxNormalError) whose error, scaled to world space by the object's transform
// and seen at the nearest point of its bounding sphere (no nearer than the near plane), spans
// at most kMaxLevelErrorPixels of a frame `height` pixels high; the object's own mesh when no
// level qualifies (or it has none).
RasterMesh mesh_for_view(const PreparedObject& object, const Camera& camera, int height);

}  // namespace soltex::render
