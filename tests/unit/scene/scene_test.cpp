#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/geometric.hpp>
#include <limits>
#include <nlohmann/json.hpp>

#include "soltex/scene/default_scene.h"
#include "soltex/scene/scene_error.h"
#include "soltex/scene/scene_loader.h"
#include "soltex/scene/texture_spec_json.h"
#include "soltex/scene/texture_volume.h"

namespace soltex {
namespace {

using nlohmann::json;
using ::testing::AllOf;
using ::testing::HasSubstr;

// A valid one-object scene; tests edit a copy of it.
json minimal_scene() {
  return json::parse(R"({
    "objects": [{"mesh": "sphere", "material": {"texture": {"marble": {}}}}]
  })");
}

SceneError scene_error_of(const std::string& text, const std::string& file = "test.json") {
  try {
    (void)parse_scene(text, file);
  } catch (const SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "expected a SceneError for " << text;
  return SceneError("", "", "");
}

SceneError scene_error_of_json(const json& scene) {
  return scene_error_of(scene.dump());
}

template <class T>
bool holds(const Pattern& pattern) {
  return std::holds_alternative<T>(pattern);
}

TEST(DefaultScene, IsValidAndShowsSeveralLectureTextures) {
  const Scene scene = default_scene();
  EXPECT_EQ(scene.image.width, 1280);
  EXPECT_EQ(scene.image.height, 720);
  ASSERT_EQ(scene.lights.size(), 1u);
  EXPECT_TRUE(std::holds_alternative<DirectionalLight>(scene.lights[0]));
  EXPECT_GT(scene.ambient.intensity, 0.0f);
  ASSERT_GE(scene.objects.size(), 4u);

  int marble = 0, wood = 0, checker_3d = 0, turbulence = 0, cut = 0;
  for (const SceneObject& object : scene.objects) {
    ASSERT_NE(object.mesh, nullptr) << object.name;
    EXPECT_GT(object.mesh->triangle_count(), 0u);
    EXPECT_TRUE(std::holds_alternative<BuiltinShape>(object.source)) << "needs no files";
    const Pattern& p = object.material.texture.pattern;
    marble += holds<MarbleParams>(p);
    wood += holds<WoodParams>(p);
    checker_3d += holds<CheckerParams>(p) && std::get<CheckerParams>(p).three_d;
    turbulence += holds<TurbulenceParams>(p);
    cut += !object.clip_planes.empty();
    const Volume volume = texture_volume(object, 9);
    EXPECT_EQ(volume.finest_level_log2, 9);
  }
  EXPECT_EQ(marble, 1);
  EXPECT_EQ(wood, 1);
  EXPECT_EQ(checker_3d, 1);
  EXPECT_EQ(turbulence, 1);
  EXPECT_EQ(cut, 1) << "one object is cut open";
}

TEST(DefaultScene, ClipPlaneCutsThroughTheMarbleSphere) {
  const Scene scene = default_scene();
  for (const SceneObject& object : scene.objects) {
    if (object.clip_planes.empty()) continue;
    const ClipPlane& plane = object.clip_planes[0];
    EXPECT_NEAR(glm::length(plane.normal), 1.0, 1e-12);
    const glm::dvec3 centre = object.transform.translate;
    // The plane passes inside the object: part of it is kept, part cut away.
    EXPECT_TRUE(plane.keeps(centre));
    EXPECT_FALSE(plane.keeps(centre + plane.normal));
  }
}

TEST(ParseScene, MinimalSceneTakesTheDefaults) {
  const Scene scene = parse_scene(minimal_scene().dump(), "minimal.json");
  EXPECT_EQ(scene.name, "minimal.json");
  EXPECT_EQ(scene.image.width, 1280);
  EXPECT_EQ(scene.camera.position, glm::dvec3(0, 0, 5));
  EXPECT_DOUBLE_EQ(scene.camera.fov_y_degrees, 45.0);
  EXPECT_FALSE(scene.orbit.has_value());
  EXPECT_TRUE(scene.lights.empty());
  ASSERT_EQ(scene.objects.size(), 1u);
  const SceneObject& object = scene.objects[0];
  EXPECT_EQ(object.name, "object 0");
  EXPECT_EQ(object.transform.scale, glm::dvec3(1.0));
  EXPECT_EQ(object.material.space, TextureSpace::object);
  EXPECT_FALSE(object.material.volume.box.has_value());
  EXPECT_FALSE(object.material.volume.finest_level_log2.has_value());
  EXPECT_FALSE(object.material.unlit);
  const MarbleParams& marble = std::get<MarbleParams>(object.material.texture.pattern);
  EXPECT_EQ(marble.frequency, 2.0);
  EXPECT_EQ(marble.turbulence.octave_max, 5);
  EXPECT_FALSE(object.material.texture.ramp.keys.empty()) << "validated() filled the ramp";
  EXPECT_EQ(object.mesh->triangle_count(), make_sphere({}).triangle_count());
}

// Any non-zero direction is one, however short: it is scaled by its largest component before
// its length is taken, which would otherwise underflow.
TEST(ParseScene, TinyDirectionsAreDirections) {
  for (const double scale : {1e-13, 1e-200, 5e-324}) {
    json s = minimal_scene();
    s["lights"] = {{{"directional", {{"direction", {0, -scale, 0}}}}}};
    s["camera"] = {{"up", {scale, scale, 0}}};
    const Scene scene = parse_scene(s.dump(), "tiny.json");
    EXPECT_EQ(std::get<DirectionalLight>(scene.lights[0]).direction, glm::dvec3(0, -1, 0));
    EXPECT_NEAR(scene.camera.up.x, std::sqrt(0.5), 1e-15) << scale;
    EXPECT_NEAR(scene.camera.up.y, std::sqrt(0.5), 1e-15) << scale;
  }
}

TEST(ParseScene, ReadsEveryField) {
  const Scene scene = parse_scene(R"({
    "description": "all fields",
    "image": {"width": 640, "height": 480},
    "camera": {"position": [1, 2, 3], "target": {"x": 0, "y": 1, "z": 0}, "up": [0, 2, 0],
               "fov_y_degrees": 60, "near": 0.5, "far": 50,
               "orbit": {"degrees_per_second": 30, "frames": 90}},
    "ambient": {"colour": {"r": 0.5, "g": 0.6, "b": 0.7}, "intensity": 0.3},
    "lights": [{"directional": {"direction": [0, -2, 0], "colour": [1, 0.5, 0.25],
                                "intensity": 2}},
               {"point": {"position": [4, 5, 6], "intensity": 10}}],
    "objects": [
      {"name": "a", "mesh": {"torus": {"major_radius": 2, "minor_radius": 0.5,
                                       "major_segments": 8, "minor_segments": 6}},
       "transform": {"translate": [1, 0, 0], "rotate": [90, 0, 0], "scale": [1, 2, 3]},
       "solid": false,
       "material": {"texture": {"wood": {"ring_spacing": 0.2}, "channels": ["colour", "specular"],
                                "specular": {"low": 0.1, "high": 0.9}},
                    "space": "world",
                    "volume": {"min": [-10, -10, -10], "max": [10, 10, 10], "finest_level_log2": 7},
                    "specular": 0.6, "shininess": 64, "unlit": true}},
      {"name": "b", "mesh": {"box": {"size": [1, 2, 3], "subdivisions": 2}}, "transform": {"scale": 2},
       "double_sided": false,
       "material": {"texture": {"stripes": {"axis": "z"}}, "volume": {"finest_level_log2": 5}}},
      {"name": "c", "mesh": {"plane": {"size": 3}},
       "material": {"texture": {"noise": {"basis": "gradient"}}}}
    ],
    "clip_planes": [{"normal": [0, 0, 2], "offset": 0.5},
                    {"point": [1, 1, 1], "normal": [1, 0, 0], "objects": ["b"]}]
  })",
                                  "full.json");
  EXPECT_EQ(scene.description, "all fields");
  EXPECT_EQ(scene.image.width, 640);
  EXPECT_EQ(scene.image.height, 480);
  EXPECT_EQ(scene.camera.target, glm::dvec3(0, 1, 0));
  EXPECT_EQ(scene.camera.up, glm::dvec3(0, 1, 0)) << "normalised";
  EXPECT_EQ(scene.camera.far, 50.0);
  ASSERT_TRUE(scene.orbit.has_value());
  EXPECT_EQ(scene.orbit->rate, CameraOrbit::Rate::per_second);
  EXPECT_EQ(scene.orbit->degrees, 30.0);
  EXPECT_EQ(scene.orbit->frames, 90);
  EXPECT_EQ(scene.ambient.colour, glm::vec3(0.5f, 0.6f, 0.7f));
  ASSERT_EQ(scene.lights.size(), 2u);
  EXPECT_EQ(std::get<DirectionalLight>(scene.lights[0]).direction, glm::dvec3(0, -1, 0));
  EXPECT_EQ(std::get<DirectionalLight>(scene.lights[0]).intensity, 2.0f);
  EXPECT_EQ(std::get<PointLight>(scene.lights[1]).position, glm::dvec3(4, 5, 6));
  EXPECT_EQ(std::get<PointLight>(scene.lights[1]).colour, glm::vec3(1.0f));

