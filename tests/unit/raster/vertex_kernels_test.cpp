// transform_and_project (client/raster/src/vertex_kernels.cpp) on every Highway target the CPU
// runs, against the vertex-by-vertex definition: transform_vertices() and then
// TriangleSetup::project_vertices().

#include "vertex_kernels.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/ext/matrix_transform.hpp>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "../texture/dispatch_targets.h"
#include "object_frame.h"
#include "raster_test_scenes.h"
#include "triangle_setup.h"

namespace soltex::raster_internal {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 200;

// Positions around and behind the camera, far past the guard band, on the near plane, huge,
// and not finite; normals of every length, zero and not finite.
std::vector<glm::vec3> awkward_vectors(std::size_t count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> near(-3.0f, 3.0f);
  std::uniform_real_distribution<float> exponent(-40.0f, 38.0f);
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const float specials[] = {0.0f,   -0.0f, kInf,   -kInf, std::numeric_limits<float>::quiet_NaN(),
                            1e-30f, 3e38f, -3e38f, 1e6f};
  std::vector<glm::vec3> out(count);
  for (glm::vec3& v : out) {
    for (int c = 0; c < 3; ++c) {
      const auto kind = rng() % 16;
      if (kind < 11) {
        v[c] = near(rng);
      } else if (kind < 14) {
        v[c] = (rng() & 1 ? 1.0f : -1.0f) * std::pow(10.0f, exponent(rng));
      } else {
        v[c] = specials[rng() % std::size(specials)];
      }
    }
  }
  return out;
}

struct Case {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  RasterObject object;
  ObjectFrame frame;
};

Case make_case(std::size_t count, bool with_normals, uint64_t seed, std::size_t first_vertex) {
  Case c;
  c.positions = awkward_vectors(count, seed);
  if (with_normals) c.normals = awkward_vectors(count, seed + 1);
  c.object.mesh.positions = c.positions;
  c.object.mesh.normals = c.normals;
  c.object.model = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, -0.2f, -4.0f)), 0.7f,
                               glm::vec3(0.2f, 1.0f, 0.1f));
  c.object.model = glm::scale(c.object.model, glm::vec3(1.5f, 0.5f, 2.0f));
  c.object.texture_from_object =
      glm::translate(glm::dmat4(1.0), glm::dvec3(1e9, -2.5e6, 0.125)) * glm::dmat4(3.0);
  RasterView view;
  view.width = kWidth;
  view.height = kHeight;
  view.view_projection = raster_test::perspective_look_at({0, 0, 0}, {0, 0, -1}, kWidth, kHeight);
  c.frame = make_object_frame(c.object, view, first_vertex, planes_keeping_the_eye(view));
  return c;
}

// The fields a triangle reads: clip position, texture, normal and validity always; outcodes
// where valid; the screen position where also inside the guard band.
// A NaN's sign and payload are not compared: which operand's NaN an addition passes on is
// the compiler's choice once it commutes the operands, and a vertex with a NaN is invalid.
template <typename Vector>
void expect_same_bits(const Vector& a, const Vector& b, const std::string& where) {
  for (int c = 0; c < Vector::length(); ++c) {
    if (std::isnan(a[c]) && std::isnan(b[c])) continue;
    ASSERT_EQ(std::bit_cast<uint64_t>(static_cast<double>(a[c])),
              std::bit_cast<uint64_t>(static_cast<double>(b[c])))
        << where << " component " << c << ": " << a[c] << " against " << b[c];
  }
}

void expect_same_vertex(const TransformedVertices& a, const TransformedVertices& b, std::size_t at,
                        const std::string& where) {
  expect_same_bits(a.clip[at], b.clip[at], where + " clip");
  const TransformedVertex& u = a.vertex[at];
  const TransformedVertex& v = b.vertex[at];
  expect_same_bits(u.texture, v.texture, where + " texture");
  expect_same_bits(u.normal, v.normal, where + " normal");
  ASSERT_EQ(u.valid, v.valid) << where;
  if (u.valid == 0) return;
  ASSERT_EQ(u.frustum_outside, v.frustum_outside) << where;
  ASSERT_EQ(u.clip_outside, v.clip_outside) << where;
  if (u.clip_outside != 0) return;
  ASSERT_EQ(u.x, v.x) << where;
  ASSERT_EQ(u.y, v.y) << where;
  ASSERT_EQ(std::bit_cast<uint64_t>(u.depth), std::bit_cast<uint64_t>(v.depth)) << where;
  ASSERT_EQ(std::bit_cast<uint32_t>(u.inv_w), std::bit_cast<uint32_t>(v.inv_w)) << where;
}

TEST(VertexKernels, EveryTargetTransformsAndProjectsAsTheDefinition) {
  const std::vector<int64_t> targets = test::targets_to_run(vertex_kernels_compiled_targets());
  ASSERT_FALSE(targets.empty());
  const TriangleSetup setup(kWidth, kHeight, 0);
  for (const int64_t target : targets) {
    const test::ForcedTarget forced(target);
    ASSERT_EQ(vertex_kernels_dispatched_target(), target) << hwy::TargetName(target);
    // Blocks shorter than, equal to and longer than the kernel's, and a range that starts
    // inside the mesh and at a later place in the frame's vertex array.
    for (const std::size_t count :
         {std::size_t{1}, std::size_t{63}, std::size_t{64}, std::size_t{65}, std::size_t{1000}}) {
      for (const bool with_normals : {true, false}) {
        const std::size_t first_vertex = count % 7;
        const Case c = make_case(count, with_normals, count * 2 + with_normals, first_vertex);
        const std::size_t begin = count > 10 ? 3 : 0;
        TransformedVertices lanes, definition;
        lanes.resize(first_vertex + count, 0);
        definition.resize(first_vertex + count, 0);
        setup.transform_and_project(c.frame, begin, count, lanes);
        transform_vertices(c.frame, begin, count, definition);
        setup.project_vertices(definition, first_vertex + begin, first_vertex + count);
        std::size_t projected = 0;
        for (std::size_t i = begin; i < count; ++i) {
          const std::size_t at = first_vertex + i;
          expect_same_vertex(lanes, definition, at,
                             std::string(hwy::TargetName(target)) + " count " +
                                 std::to_string(count) + " vertex " + std::to_string(i));
          projected += definition.vertex[at].valid && definition.vertex[at].clip_outside == 0;
        }
        // The awkward inputs still leave most vertices on screen: the comparison is not
        // only of rejected ones.
        if (count >= 64) {
          EXPECT_GT(projected, count / 4) << hwy::TargetName(target);
        }
      }
    }
  }
}

}  // namespace
}  // namespace soltex::raster_internal
