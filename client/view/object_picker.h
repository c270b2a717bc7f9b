#pragma once

#include <cstddef>
#include <optional>

#include "soltex/raster/gbuffer.h"
#include "soltex/raster/rasterizer.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/camera.h"

namespace soltex::view {

// Which object a pixel of a frame shows. Rasterizes the scene into a one-pixel view that is
// exactly that pixel of the width x height frame, so picking costs one tiny raster pass and
// sees clip planes and caps as the frame does.
class ObjectPicker {
 public:
  ObjectPicker();

  // The index into scene.objects of the object drawn at pixel (x, y); nullopt over the
  // background or outside the frame.
  std::optional<std::size_t> pick(const PreparedScene& scene, const Camera& camera, int width,
                                  int height, int x, int y);

 private:
  Rasterizer rasterizer_;
  GBuffer gbuffer_;
};

}  // namespace soltex::view