  ASSERT_EQ(scene.objects.size(), 3u);
  const SceneObject& a = scene.objects[0];
  EXPECT_EQ(a.name, "a");
  EXPECT_EQ(std::get<TorusShape>(std::get<BuiltinShape>(a.source)).major_segments, 8);
  EXPECT_EQ(a.mesh->triangle_count(), 2u * 8u * 6u);
  EXPECT_EQ(a.transform.rotate_degrees, glm::dvec3(90, 0, 0));
  EXPECT_EQ(a.transform.scale, glm::dvec3(1, 2, 3));
  EXPECT_TRUE(a.double_sided) << "the default";
  EXPECT_FALSE(scene.objects[1].double_sided);
  EXPECT_EQ(a.material.space, TextureSpace::world);
  EXPECT_TRUE(a.material.texture.channels.specular);
  EXPECT_FLOAT_EQ(a.material.texture.specular.high, 0.9f);
  EXPECT_EQ(std::get<WoodParams>(a.material.texture.pattern).ring_spacing, 0.2);
  ASSERT_TRUE(a.material.volume.box.has_value());
  EXPECT_EQ(a.material.volume.box->max, glm::dvec3(10.0));
  EXPECT_EQ(a.material.volume.finest_level_log2, 7);
  EXPECT_FLOAT_EQ(a.material.specular, 0.6f);
  EXPECT_FLOAT_EQ(a.material.shininess, 64.0f);
  EXPECT_TRUE(a.material.unlit);
  const Volume explicit_volume = texture_volume(a, 10);
  EXPECT_EQ(explicit_volume.min, glm::dvec3(-10.0));
  EXPECT_EQ(explicit_volume.finest_level_log2, 7) << "the scene's level wins";

