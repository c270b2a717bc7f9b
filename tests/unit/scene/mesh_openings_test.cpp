// A mesh's openings, as a fraction of its area, tell a solid (closed, or nearly: small holes
// left by a scan) from a sheet whose back faces are its other side.
#include "soltex/scene/mesh_openings.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "soltex/scene/builtin_meshes.h"
#include "soltex/scene/obj_loader.h"

namespace soltex {
namespace {

TEST(MeshOpenings, TheBuiltInSolidsAreClosed) {
  EXPECT_EQ(opening_fraction(make_sphere(SphereShape{})), 0.0);
  EXPECT_EQ(opening_fraction(make_torus(TorusShape{})), 0.0);
  // Each face has vertices of its own: the faces close by position, not by index.
  EXPECT_EQ(opening_fraction(make_box(BoxShape{{2.0, 0.5, 3.0}, 4})), 0.0);
}

TEST(MeshOpenings, ASheetIsAllOpening) {
  EXPECT_NEAR(opening_fraction(make_plane(PlaneShape{{12.0, 8.0}, 8})), 1.0, 1e-12);
  const LoadedObj quad = parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", "quad");
  EXPECT_NEAR(opening_fraction(quad.mesh), 1.0, 1e-12);
}

TEST(MeshOpenings, ABoxWithoutItsLidIsOneFifthOpen) {
  Mesh box = make_box(BoxShape{{2.0, 2.0, 2.0}, 3});
  // Drop the triangles of the face at y = +1.
  std::vector<uint32_t> kept;
  for (std::size_t t = 0; t < box.indices.size(); t += 3) {
    bool top = true;
    for (int k = 0; k < 3; ++k) top = top && box.positions[box.indices[t + k]].y == 1.0f;
    if (!top) kept.insert(kept.end(), box.indices.begin() + t, box.indices.begin() + t + 3);
  }
  ASSERT_EQ(kept.size(), box.indices.size() * 5 / 6);
  box.indices = kept;
  const double fraction = opening_fraction(box);
  EXPECT_NEAR(fraction, 0.2, 1e-12);
  EXPECT_LE(fraction, kMostOpeningOfASolid);
}

TEST(MeshOpenings, AHemisphereIsASheet) {
  Mesh sphere = make_sphere(SphereShape{1.0, 128, 64});
  std::vector<uint32_t> kept;
  for (std::size_t t = 0; t < sphere.indices.size(); t += 3) {
    bool upper = true;
    for (int k = 0; k < 3; ++k) upper = upper && sphere.positions[sphere.indices[t + k]].y >= 0.0f;
    if (upper) kept.insert(kept.end(), sphere.indices.begin() + t, sphere.indices.begin() + t + 3);
  }
  sphere.indices = kept;
  // The rim spans pi r^2 of the dome's 2 pi r^2.
  EXPECT_NEAR(opening_fraction(sphere), 0.5, 0.01);
  EXPECT_GT(opening_fraction(sphere), kMostOpeningOfASolid);
}

TEST(MeshOpenings, FacesWoundAgainstTheirNeighboursOpenTheirEdges) {
  // A tetrahedron with one face turned round: each of its three edges is met twice in the
  // same direction, two open sides along the face's outline.
  const LoadedObj flipped = parse_obj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 3 4\n", "flipped");
  EXPECT_GT(opening_fraction(flipped.mesh), 0.0);
  const LoadedObj closed = parse_obj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n", "closed");
  EXPECT_EQ(opening_fraction(closed.mesh), 0.0);
}

// Real models keep small holes and stay solids.
TEST(MeshOpenings, TheStanfordBunnysHolesLeaveItASolid) {
  const auto path = std::filesystem::path(SOLTEX_SHARED_MODELS_DIR) / "stanford-bunny.obj";
  if (!std::filesystem::exists(path)) {
    GTEST_SKIP() << "../shared/models is absent (the shared test models sit beside the checkout)";
  }
  const double fraction = opening_fraction(load_obj(path).mesh);
  EXPECT_GT(fraction, 0.0);
  EXPECT_LT(fraction, 0.05);
}

}  // namespace
}  // namespace soltex
