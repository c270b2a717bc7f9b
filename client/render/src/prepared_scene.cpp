#include "soltex/render/prepared_scene.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/type_ptr.hpp>

namespace soltex {
namespace {

// A cube enclosing `box`, 4 % larger, so every surface point has room for a trilinear cell.
Volume cube_around(const BoundingBox& box, int finest_level_log2) {
  const glm::dvec3 lo(box.min), hi(box.max);
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double half = 0.52 * std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-3});
  Volume volume;
  volume.min = centre - half;
  volume.max = centre + half;
  volume.finest_level_log2 = finest_level_log2;
  return volume;
}

BoundingBox transformed_bounds(const BoundingBox& box, const glm::dmat4& m) {
  BoundingBox out;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 p((corner & 1) ? box.max.x : box.min.x, (corner & 2) ? box.max.y : box.min.y,
                       (corner & 4) ? box.max.z : box.min.z);
    out.extend(glm::vec3(glm::dvec3(m * glm::dvec4(p, 1.0))));
  }
  return out;
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
    const int level_log2 =
        object.material.volume.finest_level_log2.value_or(resolution.finest_level_log2);
    Volume volume;
    if (object.material.volume.box) {
      volume.min = object.material.volume.box->min;
      volume.max = object.material.volume.box->max;
      volume.finest_level_log2 = level_log2;
    } else {
      volume =
          cube_around(world ? transformed_bounds(mesh.bounds, model) : mesh.bounds, level_log2);
    }
    PreparedObject p{&object,
                     RasterObject{},
                     object.material.texture,
                     volume,
                     BrickLayout(volume, resolution.brick_size),
                     0,
                     object.material.texture.channels.sample_count()};
    p.raster.mesh = {mesh.positions, mesh.normals, mesh.indices};
    p.raster.model = glm::mat4(model);
    p.raster.texture_from_object = texture_from_object;
    p.raster.object_id = id++;
    p.raster.clip_plane_mask = 0;
    for (const ClipPlane& plane : object.clip_planes) {
      const glm::dvec4 raster_plane(-plane.normal, plane.offset);
      const auto at =
          std::find(prepared.clip_planes.begin(), prepared.clip_planes.end(), raster_plane);
      p.raster.clip_plane_mask |= 1u << static_cast<uint32_t>(at - prepared.clip_planes.begin());
    }
    p.texture_id =
        source.register_texture(p.texture, volume, resolution.brick_size, resolution.mip);
    prepared.objects.push_back(std::move(p));
  }
  return prepared;
}

}  // namespace soltex
