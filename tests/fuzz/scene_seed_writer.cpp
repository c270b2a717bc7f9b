// Writes the starting corpus of scene_parser_fuzz: scene files that use every mesh kind, both
// light kinds, clip planes, orbits, explicit volumes and all eight texture patterns, and OBJ
// files (triangles, quads, a non-convex polygon, relative indices, groups). The OBJ files also
// go into a second folder, where relative OBJ paths in fuzzed scenes resolve.
//
//   scene_seed_writer <corpus-dir> <obj-dir>
//
// Plain text, no scene library: it builds wherever the fuzz target does.

#include <cstdio>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "seed_file.h"

namespace {

struct NamedText {
  const char* name;
  const char* text;
};

constexpr NamedText kObjFiles[] = {
    {"tetrahedron.obj", R"(# a closed tetrahedron
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
f 1 3 2
f 1 2 4
f 1 4 3
f 2 3 4
)"},
    {"quad-cube.obj", R"(o cube
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
vn 0 0 -1
vt 0 0
g sides
f 1/1/1 4/1/1 3/1/1 2/1/1
f 5 6 7 8
f 1 2 6 5
g caps
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
)"},
    {"non-convex.obj", R"(# an L-shaped hexagon and a seam of duplicate vertices
v 0 0 0
v 2 0 0
v 2 1 0
v 1 1 0
v 1 2 0
v 0 2 0
v 0 0 0
f 1 2 3 4 5 6
f 7 2 3
)"},
    {"relative.obj", R"(v 0 0 0
v 1 0 0
v 1 1 0
f -3 -2 -1
v 0 1 0
f 1 -2 -1
f 1 1 2
)"},
};

constexpr NamedText kScenes[] = {
    {"minimal.json",
     R"({"objects": [{"mesh": "sphere", "material": {"texture": {"marble": {}}}}]})"},
    {"graph.json", R"({"objects": [{"mesh": "sphere", "material": {"texture": {"graph": {
       "nodes": [
         {"name": "p", "category": "position"},
         {"name": "p4", "category": "multiply", "inputs": {"in1": {"node": "p"}, "in2": 4}},
         {"name": "f", "category": "turbulence", "inputs": {"position": {"node": "p4"},
          "octaves": 5, "basis": "value"}},
         {"name": "c", "category": "ramp", "inputs": {"in": {"node": "f"}, "keys": [
           {"position": 0, "colour": [0, 0, 0]}, {"position": 1, "colour": [1, 0.9, 0.8]}]}}],
       "outputs": {"colour": "c"}}}}}]})"},
    {"builtins.json", R"({
  "description": "every built-in mesh, both lights, an orbit and a clip plane",
  "image": {"width": 640, "height": 480},
  "camera": {"position": [0, 2.4, 7.2], "target": [0, -0.1, 0], "up": [0, 1, 0],
             "fov_y_degrees": 40, "near": 0.1, "far": 100,
             "orbit": {"degrees_per_frame": 2, "frames": 180}},
  "ambient": {"colour": [1, 1, 1], "intensity": 0.2},
  "lights": [
    {"directional": {"direction": [-0.5, -1.0, -0.7], "colour": [1, 0.97, 0.92], "intensity": 0.9}},
    {"point": {"position": [2, 1.5, 2.5], "colour": {"r": 0.8, "g": 0.85, "b": 1}, "intensity": 3}}
  ],
  "objects": [
    {"name": "sphere", "mesh": {"sphere": {"radius": 1, "segments": 12, "rings": 6}},
     "transform": {"translate": [-2.4, 0, 0], "scale": 0.5},
     "material": {"texture": {"marble": {"frequency": 1.5, "amplitude": 4, "ripple": "product",
                                         "axis": "z",
                                         "turbulence": {"scale": 2, "octave_min": 1,
                                                        "octave_max": 6, "basis": "gradient",
                                                        "signed_octaves": true}}},
                  "specular": 0.5, "shininess": 48}},
    {"name": "torus", "mesh": {"torus": {"major_radius": 0.75, "minor_radius": 0.3,
                                         "major_segments": 16, "minor_segments": 8}},
     "transform": {"rotate": [60, 0, 0], "scale": [1, 2, 0.5]},
     "material": {"texture": {"wood": {"ring_spacing": 0.15, "tilt_y": 0.3, "tilt_z": 0.15,
                                       "twist": 0.5, "jitter": 0.6, "jitter_scale": 4,
                                       "grain_fraction": 0.2}},
                  "space": "world", "unlit": true}},
    {"name": "box", "mesh": {"box": {"size": [1.6, 0.2, 1], "subdivisions": 3}}, "solid": true,
     "transform": {"translate": {"x": 2.4, "y": 0, "z": 0}, "rotate": [25, 35, 0]},
     "material": {"texture": {"checker": {"size": [0.4, 0.4, 0.4], "offset": 0.5,
                                          "three_d": true},
                              "channels": ["colour", "opacity"],
                              "opacity": {"low": 0.2, "high": 0.9}},
                  "specular": 0.1}},
    {"name": "floor", "mesh": {"plane": {"size": [12, 8], "subdivisions": 4}},
     "transform": {"translate": [0, -1.25, 0]},
     "material": {"texture": {"turbulence": {"fractal": {"scale": 1, "octave_max": 6}},
                              "ramp": {"keys": [
                                {"position": 0.0, "colour": [0.16, 0.18, 0.22]},
                                {"position": 0.5, "colour": [0.45, 0.47, 0.5]},
                                {"position": 1.0, "colour": [0.85, 0.84, 0.8]}]}},
                  "space": "world", "specular": 0,
                  "volume": {"min": [-6, -2, -4], "max": [6, 2, 4], "finest_level_log2": 9}}}
  ],
  "clip_planes": [
    {"point": [-2.4, 0, 0.3], "normal": [0.5, 0.4, 1], "objects": ["sphere", "box"]},
    {"offset": 0.5, "normal": {"x": 0, "y": 1, "z": 0}}
  ]
})"},
    {"patterns.json", R"({
  "camera": {"position": [0, 0, 5], "target": [0, 0, 0],
             "orbit": {"degrees_per_second": -30, "frames": 10}},
  "objects": [
    {"mesh": "box", "material": {"texture": {"stripes": {"width": 0.25, "offset": 0.5,
                                                         "axis": "y"}}}},
    {"mesh": "plane", "material": {"texture": {"colour_cube": {"period": 2}}}},
    {"mesh": "torus", "material": {"texture": {"rings": {"thickness": 0.1, "base": 0.2,
                                                         "amplitude": 0.6},
                                               "channels": ["specular"],
                                               "specular": {"low": 0.1, "high": 0.7}}}},
    {"mesh": {"sphere": {}}, "material": {"texture": {"noise": {"scale": 8,
                                                                "basis": "gradient"}}}},
    {"mesh": "sphere", "material": {"texture": {"noise": {}}, "volume": {"finest_level_log2": 4}}}
  ]
})"},
    {"obj-meshes.json", R"({
  "objects": [
    {"name": "cube", "mesh": {"obj": {"path": "quad-cube.obj"}},
     "material": {"texture": {"wood": {}}}},
    {"name": "tetra", "mesh": {"obj": {"path": "tetrahedron.obj", "normalize": false}},
     "transform": {"scale": 3},
     "material": {"texture": {"checker": {}}, "space": "world"}},
    {"name": "l-shape", "mesh": {"obj": {"path": "non-convex.obj"}},
     "material": {"texture": {"stripes": {}}}},
    {"name": "relative", "mesh": {"obj": {"path": "relative.obj"}},
     "material": {"texture": {"turbulence": {"fractal": {}}}}}
  ]
})"},
};

}  // namespace

int main(int argc, char** argv) {
  return soltex::fuzz::seed_writer_main(
      argc, argv, {"corpus-dir", "obj-dir"}, [](const auto& dirs) {
        const std::filesystem::path& corpus = dirs[0];
        const std::filesystem::path& obj_dir = dirs[1];
        int written = 0;
        for (const NamedText& obj : kObjFiles) {
          soltex::fuzz::write_seed_file(obj_dir / obj.name, obj.text);
          soltex::fuzz::write_seed_file(corpus / (std::string("seed-") + obj.name), obj.text);
          ++written;
        }
        for (const NamedText& scene : kScenes) {
          soltex::fuzz::write_seed_file(corpus / (std::string("seed-") + scene.name), scene.text);
          ++written;
        }
        std::printf("wrote %d seeds to %s and %zu OBJ files to %s\n", written, corpus.c_str(),
                    std::size(kObjFiles), obj_dir.c_str());
      });
}
