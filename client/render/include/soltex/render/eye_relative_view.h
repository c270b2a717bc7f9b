#pragma once

#include <glm/mat4x4.hpp>
#include <vector>

#include "soltex/raster/raster_object.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/camera.h"

// Frames are drawn relative to the eye: the float matrices the rasterizer gets then carry only
// offsets from the camera, so objects far from the origin (1e6, 1e9) keep their precision.
namespace soltex {

struct EyeRelativeView {
  std::vector<RasterObject> objects;
  std::vector<glm::dvec4> clip_planes;
  glm::dmat4 view_projection;
  double near = 0.0;  // the near plane view_projection has (further out than the camera's
                      // where no object comes nearer: float depth then keeps its order)
};

// The scene as a width x height frame of `camera` draws it. `simplified`: each object at the
// coarsest level of its mesh no pixel can tell from it; the reference draws every mesh as is.
EyeRelativeView eye_relative_view(const PreparedScene& scene, const Camera& camera, int width,
                                  int height, bool simplified);

}  // namespace soltex
