#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "soltex/scene/scene.h"

// Scene files (JSON; the format is docs/SCENES.md). Every field is checked: unknown keys,
// wrong types, missing required fields and out-of-range numbers throw SceneError naming the
// file, the field path and the bound. Meshes are built or loaded while parsing, so a scene
// that loads is ready to draw.
namespace soltex {

// Reads a scene file; OBJ paths in it are relative to the file's folder.
Scene load_scene(const std::filesystem::path& path);

// Parses scene text; name_for_errors stands for the file in messages and relative OBJ paths
// are resolved against obj_directory.
Scene parse_scene(std::string_view json_text, const std::string& name_for_errors,
                  const std::filesystem::path& obj_directory = {});

// Bounds on the size of a scene.
struct SceneLimits {
  // An image side below 16 pixels shows nothing; above 8192 one frame's colour, depth and
  // coverage buffers pass 1 GiB.
  static constexpr int kMinImageSide = 16;
  static constexpr int kMaxImageSide = 8192;
  static constexpr int kMaxObjects = 1024;
  static constexpr int kMaxLights = 64;
  // What the rasterizer tests per vertex in one byte (RasterView::kMaxClipPlanes).
  static constexpr int kMaxClipPlanes = 8;
  static constexpr int kMaxOrbitFrames = 100000;
  // Camera, lights and clip planes; as wide as TransformLimits::kMaxTranslate (see there).
  static constexpr double kMaxCoordinate = 1e9;
  // All distinct meshes together: each shape is bounded, but a thousand of them need not be.
  static constexpr std::size_t kMaxTotalTriangles = 16u << 20;
};

}  // namespace soltex
