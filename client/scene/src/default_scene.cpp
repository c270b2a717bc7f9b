#include "soltex/scene/default_scene.h"

#include "soltex/scene/scene_loader.h"

namespace soltex {

const char* default_scene_json() {
  return R"json({
  "description": "Lecture textures side by side: marble (cut open), wood, a 3D checker, turbulence",
  "image": {"width": 1280, "height": 720},
  "camera": {"position": [0, 2.4, 7.2], "target": [0, -0.1, 0], "up": [0, 1, 0],
             "fov_y_degrees": 40, "near": 0.1, "far": 100},
  "ambient": {"colour": [1, 1, 1], "intensity": 0.2},
  "lights": [
    {"directional": {"direction": [-0.5, -1.0, -0.7], "colour": [1, 0.97, 0.92], "intensity": 0.9}}
  ],
  "objects": [
    {"name": "marble sphere",
     "mesh": {"sphere": {"radius": 1, "segments": 96, "rings": 48}},
     "transform": {"translate": [-2.4, 0, 0]},
     "material": {"texture": {"marble": {"frequency": 1.5, "amplitude": 4,
                                         "turbulence": {"scale": 2, "octave_max": 6}}},
                  "specular": 0.5, "shininess": 48}},
    {"name": "wood torus", "double_sided": false,
     "mesh": {"torus": {"major_radius": 0.75, "minor_radius": 0.3}},
     "transform": {"rotate": [60, 0, 0]},
     "material": {"texture": {"wood": {}}, "specular": 0.25, "shininess": 24}},
    {"name": "checker box", "double_sided": false,
     "mesh": {"box": {"size": 1.6}},
     "transform": {"translate": [2.4, 0, 0], "rotate": [25, 35, 0]},
     "material": {"texture": {"checker": {"size": [0.4, 0.4, 0.4], "offset": 0.5,
                                          "three_d": true}},
                  "specular": 0.1}},
    {"name": "turbulence floor",
     "mesh": {"plane": {"size": [12, 8], "subdivisions": 8}},
     "transform": {"translate": [0, -1.25, 0]},
     "material": {"texture": {"turbulence": {"fractal": {"scale": 1, "octave_max": 6}},
                              "ramp": {"keys": [
                                {"position": 0.0, "colour": [0.16, 0.18, 0.22]},
                                {"position": 0.5, "colour": [0.45, 0.47, 0.5]},
                                {"position": 1.0, "colour": [0.85, 0.84, 0.8]}]}},
                  "space": "world", "specular": 0}}
  ],
  "clip_planes": [
    {"point": [-2.4, 0, 0.3], "normal": [0.5, 0.4, 1], "objects": ["marble sphere"]}
  ]
})json";
}

Scene default_scene() {
  return parse_scene(default_scene_json(), "<default scene>");
}

}  // namespace soltex
