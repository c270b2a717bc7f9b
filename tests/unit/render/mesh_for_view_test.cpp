#include "mesh_for_view.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "soltex/scene/scene_loader.h"
#include "soltex/scene/texture_volume.h"

namespace soltex::render {
namespace {

// A fine sphere of radius 1 at the origin, with its levels as a scene file would load it.
struct FineSphere {
  FineSphere()
      : scene(parse_scene(R"({"objects": [{"name": "ball",
            "mesh": {"sphere": {"radius": 1, "segments": 400, "rings": 200}},
            "material": {"texture": {"marble": {}}}}]})",
                          "<fine sphere>")),
        object(prepared(scene.objects.front())) {}

  static PreparedObject prepared(const SceneObject& ball) {
    const Volume volume = texture_volume(ball, 8);
    PreparedObject p{&ball,
                     RasterObject{},
                     glm::dmat4(1.0),
                     ball.material.texture,
                     volume,
                     BrickLayout(volume, 16),
                     0,
                     3,
                     false,
                     {}};
    p.raster.mesh = {ball.mesh->positions, ball.mesh->normals, ball.mesh->indices};
    return p;
  }

  Scene scene;
  PreparedObject object;
};

Camera at_distance(double distance) {
  Camera camera;
  camera.position = {0.0, 0.0, distance};
  camera.fov_y_degrees = 40.0;
  return camera;
}

TEST(MeshForView, CoarserLevelsAsTheObjectRecedes) {
  const FineSphere sphere;
  ASSERT_FALSE(sphere.scene.objects.front().levels->empty());
  const std::size_t own = sphere.object.raster.mesh.indices.size();
  // Close up the mesh itself: at 1.2 a pixel of 720 rows spans 2.5e-4, too fine for any level.
  EXPECT_EQ(mesh_for_view(sphere.object, at_distance(1.2), 720).indices.size(), own);
  std::size_t previous = own;
  for (double distance : {3.0, 10.0, 30.0, 300.0}) {
    const RasterMesh mesh = mesh_for_view(sphere.object, at_distance(distance), 720);
    EXPECT_LE(mesh.indices.size(), previous) << "at " << distance;
    previous = mesh.indices.size();
  }
  EXPECT_LT(previous, own / 2);
}

TEST(MeshForView, MorePixelsOrALargerObjectKeepFinerLevels) {
  FineSphere sphere;
  const Camera camera = at_distance(10.0);
  const std::size_t at_720 = mesh_for_view(sphere.object, camera, 720).indices.size();
  EXPECT_GE(mesh_for_view(sphere.object, camera, 2880).indices.size(), at_720);
  EXPECT_LT(at_720, sphere.object.raster.mesh.indices.size());
  // Ten times as large, as far from its surface: the same error spans ten times the pixels.
  sphere.object.world_from_object = glm::scale(glm::dmat4(1.0), glm::dvec3(10.0));
  EXPECT_GT(mesh_for_view(sphere.object, at_distance(19.0), 720).indices.size(), at_720);
}

TEST(MeshForView, ObjectsWithoutLevelsDrawTheirOwnMesh) {
  FineSphere sphere;
  sphere.object.object = nullptr;  // made by hand, not loaded
  EXPECT_EQ(mesh_for_view(sphere.object, at_distance(300.0), 720).indices.data(),
            sphere.object.raster.mesh.indices.data());
}

}  // namespace
}  // namespace soltex::render