  const SceneObject& b = scene.objects[1];
  EXPECT_EQ(b.transform.scale, glm::dvec3(2.0));
  EXPECT_EQ(b.mesh->bounds.max, glm::vec3(0.5f, 1.0f, 1.5f));
  EXPECT_EQ(std::get<StripesParams>(b.material.texture.pattern).axis, Axis::z);
  EXPECT_EQ(texture_volume(b, 10).finest_level_log2, 5);

  // The first plane cuts every object, the second only "b".
  EXPECT_EQ(a.clip_planes.size(), 1u);
  ASSERT_EQ(b.clip_planes.size(), 2u);
  EXPECT_EQ(scene.objects[2].clip_planes.size(), 1u);
  EXPECT_EQ(a.clip_planes[0].normal, glm::dvec3(0, 0, 1));
  EXPECT_EQ(a.clip_planes[0].offset, 0.5);
  EXPECT_EQ(b.clip_planes[1].offset, 1.0) << "offset = dot(normal, point)";
  EXPECT_EQ(std::get<PlaneShape>(std::get<BuiltinShape>(scene.objects[2].source)).size,
            glm::dvec2(3.0));
  // Caps need a solid: as the scene says for the torus, as the meshes' openings say for the
  // closed box and the plane, a sheet.
  EXPECT_EQ(a.solid, false);
  EXPECT_EQ(b.solid, true);
  EXPECT_EQ(scene.objects[2].solid, false);
}

// One bad scene per row: the error must name the file, the field path and the problem.
struct BadScene {
  const char* name;
  std::function<void(json&)> edit;
  std::string field;
  std::string problem;
};

class SceneErrors : public ::testing::TestWithParam<BadScene> {};

TEST_P(SceneErrors, NameFileFieldAndProblem) {
  json scene = minimal_scene();
  GetParam().edit(scene);
  const SceneError e = scene_error_of_json(scene);
  EXPECT_EQ(e.file(), "test.json");
  EXPECT_EQ(e.field(), GetParam().field);
  EXPECT_THAT(e.problem(), HasSubstr(GetParam().problem));
  EXPECT_THAT(e.what(), AllOf(HasSubstr("test.json: "), HasSubstr(GetParam().field),
                              HasSubstr(GetParam().problem)));
}

json& first_object(json& scene) {
  return scene["objects"][0];
}
json& texture(json& scene) {
  return first_object(scene)["material"]["texture"];
}

