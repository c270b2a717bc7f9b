#include "object_picker.h"

#include "soltex/render/eye_relative_view.h"

namespace soltex::view {

ObjectPicker::ObjectPicker() : rasterizer_(RasterOptions{1, false}) {}

std::optional<std::size_t> ObjectPicker::pick(const PreparedScene& scene, const Camera& camera,
                                              int width, int height, int x, int y) {
  if (width <= 0 || height <= 0 || x < 0 || y < 0 || x >= width || y >= height) {
    return std::nullopt;
  }
  // Moves the pixel's centre to the centre of normalized device coordinates and widens it to
  // fill them (as gluPickMatrix does), in clip space: x' = width * (x - centre_x * w).
  const double centre_x = (x + 0.5) / width * 2.0 - 1.0;
  const double centre_y = 1.0 - (y + 0.5) / height * 2.0;
  glm::dmat4 pick_matrix(1.0);
  pick_matrix[0][0] = width;
  pick_matrix[3][0] = -centre_x * width;
  pick_matrix[1][1] = height;
  pick_matrix[3][1] = -centre_y * height;

  // The scene as the frame draws it (relative to the eye, its near plane, its mesh levels),
  // so the pick sees the depth order the picture shows.
  const EyeRelativeView frame = eye_relative_view(scene, camera, width, height, true);
  RasterView view;
  view.width = 1;
  view.height = 1;
  view.view_projection = glm::mat4(pick_matrix * frame.view_projection);
  view.clip_planes = frame.clip_planes;
  rasterizer_.render(view, frame.objects, gbuffer_);

  const uint32_t id = gbuffer_.object_id[0];
  if (id == GBuffer::kNoObject) return std::nullopt;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (scene.objects[i].raster.object_id == id) return i;
  }
  return std::nullopt;
}

}  // namespace soltex::view
