#include "soltex/render/prepared_scene.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>
#include <string>

#include "soltex/common/spec_error.h"
#include "soltex/raster/raster_view.h"
#include "soltex/scene/scene_loader.h"
#include "soltex/scene/texture_volume.h"

namespace soltex {

// Every plane a scene may name is one the rasterizer can test.
static_assert(SceneLimits::kMaxClipPlanes <= static_cast<int>(RasterView::kMaxClipPlanes));

namespace {

// The object's brick layout. A volume its material asks for that bricks of this size cannot
// make (a finest level below the brick's) is refused as the scene file names it.
BrickLayout object_layout(const Scene& scene, uint32_t index, const Volume& volume,
                          int brick_size) {
  try {
    return BrickLayout(volume, brick_size);
  } catch (const SpecError& e) {
    if (e.field().rfind("volume", 0) != 0) throw;
    const std::string field = "objects[" + std::to_string(index) + "].material." + e.field();
    throw SpecError(scene.name.empty() ? field : scene.name + ": " + field, e.value(), e.bound());
  }
}

}  // namespace

PreparedScene prepare_scene(const Scene& scene, const TextureResolution& resolution,
                            net::BrickSource& source) {
  PreparedScene prepared;
  prepared.scene = &scene;
  for (const SceneObject& object : scene.objects) {
    for (const ClipPlane& plane : object.clip_planes) {
      // ClipPlane keeps n.p - offset <= 0; the rasterizer keeps a.p + d >= 0.
      const glm::dvec4 raster_plane(-plane.normal, plane.offset);
      if (std::find(prepared.clip_planes.begin(), prepared.clip_planes.end(), raster_plane) ==
          prepared.clip_planes.end()) {
        prepared.clip_planes.push_back(raster_plane);
      }
    }
  }
  uint32_t id = 0;
  for (const SceneObject& object : scene.objects) {
    const Mesh& mesh = *object.mesh;
    const glm::dmat4 model = object.transform.matrix();
    const bool world = object.material.space == TextureSpace::world;
    const glm::dmat4 texture_from_object = world ? model : glm::dmat4(1.0);
    const Volume volume = texture_volume(object, resolution.finest_level_log2);
    PreparedObject p{&object, RasterObject{},
                     model,   object.material.texture,
                     volume,  object_layout(scene, id, volume, resolution.brick_size),
                     0,       object.material.texture.channels.sample_count(),
                     false,   {}};
    p.raster.mesh = {mesh.positions, mesh.normals, mesh.indices};
    p.raster.model = glm::mat4(model);
    p.raster.texture_from_object = texture_from_object;
    p.raster.object_id = id++;
    p.raster.cull_back_faces = !object.double_sided && !mesh.two_sided;
    p.raster.closed = object.solid.value_or(true);
    p.raster.bounds_min = mesh.bounds.min;
    p.raster.bounds_max = mesh.bounds.max;
    p.raster.clip_plane_mask = 0;
    for (const ClipPlane& plane : object.clip_planes) {
      const glm::dvec4 raster_plane(-plane.normal, plane.offset);
      const auto at =
          std::find(prepared.clip_planes.begin(), prepared.clip_planes.end(), raster_plane);
      p.raster.clip_plane_mask |= 1u << static_cast<uint32_t>(at - prepared.clip_planes.begin());
    }
    try {
      p.texture_id =
          source.register_texture(p.texture, volume, resolution.brick_size, resolution.mip);
    } catch (const net::TextureRefused& e) {
      // The rest of the scene still draws from the server; this object costs more per pixel.
      p.evaluated_here = true;
      p.refusal = e.what();
    }
    prepared.objects.push_back(std::move(p));
  }
  return prepared;
}

std::vector<std::size_t> evaluate_refused_textures(PreparedScene& prepared,
                                                   net::BrickSource& source) {
  std::vector<std::size_t> marked;
  for (const auto& [id, reason] : source.take_refused_textures()) {
    for (std::size_t i = 0; i < prepared.objects.size(); ++i) {
      PreparedObject& o = prepared.objects[i];
      if (o.texture_id != id || o.evaluated_here) continue;
      o.evaluated_here = true;
      o.refusal = reason;
      marked.push_back(i);
    }
  }
  return marked;
}

}  // namespace soltex
