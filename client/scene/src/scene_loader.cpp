#include "soltex/scene/scene_loader.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <glm/geometric.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "json_reader.h"
#include "soltex/common/spec_error.h"
#include "soltex/common/text_file.h"
#include "soltex/scene/mesh_lod.h"
#include "soltex/scene/mesh_openings.h"
#include "soltex/scene/mesh_order.h"
#include "soltex/scene/obj_loader.h"
#include "soltex/scene/scene_error.h"
#include "soltex/scene/strict_json.h"
#include "soltex/scene/texture_spec_json.h"
#include "soltex/scene/texture_volume.h"

namespace soltex {
namespace {

constexpr double kMaxCoordinate = SceneLimits::kMaxCoordinate;
constexpr double kMaxIntensity = 1e6;

// A direction: non-zero, returned with unit length. Scaled by its largest component first, so
// that a tiny one (1e-13, or denormal components) has a length that does not underflow.
glm::dvec3 read_direction(const JsonValue& value) {
  const glm::dvec3 v = value.vec3(-kMaxCoordinate, kMaxCoordinate);
  const glm::dvec3 magnitude = glm::abs(v);
  const double largest = std::max({magnitude.x, magnitude.y, magnitude.z});
  if (!(largest > 0.0)) value.fail("must not be the zero vector");
  return glm::normalize(v / largest);
}

ImageSize read_image(const JsonValue& value) {
  JsonObject object(value);
  ImageSize image;
  // Refused outside the bounds, never quietly replaced: the output is the size asked for.
  image.width =
      object.integer("width", image.width, SceneLimits::kMinImageSide, SceneLimits::kMaxImageSide);
  image.height = object.integer("height", image.height, SceneLimits::kMinImageSide,
                                SceneLimits::kMaxImageSide);
  object.reject_unknown_keys();
  return image;
}

CameraOrbit read_orbit(const JsonValue& value) {
  JsonObject object(value);
  CameraOrbit orbit;
  const std::size_t which = object.one_of({"degrees_per_frame", "degrees_per_second"}, {"frames"});
  orbit.rate = which == 0 ? CameraOrbit::Rate::per_frame : CameraOrbit::Rate::per_second;
  orbit.degrees =
      object.get(which == 0 ? "degrees_per_frame" : "degrees_per_second").number(-360.0, 360.0);
  orbit.frames = object.integer("frames", orbit.frames, 1, SceneLimits::kMaxOrbitFrames);
  object.reject_unknown_keys();
  return orbit;
}

void read_camera(const JsonValue& value, Scene& scene) {
  JsonObject object(value);
  Camera& camera = scene.camera;
  camera.position = object.vec3("position", camera.position, -kMaxCoordinate, kMaxCoordinate);
  camera.target = object.vec3("target", camera.target, -kMaxCoordinate, kMaxCoordinate);
  const auto up = object.find("up");
  if (up) camera.up = read_direction(*up);
  camera.fov_y_degrees = object.number("fov_y_degrees", camera.fov_y_degrees, 1.0, 179.0);
  camera.near = object.number("near", camera.near, 1e-6, 1e6);
  const auto far = object.find("far");
  if (far) camera.far = far->number(1e-6, 1e7);
  if (const auto orbit = object.find("orbit")) scene.orbit = read_orbit(*orbit);
  object.reject_unknown_keys();

  if (!(camera.far > camera.near)) {
    (far ? *far : value)
        .fail("far = " + format_number(camera.far) +
              " must be greater than near = " + format_number(camera.near));
  }
  const glm::dvec3 view = camera.target - camera.position;
  // A view direction from points closer than this would carry little but their rounding.
  constexpr double kMinViewDistance = 1e-9;
  if (!(glm::length(view) >= kMinViewDistance)) {
    value.fail("position and target are " + format_number(glm::length(view)) +
               " apart; they must be at least " + format_number(kMinViewDistance) + " apart");
  }
  if (!(glm::length(glm::cross(glm::normalize(view), camera.up)) > 1e-6)) {
    if (up) up->fail("must not be parallel to the view direction (target - position)");
    value.fail(
        "up, absent, is [0, 1, 0], parallel to the view direction (target - position): give "
        "an up not parallel to it");
  }
}

AmbientLight read_ambient(const JsonValue& value) {
  JsonObject object(value);
  AmbientLight ambient;
  ambient.colour = object.colour("colour", ambient.colour);
  ambient.intensity =
      static_cast<float>(object.number("intensity", ambient.intensity, 0.0, kMaxIntensity));
  object.reject_unknown_keys();
  return ambient;
}

Light read_light(const JsonValue& value) {
  JsonObject outer(value);
  const std::size_t which = outer.one_of({"directional", "point"});
  outer.reject_unknown_keys();
  JsonObject object(outer.get(which == 0 ? "directional" : "point"));
  Light light;
  if (which == 0) {
    DirectionalLight directional;
    if (const auto direction = object.find("direction")) {
      directional.direction = read_direction(*direction);
    }
    directional.colour = object.colour("colour", directional.colour);
    directional.intensity =
        static_cast<float>(object.number("intensity", directional.intensity, 0.0, kMaxIntensity));
    light = directional;
  } else {
    PointLight point;
    point.position = object.get("position").vec3(-kMaxCoordinate, kMaxCoordinate);
    point.colour = object.colour("colour", point.colour);
    point.intensity =
        static_cast<float>(object.number("intensity", point.intensity, 0.0, kMaxIntensity));
    light = point;
  }
  object.reject_unknown_keys();
  return light;
}

double read_length(JsonObject& object, const char* key, double fallback) {
  return object.number(key, fallback, ShapeLimits::kMinLength, ShapeLimits::kMaxLength);
}

int read_segments(JsonObject& object, const char* key, int fallback, int minimum) {
  return object.integer(key, fallback, minimum, ShapeLimits::kMaxSegments);
}

int read_subdivisions(JsonObject& object, int fallback) {
  return object.integer("subdivisions", fallback, 1, ShapeLimits::kMaxSubdivisions);
}

constexpr const char* kMeshKinds[] = {"sphere", "torus", "box", "plane", "obj"};

BuiltinShape read_builtin(std::size_t which, JsonObject object) {
  switch (which) {
    case 0: {
      SphereShape s;
      s.radius = read_length(object, "radius", s.radius);
      s.segments = read_segments(object, "segments", s.segments, ShapeLimits::kMinSegments);
      s.rings = read_segments(object, "rings", s.rings, ShapeLimits::kMinRings);
      object.reject_unknown_keys();
      return s;
    }
    case 1: {
      TorusShape s;
      s.major_radius = read_length(object, "major_radius", s.major_radius);
      const auto minor = object.find("minor_radius");
      if (minor) s.minor_radius = minor->number(ShapeLimits::kMinLength, ShapeLimits::kMaxLength);
      s.major_segments =
          read_segments(object, "major_segments", s.major_segments, ShapeLimits::kMinSegments);
      s.minor_segments =
          read_segments(object, "minor_segments", s.minor_segments, ShapeLimits::kMinSegments);
      object.reject_unknown_keys();
      if (!(s.minor_radius < s.major_radius)) {
        (minor ? *minor : object.value())
            .fail("minor_radius = " + format_number(s.minor_radius) +
                  " must be less than major_radius = " + format_number(s.major_radius));
      }
      return s;
    }
    case 2: {
      BoxShape s;
      if (const auto size = object.find("size")) {
        s.size = size->json().is_number()
                     ? glm::dvec3(size->number(ShapeLimits::kMinLength, ShapeLimits::kMaxLength))
                     : size->vec3(ShapeLimits::kMinLength, ShapeLimits::kMaxLength);
      }
      s.subdivisions = read_subdivisions(object, s.subdivisions);
      object.reject_unknown_keys();
      return s;
    }
    default: {
      PlaneShape s;
      if (const auto size = object.find("size")) {
        if (size->json().is_number()) {
          s.size = glm::dvec2(size->number(ShapeLimits::kMinLength, ShapeLimits::kMaxLength));
        } else {
          const std::vector<JsonValue> sides = size->elements(2);
          if (sides.size() != 2) size->fail("expected a number or [x, z]");
          s.size = {sides[0].number(ShapeLimits::kMinLength, ShapeLimits::kMaxLength),
                    sides[1].number(ShapeLimits::kMinLength, ShapeLimits::kMaxLength)};
        }
      }
      s.subdivisions = read_subdivisions(object, s.subdivisions);
      object.reject_unknown_keys();
      return s;
    }
  }
}

// A mesh as the file names it, before anything is built or loaded.
struct MeshRequest {
  MeshSource source;
  std::string cache_key;
  std::string field;  // for errors while loading
};

MeshRequest read_mesh(const JsonValue& value, const std::filesystem::path& obj_directory) {
  MeshRequest request;
  if (value.json().is_string()) {  // "sphere": a built-in with its defaults
    const std::size_t which =
        value.choice<std::size_t>({{"sphere", 0}, {"torus", 1}, {"box", 2}, {"plane", 3}});
    request.source = read_builtin(
        which, JsonObject(JsonValue(nlohmann::json::object(), value.path(), value.file())));
    request.cache_key = value.json().dump();
    return request;
  }
  JsonObject object(value);
  const std::size_t which =
      object.one_of({kMeshKinds[0], kMeshKinds[1], kMeshKinds[2], kMeshKinds[3], kMeshKinds[4]});
  object.reject_unknown_keys();
  const JsonValue inner = object.get(kMeshKinds[which]);
  if (which < 4) {
    request.source = read_builtin(which, JsonObject(inner));
    request.cache_key = value.json().dump();
    return request;
  }
  JsonObject obj(inner);
  const JsonValue path = obj.get("path");
  ObjFile file;
  const std::string text = path.string();
  if (text.empty()) path.fail("must not be empty");
  // The file system reads a path up to its first NUL: the file opened would not be the one
  // named.
  if (text.find('\0') != std::string::npos) path.fail("must not hold a NUL character");
  const std::filesystem::path named = text;
  file.path = named.is_absolute() ? named : obj_directory / named;
  file.normalize = obj.boolean("normalize", true);
  if (const auto crease = obj.find("crease_angle"))
    file.crease_degrees = crease->number(0.0, 180.0);
  obj.reject_unknown_keys();
  request.cache_key = "obj " + std::string(file.normalize ? "normalized " : "") + "crease " +
                      std::to_string(file.crease_degrees) + " " +
                      std::filesystem::absolute(file.path).lexically_normal().string();
  request.field = path.path();
  request.source = file;
  return request;
}

Transform read_transform(const JsonValue& value) {
  JsonObject object(value);
  Transform t;
  t.translate = object.vec3("translate", t.translate, -TransformLimits::kMaxTranslate,
                            TransformLimits::kMaxTranslate);
  t.rotate_degrees = object.vec3("rotate", t.rotate_degrees, -TransformLimits::kMaxRotateDegrees,
                                 TransformLimits::kMaxRotateDegrees);
  if (const auto scale = object.find("scale")) {
    t.scale =
        scale->json().is_number()
            ? glm::dvec3(scale->number(TransformLimits::kMinScale, TransformLimits::kMaxScale))
            : scale->vec3(TransformLimits::kMinScale, TransformLimits::kMaxScale);
  }
  object.reject_unknown_keys();
  return t;
}

Material read_material(const JsonValue& value) {
  JsonObject object(value);
  Material material;
  const JsonValue texture = object.get("texture");
  material.texture = texture_spec_from_json(texture.json(), texture.file(), texture.path());
  if (const auto space = object.find("space")) {
    material.space = space->choice<TextureSpace>(
        {{"object", TextureSpace::object}, {"world", TextureSpace::world}});
  }
  if (const auto volume = object.find("volume")) {
    JsonObject fields(*volume);
    const auto min = fields.find("min");
    const auto max = fields.find("max");
    if (min.has_value() != max.has_value()) {
      volume->fail("give both min and max, or neither (the object's padded bounds)");
    }
    if (const auto level = fields.find("finest_level_log2")) {
      // At least one brick of the smaller size, 8, on a side; bricks of 16 need 4.
      material.volume.finest_level_log2 = level->integer(3, SpecLimits::kMaxFinestLevelLog2);
    }
    fields.reject_unknown_keys();
    if (min) {
      const double bound = SpecLimits::kMaxVolumeCoordinate;
      Volume box;
      box.min = min->vec3(-bound, bound);
      box.max = max->vec3(-bound, bound);
      try {
        (void)validated(box);  // max > min on every axis
      } catch (const SpecError& error) {
        throw SceneError::from_spec_error(value.file(), value.path(), error);
      }
      material.volume.box = VolumeRequest::Box{box.min, box.max};
    }
  }
  material.specular = static_cast<float>(object.number("specular", material.specular, 0.0, 1.0));
  material.shininess =
      static_cast<float>(object.number("shininess", material.shininess, 1.0, 10000.0));
  material.unlit = object.boolean("unlit", material.unlit);
  object.reject_unknown_keys();
  return material;
}

// Clip planes name the objects they cut; an empty list cuts every object.
void read_clip_plane(const JsonValue& value, Scene& scene,
                     const std::map<std::string, std::size_t>& object_by_name) {
  JsonObject object(value);
  ClipPlane plane;
  plane.normal = read_direction(object.get("normal"));
  const auto point = object.find("point");
  const auto offset = object.find("offset");
  if (point && offset) value.fail("give offset or point, not both");
  if (point) plane.offset = glm::dot(plane.normal, point->vec3(-kMaxCoordinate, kMaxCoordinate));
  if (offset) plane.offset = offset->number(-kMaxCoordinate, kMaxCoordinate);
  std::vector<std::size_t> targets;
  const auto names = object.find("objects");
  if (names) {
    // An empty list would read as "no object" but the absent key means "every object":
    // neither may be guessed.
    if (names->json().is_array() && names->json().empty()) {
      names->fail("names no object: leave \"objects\" out to cut every object");
    }
    for (const JsonValue& name : names->elements(scene.objects.size())) {
      const auto found = object_by_name.find(name.string());
      if (found == object_by_name.end()) name.fail("no object is named \"" + name.string() + "\"");
      if (std::find(targets.begin(), targets.end(), found->second) != targets.end()) {
        name.fail("\"" + found->first + "\" is listed twice");
      }
      targets.push_back(found->second);
    }
  }
  object.reject_unknown_keys();
  if (!names) {
    for (SceneObject& target : scene.objects) target.clip_planes.push_back(plane);
  } else {
    for (std::size_t index : targets) scene.objects[index].clip_planes.push_back(plane);
  }
}

// Whether each object a clip plane cuts is a solid, as its scene says or else by the openings
// of its mesh, measured once per mesh. Uncut objects draw no caps, so theirs is not measured.
void decide_solids(Scene& scene, const std::vector<MeshRequest>& meshes,
                   const std::vector<std::optional<bool>>& solid_given) {
  std::map<std::string, bool> measured;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    SceneObject& object = scene.objects[i];
    if (solid_given[i]) {
      object.solid = solid_given[i];
    } else if (!object.clip_planes.empty()) {
      const auto [at, fresh] = measured.try_emplace(meshes[i].cache_key, false);
      if (fresh) at->second = openings_leave_a_solid(*object.mesh);
      object.solid = at->second;
    }
  }
}

std::shared_ptr<const Mesh> build_mesh(const MeshRequest& request, const std::string& file) {
  if (const auto* shape = std::get_if<BuiltinShape>(&request.source)) {
    return std::make_shared<const Mesh>(make_mesh(*shape));
  }
  const ObjFile& obj = std::get<ObjFile>(request.source);
  try {
    Mesh mesh =
        load_obj(obj.path, {.normalize = obj.normalize, .crease_degrees = obj.crease_degrees}).mesh;
    order_for_locality(mesh);
    return std::make_shared<const Mesh>(std::move(mesh));
  } catch (const ObjError& error) {
    throw SceneError(file, request.field, error.what());
  }
}

std::string format_box(const glm::dvec3& min, const glm::dvec3& max) {
  const auto point = [](const glm::dvec3& p) {
    return "[" + format_number(p.x) + ", " + format_number(p.y) + ", " + format_number(p.z) + "]";
  };
  return point(min) + " to " + point(max);
}

// A scene that loads is ready to draw: every object's texture volume must be valid (size,
// scale and translation can each be in bounds and still put it beyond the volume bound), and
// an explicit one must contain its object.
void check_volume(const SceneObject& object, std::size_t index, const std::string& file) {
  const std::string field = "objects[" + std::to_string(index) + "]";
  try {
    (void)texture_volume(object, object.material.volume.finest_level_log2.value_or(8));
  } catch (const SpecError& e) {
    const bool made_around_object =
        !object.material.volume.box &&
        (e.field().starts_with("volume.min") || e.field().starts_with("volume.max"));
    if (!made_around_object) throw SceneError::from_spec_error(file, field, e);
    // The scene has no volume to name: the object's extent is what broke the bound.
    const BoundingBox bounds = texture_space_bounds(object);
    const bool world = object.material.space == TextureSpace::world;
    throw SceneError(file, field,
                     "spans " + format_box(glm::dvec3(bounds.min), glm::dvec3(bounds.max)) +
                         " in " + (world ? "world" : "object") +
                         " space, so the texture volume made around it has " + e.field() + " = " +
                         e.value() + ", which " + e.bound() +
                         ": scale the object down, set its OBJ mesh's \"normalize\", or give "
                         "material.volume");
  }
  if (!explicit_volume_contains_object(object)) {
    const BoundingBox bounds = texture_space_bounds(object);
    const VolumeRequest::Box& box = *object.material.volume.box;
    const bool world = object.material.space == TextureSpace::world;
    throw SceneError(file, field + ".material.volume",
                     "does not contain object \"" + object.name + "\": in " +
                         (world ? "world" : "object") + " space the object spans " +
                         format_box(glm::dvec3(bounds.min), glm::dvec3(bounds.max)) +
                         ", the volume " + format_box(box.min, box.max) +
                         " (leave out min and max for a volume fitted to the object)");
  }
}

// Builds each distinct mesh once and gives it to its objects, refusing a scene whose distinct
// meshes pass the triangle bound as soon as they do, so at most one mesh past it is made.
void build_meshes(Scene& scene, const std::vector<MeshRequest>& meshes, const std::string& file) {
  std::map<std::string, std::shared_ptr<const Mesh>> built;
  std::size_t total_triangles = 0;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    std::shared_ptr<const Mesh>& mesh = built[meshes[i].cache_key];
    if (!mesh) {
      mesh = build_mesh(meshes[i], file);
      total_triangles += mesh->triangle_count();
      if (total_triangles > SceneLimits::kMaxTotalTriangles) {
        throw SceneError(file, "objects[" + std::to_string(i) + "].mesh",
                         "the scene's distinct meshes reach " + std::to_string(total_triangles) +
                             " triangles; at most " +
                             std::to_string(SceneLimits::kMaxTotalTriangles) + " in all");
      }
    }
    scene.objects[i].mesh = mesh;
  }
}