INSTANTIATE_TEST_SUITE_P(
    Cases, SceneErrors,
    ::testing::Values(
        BadScene{"TypeMismatch",
                 [](json& s) {
                   first_object(s)["transform"] = {{"translate", "1, 2, 3"}};
                 },
                 "objects[0].transform.translate", "expected [x, y, z]"},
        BadScene{"WrongVectorLength",
                 [](json& s) {
                   first_object(s)["transform"] = {{"rotate", {1, 2}}};
                 },
                 "objects[0].transform.rotate", "expected 3 numbers"},
        BadScene{"DoubleSidedNotABoolean", [](json& s) { first_object(s)["double_sided"] = "no"; },
                 "objects[0].double_sided", "expected true or false, found a string"},
        BadScene{
            "ObjPathWithANul",
            [](json& s) {
              first_object(s)["mesh"] = {{"obj", {{"path", std::string("quads.obj\0.txt", 14)}}}};
            },
            "objects[0].mesh.obj.path", "must not hold a NUL character"},
        BadScene{"ClipPlaneNamingNoObject",
                 [](json& s) {
                   s["clip_planes"] = {{{"normal", {0, 1, 0}}, {"objects", json::array()}}};
                 },
                 "clip_planes[0].objects", "names no object"},
        BadScene{"SolidNotABoolean", [](json& s) { first_object(s)["solid"] = 1; },
                 "objects[0].solid", "expected true or false, found a number"},
        BadScene{"MissingMaterial", [](json& s) { first_object(s).erase("material"); },
                 "objects[0].material", "missing required field"},
        BadScene{"MissingObjects", [](json& s) { s.erase("objects"); }, "objects",
                 "missing required field"},
        BadScene{"NoObjects", [](json& s) { s["objects"] = json::array(); }, "objects",
                 "at least one object"},
        BadScene{"UnknownPattern",
                 [](json& s) {
                   texture(s) = {{"marbel", json::object()}};
                 },
                 "objects[0].material.texture.marbel",
                 "unknown field: expected one of stripes, checker, colour_cube"},
        BadScene{"TwoPatterns", [](json& s) { texture(s)["wood"] = json::object(); },
                 "objects[0].material.texture", "only one of"},
        BadScene{"UnknownTransformField",
                 [](json& s) {
                   first_object(s)["transform"] = {{"rotation", {0, 0, 0}}};
                 },
                 "objects[0].transform.rotation",
                 "unknown field: expected one of translate, rotate, scale"},
        BadScene{"UnknownPatternField",
                 [](json& s) {
                   texture(s)["marble"]["turbulence"] = {{"octaves", 3}};
                 },
                 "objects[0].material.texture.marble.turbulence.octaves", "unknown field"},
        BadScene{"UnknownTopLevelField", [](json& s) { s["light"] = json::array(); }, "light",
                 "unknown field"},
        BadScene{"UnknownEnumValue", [](json& s) { texture(s)["marble"]["axis"] = "w"; },
                 "objects[0].material.texture.marble.axis",
                 "unknown value \"w\": expected one of x, y, z"},
        BadScene{"UnknownBuiltinMesh", [](json& s) { first_object(s)["mesh"] = "cube"; },
                 "objects[0].mesh", "expected one of sphere, torus, box, plane"},
        BadScene{"ScaleOutOfRange",
                 [](json& s) {
                   first_object(s)["transform"] = {{"scale", 0}};
                 },
                 "objects[0].transform.scale", "0 is out of range: must be in [1e-06, 1e+06]"},
        BadScene{"RotateOutOfRange",
                 [](json& s) {
                   first_object(s)["transform"] = {{"rotate", {0, 400, 0}}};
                 },
                 "objects[0].transform.rotate[1]", "400 is out of range: must be in [-360, 360]"},
        BadScene{"TranslateOutOfRange",
                 [](json& s) {
                   first_object(s)["transform"] = {{"translate", {0, 0, 2e9}}};
                 },
                 "objects[0].transform.translate[2]", "must be in [-1e+09, 1e+09]"},
        BadScene{"CameraBeyondTheCoordinateBound",
                 [](json& s) {
                   s["camera"] = {{"position", {0, -1.5e9, 0}}};
                 },
                 "camera.position[1]", "must be in [-1e+09, 1e+09]"},
        BadScene{"NotAnInteger",
                 [](json& s) {
                   first_object(s)["mesh"] = {{"sphere", {{"segments", 3.5}}}};
                 },
                 "objects[0].mesh.sphere.segments", "3.5 is not an integer"},
        BadScene{"CreaseAngleOverAHalfTurn",
                 [](json& s) {
                   first_object(s)["mesh"] = {{"obj", {{"path", "a.obj"}, {"crease_angle", 181}}}};
                 },
                 "objects[0].mesh.obj.crease_angle", "181 is out of range: must be in [0, 180]"},
        BadScene{"TorusTubeTooThick",
                 [](json& s) {
                   first_object(s)["mesh"] = {{"torus", {{"minor_radius", 1}}}};
                 },
                 "objects[0].mesh.torus.minor_radius", "must be less than major_radius = 0.75"},
        BadScene{"SpecBound",
                 [](json& s) {
                   texture(s)["marble"]["turbulence"] = {{"octave_max", 40}};
                 },
                 "objects[0].material.texture.marble.turbulence.octave_max", "[0, 24]"},
        BadScene{"SpecBoundPastAnInt",
                 [](json& s) {
                   texture(s)["marble"]["turbulence"] = {{"octave_max", 4294967301.0}};
                 },
                 "objects[0].material.texture.marble.turbulence.octave_max",
                 "4294967301 is out of range: must be in [0, 24]"},
        BadScene{"RampBound",
                 [](json& s) {
                   texture(s)["ramp"] = {{"keys",
                                          {{{"position", 0.5}, {"colour", {1, 1, 1}}},
                                           {{"position", 0.2}, {"colour", {0, 0, 0}}}}}};
                 },
                 "objects[0].material.texture.ramp.keys[1].position", "must be finite and in"},
        BadScene{"ColourOutOfRange",
                 [](json& s) {
                   s["ambient"] = {{"colour", {1, 2, 1}}};
                 },
                 "ambient.colour[1]", "2 is out of range: must be in [0, 1]"},
        BadScene{"ChannelTwice",
                 [](json& s) {
                   texture(s)["channels"] = {"colour", "colour"};
                 },
                 "objects[0].material.texture.channels[1]", "listed twice"},
        BadScene{
            "VolumeInsideOut",
            [](json& s) {
              first_object(s)["material"]["volume"] = {{"min", {0, 0, 0}}, {"max", {-1, 1, 1}}};
            },
            "objects[0].material.volume.max.x", "must be greater than volume.min.x"},
        BadScene{"VolumeHalfGiven",
                 [](json& s) {
                   first_object(s)["material"]["volume"] = {{"min", {0, 0, 0}}};
                 },
                 "objects[0].material.volume", "both min and max"},
        BadScene{"LevelOutOfRange",
                 [](json& s) {
                   first_object(s)["material"]["volume"] = {{"finest_level_log2", 15}};
                 },
                 "objects[0].material.volume.finest_level_log2", "must be in [3, 14]"},
        BadScene{"FarBeforeNear",
                 [](json& s) {
                   s["camera"] = {{"near", 5}, {"far", 1}};
                 },
                 "camera.far", "must be greater than near = 5"},
        BadScene{"UpAlongView",
                 [](json& s) {
                   s["camera"] = {{"position", {0, 5, 0}}, {"up", {0, 1, 0}}};
                 },
                 "camera.up", "must not be parallel to the view direction"},
        BadScene{"ZeroLightDirection",
                 [](json& s) {
                   s["lights"] = {{{"directional", {{"direction", {0, 0, 0}}}}}};
                 },
                 "lights[0].directional.direction", "zero vector"},
        BadScene{"TargetAtThePosition",
                 [](json& s) {
                   s["camera"] = {{"position", {1, 2, 3}}, {"target", {1, 2, 3 + 1e-10}}};
                 },
                 "camera", "must be at least 1e-09 apart"},
        BadScene{"ImageTooLarge",
                 [](json& s) {
                   s["image"] = {{"width", 100000}};
                 },
                 "image.width", "must be in [16, 8192]"},
        BadScene{"ImageLargerThanTheBound",
                 [](json& s) {
                   s["image"] = {{"width", 1024}, {"height", 16384}};
                 },
                 "image.height", "16384 is out of range: must be in [16, 8192]"},
        BadScene{"ImageSmallerThanTheBound",
                 [](json& s) {
                   s["image"] = {{"width", 1}, {"height", 1}};
                 },
                 "image.width", "1 is out of range: must be in [16, 8192]"},
        BadScene{"VolumeBesideItsObject",
                 [](json& s) {
                   first_object(s)["name"] = "ball";
                   first_object(s)["material"]["volume"] = {{"min", {5, 5, 5}}, {"max", {6, 6, 6}}};
                 },
                 "objects[0].material.volume",
                 "does not contain object \"ball\": in object space the object spans"},
        BadScene{
            "VolumeCuttingItsObject",
            [](json& s) {
              first_object(s)["material"]["volume"] = {{"min", {-1, -1, -1}}, {"max", {1, 1, 0.5}}};
            },
            "objects[0].material.volume", "does not contain object \"object 0\""},
        BadScene{"OrbitWithoutRate",
                 [](json& s) {
                   s["camera"] = {{"orbit", {{"frames", 10}}}};
                 },
                 "camera.orbit", "expected one of degrees_per_frame, degrees_per_second"},
        BadScene{"ClipPlaneUnknownObject",
                 [](json& s) {
                   s["clip_planes"] = {{{"normal", {1, 0, 0}}, {"objects", {"nobody"}}}};
                 },
                 "clip_planes[0].objects[0]", "no object is named \"nobody\""},
        BadScene{"ClipPlaneObjectTwice",
                 [](json& s) {
                   first_object(s)["name"] = "a";
                   s["objects"].push_back(first_object(s));
                   s["objects"][1]["name"] = "b";
                   s["clip_planes"] = {{{"normal", {1, 0, 0}}, {"objects", {"a", "a"}}}};
                 },
                 "clip_planes[0].objects[1]", "\"a\" is listed twice"},
        BadScene{"DuplicateObjectName",
                 [](json& s) {
                   first_object(s)["name"] = "twin";
                   s["objects"].push_back(first_object(s));
                 },
                 "objects[1].name", "\"twin\" is already the name of objects[0]"},
        BadScene{"DefaultNameTaken",
                 [](json& s) {
                   first_object(s)["name"] = "object 1";
                   s["objects"].push_back(first_object(s));
                   s["objects"][1].erase("name");
                 },
                 "objects[1]", "its default \"object 1\" is already the name of objects[0]"},
        BadScene{"TooManyClipPlanes",
                 [](json& s) {
                   s["clip_planes"] = json::array();
                   for (int i = 0; i < 9; ++i) s["clip_planes"].push_back({{"normal", {1, 0, 0}}});
                 },
                 "clip_planes", "at most 8"},
        BadScene{"MissingObjFile",
                 [](json& s) {
                   first_object(s)["mesh"] = {{"obj", {{"path", "/nonexistent/x.obj"}}}};
                 },
                 "objects[0].mesh.obj.path", "/nonexistent/x.obj: cannot open"}),
    [](const ::testing::TestParamInfo<BadScene>& info) { return info.param.name; });

