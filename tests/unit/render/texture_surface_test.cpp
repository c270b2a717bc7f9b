// Where a cached lookup of stripes or checkers steps inside: along the texture axis a surface
// faces, and nowhere on a surface that crosses the pattern's planes at a slant.
#include "texture_surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace soltex::render {
namespace {

TEST(AxisFaceInset, AFaceAcrossAnAxisStepsInsideAlongThatAxisOnly) {
  const glm::dvec3 p(0.5, 0.25, -0.125);
  EXPECT_EQ(axis_face_inset(p, glm::dvec3(1.0, 0.0, 0.0), 0.01), glm::dvec3(0.49, 0.25, -0.125));
  EXPECT_EQ(axis_face_inset(p, glm::dvec3(0.0, 0.0, -1.0), 0.01), glm::dvec3(0.5, 0.25, -0.115));
  // A face turned by less than 0.8 degrees still faces its axis (a float normal's rounding,
  // a face modelled a hair off), and steps along the axis, not along its normal.
  const double tilt = 0.01;  // radians
  const glm::dvec3 near_x(std::cos(tilt), std::sin(tilt), 0.0);
  const glm::dvec3 moved = axis_face_inset(p, near_x, 0.01);
  EXPECT_EQ(moved.x, 0.49);
  EXPECT_EQ(moved.y, p.y);
  EXPECT_EQ(moved.z, p.z);
}

TEST(AxisFaceInset, ASurfaceAtASlantIsNotMoved) {
  const glm::dvec3 p(0.5, 0.25, -0.125);
  // A box face turned 30 degrees about y, and a sphere's normal 2 degrees from the x axis.
  const double turned = 30.0 * M_PI / 180.0;
  EXPECT_EQ(axis_face_inset(p, glm::dvec3(std::cos(turned), 0.0, std::sin(turned)), 0.01), p);
  const double two = 2.0 * M_PI / 180.0;
  EXPECT_EQ(axis_face_inset(p, glm::dvec3(std::cos(two), 0.0, std::sin(two)), 0.01), p);
  // No normal (a degenerate transform), or no step to take.
  EXPECT_EQ(axis_face_inset(p, glm::dvec3(0.0), 0.01), p);
  EXPECT_EQ(axis_face_inset(p, glm::dvec3(1.0, 0.0, 0.0), std::numeric_limits<double>::infinity()),
            p);
}

}  // namespace
}  // namespace soltex::render