// Each distinct mesh simplified once, after all are built: a scene past the triangle bound
// costs no simplification.
void simplify_meshes(Scene& scene, const std::vector<MeshRequest>& meshes) {
  std::map<std::string, std::shared_ptr<const std::vector<MeshLevel>>> simplified;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    auto& levels = simplified[meshes[i].cache_key];
    if (!levels) {
      levels =
          std::make_shared<const std::vector<MeshLevel>>(simplified_levels(*scene.objects[i].mesh));
    }
    scene.objects[i].levels = levels;
  }
}

}  // namespace

Scene parse_scene(std::string_view json_text, const std::string& name_for_errors,
                  const std::filesystem::path& obj_directory) {
  const std::string& file = name_for_errors;
  const nlohmann::json document = parse_strict_json(json_text, file);
  JsonObject root(JsonValue(document, "", file));
  Scene scene;
  scene.name = name_for_errors;
  if (const auto description = root.find("description")) scene.description = description->string();
  if (const auto image = root.find("image")) scene.image = read_image(*image);
  if (const auto camera = root.find("camera")) read_camera(*camera, scene);
  if (const auto ambient = root.find("ambient")) scene.ambient = read_ambient(*ambient);
  if (const auto lights = root.find("lights")) {
    for (const JsonValue& light : lights->elements(SceneLimits::kMaxLights)) {
      scene.lights.push_back(read_light(light));
    }
  }

  const JsonValue objects = root.get("objects");
  const std::vector<JsonValue> object_values = objects.elements(SceneLimits::kMaxObjects);
  if (object_values.empty()) objects.fail("a scene needs at least one object");
  std::vector<MeshRequest> meshes;
  std::vector<std::optional<bool>> solid_given;
  std::map<std::string, std::size_t> object_by_name;
  for (const JsonValue& value : object_values) {
    const std::size_t index = scene.objects.size();
    JsonObject fields(value);
    SceneObject object;
    object.name = "object " + std::to_string(index);
    if (const auto name = fields.find("name")) {
      object.name = name->string();
      if (object.name.empty()) name->fail("must not be empty");
      if (const auto it = object_by_name.find(object.name); it != object_by_name.end()) {
        name->fail("\"" + object.name + "\" is already the name of objects[" +
                   std::to_string(it->second) + "]");
      }
    } else if (const auto it = object_by_name.find(object.name); it != object_by_name.end()) {
      // A clip plane naming it would cut only one of the two.
      value.fail("has no name, and its default \"" + object.name +
                 "\" is already the name of objects[" + std::to_string(it->second) +
                 "]: name one of them");
    }
    object_by_name.emplace(object.name, index);
    meshes.push_back(read_mesh(fields.get("mesh"), obj_directory));
    object.source = meshes.back().source;
    if (const auto transform = fields.find("transform")) {
      object.transform = read_transform(*transform);
    }
    object.material = read_material(fields.get("material"));
    object.double_sided = fields.boolean("double_sided", true);
    const auto solid = fields.find("solid");
    solid_given.push_back(solid ? std::optional(solid->boolean()) : std::nullopt);
    fields.reject_unknown_keys();
    scene.objects.push_back(std::move(object));
  }

  if (const auto planes = root.find("clip_planes")) {
    for (const JsonValue& plane : planes->elements(SceneLimits::kMaxClipPlanes)) {
      read_clip_plane(plane, scene, object_by_name);
    }
  }
  root.reject_unknown_keys();

  // Everything is checked before the first mesh is built: a typo costs no OBJ load.
  build_meshes(scene, meshes, file);
  for (std::size_t i = 0; i < scene.objects.size(); ++i) check_volume(scene.objects[i], i, file);
  decide_solids(scene, meshes, solid_given);
  simplify_meshes(scene, meshes);
  return scene;
}

Scene load_scene(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path)) {
    throw SceneError(path.string(), "",
                     std::string("cannot open: ") + (in ? "is a directory" : std::strerror(errno)));
  }
  const std::optional<std::string> text = read_at_most(in, kMaxTextFileBytes);
  if (!text) {
    throw SceneError(path.string(), "",
                     "holds more than " + std::to_string(kMaxTextFileBytes) +
                         " bytes, the most a scene file may");
  }
  if (in.bad())
    throw SceneError(path.string(), "", std::string("cannot read: ") + std::strerror(errno));
  return parse_scene(*text, path.string(), path.parent_path());
}

}  // namespace soltex