TEST(SceneErrors, SpecErrorMessageComesThroughWithFileAndPath) {
  json scene = minimal_scene();
  scene["objects"].push_back(scene["objects"][0]);
  scene["objects"].push_back(scene["objects"][0]);
  scene["objects"][2]["material"]["texture"]["marble"]["turbulence"] = {{"octave_max", 40}};
  const SceneError e = scene_error_of_json(scene);
  EXPECT_STREQ(e.what(),
               "test.json: objects[2].material.texture.marble.turbulence.octave_max = 40: "
               "must be in [0, 24]");
}

TEST(SceneErrors, FileLevelProblemsNameTheFile) {
  // A syntax error names where the parser was: the file, the JSON path and line and column.
  const SceneError syntax = scene_error_of("{\"objects\": [}", "broken.json");
  EXPECT_EQ(syntax.field(), "objects[0]");
  EXPECT_THAT(syntax.what(), AllOf(HasSubstr("broken.json: objects[0]: not valid JSON"),
                                   HasSubstr("line 1, column")));

  // JSON has no NaN or Inf; a number too large for a double is where they would come from.
  const SceneError overflow = scene_error_of(
      R"({"objects": [{"mesh": "sphere", "transform": {"scale": 1e400},
          "material": {"texture": {"marble": {}}}}]})");
  EXPECT_THAT(overflow.what(),
              AllOf(HasSubstr("test.json"), HasSubstr("overflow"), HasSubstr("1e400")));

  EXPECT_THAT(scene_error_of(R"({"image": {"width": 1, "width": 2}, "objects": []})").what(),
              HasSubstr("duplicate key \"width\""));
  EXPECT_THAT(scene_error_of("[1, 2]").what(), HasSubstr("test.json: expected an object"));
}

TEST(SceneErrors, NonFiniteNumbersInTextureJsonAreRefused) {
  json spec = {{"noise", {{"scale", std::numeric_limits<double>::quiet_NaN()}}}};
  try {
    (void)texture_spec_from_json(spec, "code", "material.texture");
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "material.texture.noise.scale");
    EXPECT_THAT(e.problem(), HasSubstr("nan is not finite"));
  }
}

