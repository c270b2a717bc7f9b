// The scenes the accuracy targets are stated for (docs/IMAGES.md, "Targets").
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <stdexcept>

#include "image_case.h"
#include "soltex/scene/default_scene.h"

namespace soltex::images {
namespace {

using nlohmann::json;

// The lecture's first solid texture: a box with a checker, seen as a new user sees it.
json lecture_box(const json& checker) {
  return json{
      {"image", {{"width", 640}, {"height", 480}}},
      {"camera", {{"position", {2.2, 2.5, 4}}}},
      {"lights", json::array({{{"directional", {{"direction", {-0.5, -1, -0.7}}}}}})},
      {"objects",
       json::array({{{"mesh", "box"}, {"material", {{"texture", {{"checker", checker}}}}}}})}};
}

// A UV sphere of radius 1 centred on (c, c, c), its coordinates printed in full precision.
std::filesystem::path write_sphere_obj(const std::filesystem::path& folder, double c) {
  char name[64];
  std::snprintf(name, sizeof name, "sphere-at-%g.obj", c);
  const std::filesystem::path path = folder / name;
  std::ofstream out(path);
  constexpr int kRings = 32, kSegments = 64;
  for (int r = 0; r <= kRings; ++r) {
    const double theta = std::numbers::pi * r / kRings;
    for (int s = 0; s < kSegments; ++s) {
      const double phi = 2.0 * std::numbers::pi * s / kSegments;
      char line[160];
      std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", c + std::sin(theta) * std::cos(phi),
                    c + std::cos(theta), c + std::sin(theta) * std::sin(phi));
      out << line;
    }
  }
  for (int r = 0; r < kRings; ++r) {
    for (int s = 0; s < kSegments; ++s) {
      const int a = r * kSegments + s + 1, b = r * kSegments + (s + 1) % kSegments + 1;
      out << "f " << a << ' ' << a + kSegments << ' ' << b + kSegments << ' ' << b << '\n';
    }
  }
  if (!out) throw std::runtime_error("cannot write " + path.string());
  return path;
}

json obj_sphere_scene(const std::filesystem::path& obj) {
  return json{
      {"image", {{"width", 320}, {"height", 240}}},
      {"camera", {{"position", {2.2, 2.5, 4}}}},
      {"lights", json::array({{{"directional", {{"direction", {-0.5, -1, -0.7}}}}}})},
      {"objects", json::array({{{"mesh", {{"obj", {{"path", obj.string()}}}}},
                                {"material", {{"texture", {{"marble", {{"frequency", 2}}}}}}}}})}};
}

ImageCase target(std::string name, std::string scene, double floor, double share) {
  ImageCase c;
  c.group = "targets";
  c.name = std::move(name);
  c.scene_json = std::move(scene);
  c.psnr_floor = floor;
  c.max_share_off = share;
  return c;
}

}  // namespace

void target_cases(std::vector<ImageCase>& cases, const std::filesystem::path& scratch) {
  cases.push_back(target("box, 3D checker of 0.25 (the lecture's first solid texture)",
                         lecture_box({{"three_d", true}, {"size", {0.25, 0.25, 0.25}}}).dump(),
                         35.0, 0.02));
  cases.push_back(target("box, 2D checker", lecture_box(json::object()).dump(), 35.0, 0.02));
  ImageCase scene = target("default scene, 1280x720", default_scene_json(), 38.0, 0.02);
  scene.finest_level_log2 = 9;
  cases.push_back(scene);
  scene.name = "default scene, 1280x720, --antialias 2";
  scene.psnr_floor = 42.0;
  scene.antialias = 2;
  cases.push_back(scene);
  std::filesystem::create_directories(scratch);
  const std::string origin = "OBJ sphere near the origin";
  cases.push_back(
      target(origin, obj_sphere_scene(write_sphere_obj(scratch, 0.0)).dump(), 35.0, 0.03));
  for (double far : {1e6, 1e9}) {
    char name[64];
    std::snprintf(name, sizeof name, "OBJ sphere at %g, against the one near the origin", far);
    ImageCase c = target(name, obj_sphere_scene(write_sphere_obj(scratch, far)).dump(), 40.0, 0.01);
    c.same_as = origin;
    cases.push_back(c);
  }
}

}  // namespace soltex::images
