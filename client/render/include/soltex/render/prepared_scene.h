#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "soltex/common/brick_evaluator.h"
#include "soltex/common/brick_layout.h"
#include "soltex/net/brick_source.h"
#include "soltex/raster/raster_object.h"
#include "soltex/scene/scene.h"

namespace soltex {

// How finely textures are cached: chosen per client from its capability (or by hand).
struct TextureResolution {
  int finest_level_log2 = 8;  // used where a material does not set its own
  int brick_size = 16;
  MipSettings mip;
};

// One scene object ready to draw: its raster input and its registered texture.
struct PreparedObject {
  const SceneObject* object = nullptr;
  RasterObject raster;           // its model matrix is set per frame, relative to the eye
  glm::dmat4 world_from_object;  // the object's transform, in double
  TextureSpec texture;
  Volume volume;
  BrickLayout layout;
  uint64_t texture_id = 0;
  int channels = 0;
  // The source would not register the texture (net::TextureRefused): it is evaluated per
  // pixel here instead, and no brick of it is asked for. `refusal` says why.
  bool evaluated_here = false;
  std::string refusal;
};

struct PreparedScene {
  const Scene* scene = nullptr;
  std::vector<PreparedObject> objects;
  std::vector<glm::dvec4> clip_planes;  // raster convention: a.x + b.y + c.z + d >= 0 keeps
};

// Builds the raster objects and registers every material's texture with `source`, over the
// volume scene::texture_volume() gives (the material's, or a padded cube around the object in
// its texture space). A texture the source refuses alone is evaluated here (the caller says so:
// PreparedObject::refusal); any other failure throws. `scene` must outlive the result.
PreparedScene prepare_scene(const Scene& scene, const TextureResolution& resolution,
                            net::BrickSource& source);

// Marks the objects whose texture `source` refused after registering it
// (BrickSource::take_refused_textures) as evaluated here, with the source's reason, and
// returns their indices: a client draws on, those objects now per pixel.
std::vector<std::size_t> evaluate_refused_textures(PreparedScene& prepared,
                                                   net::BrickSource& source);

}  // namespace soltex
