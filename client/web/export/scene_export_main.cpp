// soltex-scene-export: reads a scene file with the same loader as soltex-view and writes what
// the web viewer draws: every object's triangles in world space with their normals and
// texture-volume coordinates, its registration (docs/PROTOCOL.md section 9), material, clip
// planes, and the camera and lights. Meshes, volumes and texture ids thus agree exactly with
// soltex-view's.
//   soltex-scene-export --scene deploy/scenes/knot-marble.json --finest-level 9 --out knot.json
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>
#include <variant>

#include "soltex/cli/tool_cli.h"
#include "soltex/scene/default_scene.h"
#include "soltex/scene/mesh_openings.h"
#include "soltex/scene/scene_loader.h"
#include "soltex/scene/texture_spec_json.h"
#include "soltex/scene/texture_volume.h"

namespace {

using nlohmann::json;

json vec3(const glm::dvec3& v) {
  return json::array({v.x, v.y, v.z});
}

json registration(const soltex::SceneObject& object, int finest_level) {
  const soltex::Volume volume = soltex::texture_volume(object, finest_level);
  return {{"texture", soltex::texture_spec_to_json(object.material.texture)},
          {"volume",
           {{"min", vec3(volume.min)},
            {"max", vec3(volume.max)},
            {"finest_level_log2", volume.finest_level_log2}}},
          {"brick_size", 16},
          {"mip_mode", "band_limited"}};
}

// Positions and normals in world space; texture coordinates in [0, 1]^3 across the volume,
// from the object-space or world-space position as the material says.
json geometry(const soltex::SceneObject& object, const soltex::Volume& volume) {
  const glm::dmat4 to_world = object.transform.matrix();
  const glm::dmat3 normal_matrix = object.transform.normal_matrix();
  const bool world_space = object.material.space == soltex::TextureSpace::world;
  std::vector<float> positions, normals, texcoords;
  for (std::size_t i = 0; i < object.mesh->positions.size(); ++i) {
    const glm::dvec3 p(object.mesh->positions[i]);
    const glm::dvec3 world = glm::dvec3(to_world * glm::dvec4(p, 1.0));
    const glm::dvec3 n = glm::normalize(normal_matrix * glm::dvec3(object.mesh->normals[i]));
    const glm::dvec3 t = ((world_space ? world : p) - volume.min) / (volume.max - volume.min);
    for (int k = 0; k < 3; ++k) {
      positions.push_back(static_cast<float>(world[k]));
      normals.push_back(static_cast<float>(n[k]));
      texcoords.push_back(static_cast<float>(t[k]));
    }
  }
  return {{"positions", positions},
          {"normals", normals},
          {"texcoords", texcoords},
          {"indices", object.mesh->indices}};
}

// World position -> texture-volume coordinates, column-major: where a clip plane's cap (the
// solid's cut face) takes its texture.
json world_to_volume(const soltex::SceneObject& object, const soltex::Volume& volume) {
  const glm::dmat4 to_texture_space = object.material.space == soltex::TextureSpace::world
                                          ? glm::dmat4(1.0)
                                          : glm::inverse(object.transform.matrix());
  glm::dmat4 to_unit(1.0);
  for (int k = 0; k < 3; ++k) {
    to_unit[k][k] = 1.0 / (volume.max[k] - volume.min[k]);
    to_unit[3][k] = -volume.min[k] / (volume.max[k] - volume.min[k]);
  }
  const glm::dmat4 m = to_unit * to_texture_space;
  json out = json::array();
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) out.push_back(m[c][r]);
  }
  return out;
}

json lights_json(const soltex::Scene& scene) {
  json lights = json::array();
  for (const soltex::Light& light : scene.lights) {
    if (const auto* d = std::get_if<soltex::DirectionalLight>(&light)) {
      const glm::vec3 radiance = d->colour * d->intensity;
      lights.push_back({{"directional",
                         {{"direction", vec3(d->direction)},
                          {"radiance", {radiance.r, radiance.g, radiance.b}}}}});
    } else {
      const auto& p = std::get<soltex::PointLight>(light);
      const glm::vec3 radiance = p.colour * p.intensity;
      lights.push_back(
          {{"point",
            {{"position", vec3(p.position)}, {"radiance", {radiance.r, radiance.g, radiance.b}}}}});
    }
  }
  return lights;
}

json export_scene(const soltex::Scene& scene, int finest_level) {
  json out;
  out["description"] = scene.description;
  out["image"] = {{"width", scene.image.width}, {"height", scene.image.height}};
  const soltex::Camera& c = scene.camera;
  out["camera"] = {
      {"position", vec3(c.position)},     {"target", vec3(c.target)}, {"up", vec3(c.up)},
      {"fov_y_degrees", c.fov_y_degrees}, {"near", c.near},           {"far", c.far}};
  const glm::vec3 ambient = scene.ambient.colour * scene.ambient.intensity;
  out["ambient"] = {ambient.r, ambient.g, ambient.b};
  out["lights"] = lights_json(scene);
  out["objects"] = json::array();
  for (const soltex::SceneObject& object : scene.objects) {
    const soltex::Volume volume = soltex::texture_volume(object, finest_level);
    json o = geometry(object, volume);
    o["world_to_volume"] = world_to_volume(object, volume);
    o["name"] = object.name;
    o["double_sided"] =
        object.double_sided || object.mesh->two_sided || !object.clip_planes.empty();
    // Measured here for uncut objects too: the page's own cutting plane may cut them.
    o["solid"] = object.solid ? *object.solid : soltex::openings_leave_a_solid(*object.mesh);
    o["registration"] = registration(object, finest_level);
    o["specular"] = object.material.specular;
    o["shininess"] = object.material.shininess;
    o["unlit"] = object.material.unlit;
    o["clip_planes"] = json::array();
    for (const soltex::ClipPlane& plane : object.clip_planes) {
      o["clip_planes"].push_back({plane.normal.x, plane.normal.y, plane.normal.z, plane.offset});
    }
    out["objects"].push_back(std::move(o));
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = soltex::cli;
  std::string scene_file, out_file, log_level = "warn";
  int finest_level = 9;
  CLI::App app{"soltex-scene-export: a scene file as the web viewer draws it (JSON)"};
  cli::add_common_options(app, "soltex-scene-export", log_level);
  app.add_option("--scene", scene_file, "scene file (docs/SCENES.md); default: the built-in scene");
  app.add_option("--finest-level", finest_level,
                 "2^L cells per axis at level 0 for volumes that leave it to the client")
      ->check(soltex::cli::IntegerIn(4, 14))
      ->capture_default_str();
  app.add_option("--out", out_file, "output file")->required();
  if (const auto exit_code = cli::parse(app, "soltex-scene-export", argc, argv)) return *exit_code;
  try {
    const soltex::Scene scene =
        scene_file.empty() ? soltex::default_scene() : soltex::load_scene(scene_file);
    std::ofstream(out_file) << export_scene(scene, finest_level).dump() << "\n";
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soltex-scene-export: %s\n", e.what());
    return cli::kExitFailure;
  }
  return cli::kExitOk;
}
