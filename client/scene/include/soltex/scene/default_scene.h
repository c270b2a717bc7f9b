#pragma once

#include "soltex/scene/scene.h"

namespace soltex {

// A scene that needs no files: a marble sphere cut open by a clip plane, a wood torus, a
// 3D-checker box and a turbulence floor under one directional light and ambient light,
// 1280x720. It is parsed from the JSON text default_scene_json(), so it is also a worked
// example of the format.
Scene default_scene();
const char* default_scene_json();

}  // namespace soltex