TEST(LoadScene, AFileThatNeverEndsIsRefusedAtTheBound) {
  // /dev/zero read whole would fill memory; the bound stops it, for the scene itself and
  // for a MaterialX document a scene names.
  EXPECT_THAT([] { (void)load_scene("/dev/zero"); },
              ::testing::ThrowsMessage<SceneError>(
                  AllOf(HasSubstr("/dev/zero"), HasSubstr("holds more than 67108864 bytes"))));
  nlohmann::json scene = minimal_scene();
  first_object(scene)["material"]["texture"] = {
      {"materialx", {{"path", "/dev/zero"}, {"nodegraph", "g"}, {"output", "out"}}}};
  EXPECT_THAT(
      [&] { (void)parse_scene(scene.dump(), "zero.json"); },
      ::testing::ThrowsMessage<SceneError>(AllOf(
          HasSubstr("materialx.path"), HasSubstr("'/dev/zero' holds more than 67108864 bytes"))));
}

TEST(LoadScene, MissingFileIsNamed) {
  EXPECT_THAT([] { (void)load_scene("/nonexistent/scene.json"); },
              ::testing::ThrowsMessage<SceneError>(
                  AllOf(HasSubstr("/nonexistent/scene.json"), HasSubstr("cannot open"))));
}

// A scene and an OBJ in a fresh folder, removed at the end of the test.
class SceneFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = std::filesystem::temp_directory_path() /
              ("soltex-scene-" + std::to_string(::getpid()) + "-" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(folder_ / "models");
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }
  void write(const std::string& name, std::string_view text) {
    std::ofstream(folder_ / name, std::ios::binary) << text;
  }
  std::filesystem::path folder_;
};

TEST_F(SceneFolder, ObjPathsAreRelativeToTheSceneFileAndShared) {
  write("models/tetra.obj",
        "v 10 0 0\nv 14 0 0\nv 10 2 0\nv 10 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  write("scene.json", R"({"objects": [
      {"mesh": {"obj": {"path": "models/tetra.obj"}}, "material": {"texture": {"wood": {}}}},
      {"mesh": {"obj": {"path": "models/../models/tetra.obj"}},
       "material": {"texture": {"rings": {}}}},
      {"mesh": {"obj": {"path": "models/tetra.obj", "normalize": false}},
       "material": {"texture": {"rings": {}}, "space": "world"},
       "transform": {"translate": [0, 0, -10]}}]})");
  const Scene scene = load_scene(folder_ / "scene.json");
  ASSERT_EQ(scene.objects.size(), 3u);
  EXPECT_EQ(std::get<ObjFile>(scene.objects[0].source).path, folder_ / "models/tetra.obj");
  EXPECT_EQ(scene.objects[0].mesh->triangle_count(), 4u);
  EXPECT_EQ(scene.objects[0].mesh->bounds.max, glm::vec3(1.0f, 0.5f, 0.25f))
      << "normalised by default";
  EXPECT_EQ(scene.objects[0].mesh, scene.objects[1].mesh) << "one load for one file";
  EXPECT_NE(scene.objects[0].mesh, scene.objects[2].mesh);
  EXPECT_EQ(scene.objects[2].mesh->bounds.min, glm::vec3(10.0f, 0.0f, 0.0f));

  // World space: the box of the moved vertices, padded into a cube.
  const BoundingBox world = texture_space_bounds(scene.objects[2]);
  EXPECT_EQ(world.min, glm::vec3(10.0f, 0.0f, -10.0f));
  EXPECT_EQ(world.max, glm::vec3(14.0f, 2.0f, -9.0f));
  const Volume volume = texture_volume(scene.objects[2], 8);
  const glm::dvec3 side = volume.max - volume.min;
  EXPECT_DOUBLE_EQ(side.x, 4.0 * (1.0 + 2.0 / 32.0));
  EXPECT_DOUBLE_EQ(side.y, side.x);
  EXPECT_DOUBLE_EQ(side.z, side.x);
  EXPECT_EQ(0.5 * (volume.min + volume.max), glm::dvec3(12.0, 1.0, -9.5));
}

TEST_F(SceneFolder, AnObjectTooLargeForItsVolumeIsNamedNotAVolumeTheSceneLacks) {
  write("models/huge.obj", "v -1e30 -1e30 0\nv 1e30 -1e30 0\nv 0 1e30 0\nf 1 2 3\n");
  write("scene.json", R"({"objects": [
      {"mesh": {"obj": {"path": "models/huge.obj", "normalize": false}},
       "material": {"texture": {"wood": {}}}}]})");
  try {
    (void)load_scene(folder_ / "scene.json");
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "objects[0]");
    EXPECT_THAT(e.what(), AllOf(HasSubstr("spans [-1"), HasSubstr("volume.min.x"),
                                HasSubstr("[-1e+12, 1e+12]"), HasSubstr("normalize")));
  }
}

TEST_F(SceneFolder, ObjErrorsNameTheSceneFieldAndTheObjFile) {
  write("models/bad.obj", "v 0 0 0\nf 1 2 3\n");
  write("scene.json", R"({"objects": [
      {"mesh": {"obj": {"path": "models/bad.obj"}}, "material": {"texture": {"wood": {}}}}]})");
  try {
    (void)load_scene(folder_ / "scene.json");
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), (folder_ / "scene.json").string());
    EXPECT_EQ(e.field(), "objects[0].mesh.obj.path");
    EXPECT_THAT(e.what(), AllOf(HasSubstr("bad.obj"), HasSubstr("refers to vertex 2")));
  }
}

