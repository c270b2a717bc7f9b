#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "soltex/scene/builtin_meshes.h"
#include "soltex/scene/camera.h"
#include "soltex/scene/clip_plane.h"
#include "soltex/scene/lights.h"
#include "soltex/scene/material.h"
#include "soltex/scene/mesh.h"
#include "soltex/scene/mesh_lod.h"
#include "soltex/scene/obj_loader.h"
#include "soltex/scene/transform.h"

namespace soltex {

// An OBJ file a mesh came from (the path as resolved against the scene file's folder).
struct ObjFile {
  std::filesystem::path path;
  bool normalize = true;
  double crease_degrees = kDefaultCreaseDegrees;  // ObjLoadOptions::crease_degrees
};

using MeshSource = std::variant<BuiltinShape, ObjFile>;

struct SceneObject {
  std::string name;
  MeshSource source;
  std::shared_ptr<const Mesh> mesh;  // shared by objects that name the same source
  // The mesh simplified, finest first (mesh_lod.h): empty for meshes too small to need it. Null
  // where the object was not loaded from a scene file.
  std::shared_ptr<const std::vector<MeshLevel>> levels;
  Transform transform;
  Material material;
  std::vector<ClipPlane> clip_planes;  // the scene's planes that cut this object
  // false: only the faces turned towards the camera are drawn (back faces cost nothing). For a
  // closed mesh seen from outside the picture is the same; an open one shows nothing through
  // its holes. Objects cut by a clip plane draw both faces regardless (caps need them).
  bool double_sided = true;
  // The mesh bounds a solid, so a clip plane shows its inside as a cap where the view passes
  // through its back faces; a sheet's back faces show as its other side. The scene's "solid",
  // or for a cut object what its mesh's openings say (mesh_openings.h); unset for an uncut
  // object the scene says nothing of, which draws no caps.
  std::optional<bool> solid;
};

struct ImageSize {
  int width = 1280;
  int height = 720;
};

struct Scene {
  std::string name;  // the file it came from, for messages
  std::string description;
  ImageSize image;
  Camera camera;
  std::optional<CameraOrbit> orbit;
  AmbientLight ambient;
  std::vector<Light> lights;
  std::vector<SceneObject> objects;
};

}  // namespace soltex