TEST(ExampleScenes, BunnyMarbleLoadsWhenTheSharedModelsArePresent) {
  if (!std::filesystem::exists(std::filesystem::path(SOLTEX_SHARED_MODELS_DIR) /
                               "stanford-bunny.obj")) {
    GTEST_SKIP() << "../shared/models is absent (the shared test models sit beside the checkout)";
  }
  const Scene scene =
      load_scene(std::filesystem::path(SOLTEX_SOURCE_DIR) / "deploy/scenes/bunny-marble.json");
  ASSERT_FALSE(scene.objects.empty());
  const SceneObject& bunny = scene.objects[0];
  EXPECT_EQ(bunny.mesh->triangle_count(), 69451u);
  EXPECT_TRUE(std::holds_alternative<MarbleParams>(bunny.material.texture.pattern));
}

TEST(Transform, ScalesThenRotatesXYZThenTranslates) {
  Transform t;
  t.translate = {1, 2, 3};
  t.rotate_degrees = {0, 90, 0};
  t.scale = {2, 1, 1};
  const glm::dvec4 p = t.matrix() * glm::dvec4(1, 0, 0, 1);
  // x scaled to 2, turned about y onto -z, then moved.
  EXPECT_NEAR(p.x, 1.0, 1e-12);
  EXPECT_NEAR(p.y, 2.0, 1e-12);
  EXPECT_NEAR(p.z, 1.0, 1e-12);
  Transform about_x_then_z;
  about_x_then_z.rotate_degrees = {90, 0, 90};
  const glm::dvec4 q = about_x_then_z.matrix() * glm::dvec4(0, 1, 0, 0);
  // y -> z about x, then z stays under the turn about z.
  EXPECT_NEAR(q.z, 1.0, 1e-12);
  const glm::dvec3 n = glm::normalize(t.normal_matrix() * glm::dvec3(1, 0, 0));
  EXPECT_NEAR(n.z, -1.0, 1e-12);
}

TEST(CameraOrbit, TurnsAboutTheTargetAlongUp) {
  Camera camera;
  camera.position = {0, 1, 5};
  camera.target = {0, 1, 0};
  const Camera turned = orbited(camera, 90.0);
  EXPECT_NEAR(turned.position.x, 5.0, 1e-12);
  EXPECT_NEAR(turned.position.y, 1.0, 1e-12);
  EXPECT_NEAR(turned.position.z, 0.0, 1e-12);
  EXPECT_EQ(orbit_angle_degrees({CameraOrbit::Rate::per_frame, 2.0, 10}, 5, 100.0), 10.0);
  EXPECT_EQ(orbit_angle_degrees({CameraOrbit::Rate::per_second, 30.0, 10}, 5, 0.5), 15.0);
}

// Every pattern with non-default values survives JSON and back, validated.
TEST(TextureSpecJson, RoundTripsEveryPattern) {
  FractalParams fractal{.scale = 3.0,
                        .octave_min = 1,
                        .octave_max = 7,
                        .basis = NoiseBasis::gradient,
                        .signed_octaves = true};
  const Pattern patterns[] = {
      StripesParams{.width = 0.5, .offset = 0.25, .axis = Axis::y},
      CheckerParams{.size = {0.5, 1.0, 2.0}, .offset = 0.5, .three_d = true},
      ColourCubeParams{.period = 3.0},
      RingsParams{.thickness = 0.2, .base = 0.1, .amplitude = 0.8},
      WoodParams{.ring_spacing = 0.05,
                 .tilt_y = 0.1,
                 .tilt_z = -0.2,
                 .twist = 1.0,
                 .jitter = 0.3,
                 .jitter_scale = 8.0,
                 .grain_fraction = 0.4},
      NoiseParams{.scale = 6.0, .basis = NoiseBasis::gradient},
      TurbulenceParams{.fractal = fractal},
      MarbleParams{.frequency = 1.5,
                   .amplitude = 3.0,
                   .ripple = Ripple::product,
                   .axis = Axis::z,
                   .turbulence = fractal},
  };
  for (const Pattern& pattern : patterns) {
    TextureSpec spec;
    spec.pattern = pattern;
    spec.ramp.keys = {{0.0f, {0.1f, 0.2f, 0.3f}}, {0.7f, {0.9f, 0.8f, 0.7f}}};
    spec.channels = {true, true, false};
    spec.opacity = {0.25f, 0.75f};
    spec = validated(spec);
    const json written = texture_spec_to_json(spec);
    const TextureSpec read = texture_spec_from_json(written, "round-trip", "texture");
    EXPECT_EQ(texture_spec_to_json(read), written) << written.dump();
    EXPECT_EQ(read.pattern.index(), pattern.index());
    EXPECT_EQ(read.channels, spec.channels);
    EXPECT_EQ(read.ramp.keys.size(), 2u);
    EXPECT_EQ(read.ramp.keys[1].colour, spec.ramp.keys[1].colour);
    EXPECT_EQ(read.opacity.high, 0.75f);
  }
}

TEST(TextureSpecJson, HandWrittenJsonMatchesTheStruct) {
  const json text = json::parse(R"({
    "marble": {"frequency": 1, "ripple": "product", "axis": "y",
               "turbulence": {"scale": 2, "octave_min": 1, "octave_max": 4,
                              "basis": "gradient", "signed_octaves": true}},
    "ramp": {"keys": [{"position": 0, "colour": [0, 0, 0]},
                      {"position": 1, "colour": {"r": 1, "g": 1, "b": 1}}]},
    "channels": ["specular", "colour"],
    "specular": {"high": 0.5}
  })");
  const TextureSpec spec = texture_spec_from_json(text, "hand.json", "texture");
  const MarbleParams& m = std::get<MarbleParams>(spec.pattern);
  EXPECT_EQ(m.frequency, 1.0);
  EXPECT_EQ(m.amplitude, 4.0) << "default";
  EXPECT_EQ(m.ripple, Ripple::product);
  EXPECT_EQ(m.axis, Axis::y);
  EXPECT_EQ(m.turbulence.scale, 2.0);
  EXPECT_EQ(m.turbulence.octave_min, 1);
  EXPECT_EQ(m.turbulence.octave_max, 4);
  EXPECT_EQ(m.turbulence.basis, NoiseBasis::gradient);
  EXPECT_TRUE(m.turbulence.signed_octaves);
  ASSERT_EQ(spec.ramp.keys.size(), 2u);
  EXPECT_EQ(spec.ramp.keys[1].colour, glm::vec3(1.0f));
  EXPECT_EQ(spec.channels, (ChannelSet{true, false, true}));
  EXPECT_EQ(spec.specular.low, 0.0f);
  EXPECT_EQ(spec.specular.high, 0.5f);
  EXPECT_EQ(spec.opacity.high, 1.0f);

  // No channels listed, or an empty list: colour only, as in the protocol.
  const TextureSpec plain =
      texture_spec_from_json(json::parse(R"({"checker": {}, "channels": []})"), "f", "t");
  EXPECT_EQ(plain.channels, ChannelSet{});
  EXPECT_EQ(std::get<CheckerParams>(plain.pattern).size, glm::dvec3(1.0));
}

}  // namespace
}  // namespace soltex

namespace soltex {
namespace {

// Each shape is bounded; the scene's total must be too, or a small file asks for billions.
TEST(SceneBounds, TotalTrianglesAreBounded) {
  std::string objects;
  for (int i = 0; i < 40; ++i) {
    if (i > 0) objects += ",";
    objects += R"({"mesh":{"sphere":{"radius":)" + std::to_string(1.0 + i * 0.001) +
               R"(,"segments":1024,"rings":1024}},"material":{"texture":{"noise":{}}}})";
  }
  try {
    (void)parse_scene(R"({"objects":[)" + objects + "]}", "many.json");
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("at most"), std::string::npos) << e.what();
  }
}

// Size, scale and translation each within bounds can still put a world-space texture volume
// beyond the volume bound: the scene is refused at load time, not when it is drawn.
TEST(SceneBounds, TextureVolumeBeyondItsBoundIsRefusedAtLoad) {
  const char* text = R"({"objects":[{"mesh":{"sphere":{"radius":1000000}},
    "transform":{"scale":1000000,"translate":[1000000,0,0]},
    "material":{"texture":{"marble":{}},"space":"world"}}]})";
  try {
    (void)parse_scene(text, "far.json");
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("volume.min.x"), std::string::npos) << e.what();
  }
}

// Translations and the camera reach 1e9, where a double still resolves a float's step on a
// unit object; an explicit volume there must contain the object like anywhere else.
TEST(SceneBounds, ObjectsAndCameraAsFarAsABillionLoad) {
  const Scene scene = parse_scene(R"({
    "camera": {"position": [1e9, 1e9, -999999996], "target": [1e9, 1e9, -1e9]},
    "lights": [{"point": {"position": [-1e9, 1e9, 1e9]}}],
    "objects": [
      {"mesh": "sphere", "transform": {"translate": [1e9, 1e9, -1e9]},
       "material": {"texture": {"marble": {}}, "space": "world",
                    "volume": {"min": [999999998, 999999998, -1000000002],
                               "max": [1000000002, 1000000002, -999999998]}}},
      {"mesh": "box", "transform": {"translate": [-1e9, 0, 0]},
       "material": {"texture": {"marble": {}}, "space": "world"}}],
    "clip_planes": [{"normal": [1, 0, 0], "offset": -1e9}]
  })",
                                  "far.json");
  EXPECT_EQ(scene.objects[0].transform.translate, glm::dvec3(1e9, 1e9, -1e9));
  const Volume fitted = texture_volume(scene.objects[1], 8);
  EXPECT_NEAR(0.5 * (fitted.min.x + fitted.max.x), -1e9, 1e-6);
  EXPECT_GT(fitted.max.x - fitted.min.x, 1.0);

  json shifted = json::parse(R"({"objects": [{"mesh": "sphere",
    "transform": {"translate": [1e9, 0, 0]},
    "material": {"texture": {"marble": {}}, "space": "world",
                 "volume": {"min": [-1, -1, -1], "max": [1, 1, 1]}}}]})");
  EXPECT_THAT(scene_error_of_json(shifted).what(),
              AllOf(HasSubstr("objects[0].material.volume"), HasSubstr("in world space"),
                    HasSubstr("object 0")));
}

TEST(SceneBounds, ObjPathsMustBeRegularFiles) {
  const char* text = R"({"objects":[{"mesh":{"obj":{"path":"/dev/zero"}},
    "material":{"texture":{"noise":{}}}}]})";
  EXPECT_THROW((void)parse_scene(text, "dev.json"), std::exception);
}

}  // namespace
}  // namespace soltex
