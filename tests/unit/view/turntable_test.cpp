#include "turntable.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "orbit_controller.h"

namespace soltex::view {
namespace {

using Clock = Turntable::Clock;

TEST(Turntable, WithoutAnOrbitNothingTurns) {
  Turntable turntable(std::nullopt);
  EXPECT_FALSE(turntable.playing());
  EXPECT_FALSE(turntable.next_angle(Clock::now()).has_value());
}

TEST(Turntable, PlaysItsFramesPerFrameThenHoldsStill) {
  Turntable turntable(CameraOrbit{CameraOrbit::Rate::per_frame, 2.0, 3});
  const auto now = Clock::now();
  EXPECT_EQ(turntable.next_angle(now), 0.0);
  EXPECT_EQ(turntable.next_angle(now), 2.0);
  EXPECT_EQ(turntable.next_angle(now), 4.0);
  EXPECT_FALSE(turntable.playing());
  EXPECT_FALSE(turntable.next_angle(now).has_value());
  turntable.restart();
  EXPECT_EQ(turntable.next_angle(now), 0.0);
}

TEST(Turntable, APerSecondOrbitFollowsTheClockFromItsFirstFrame) {
  Turntable turntable(CameraOrbit{CameraOrbit::Rate::per_second, 30.0, 10});
  const auto first = Clock::now() + std::chrono::seconds(5);  // set-up time does not count
  EXPECT_EQ(turntable.next_angle(first), 0.0);
  EXPECT_DOUBLE_EQ(*turntable.next_angle(first + std::chrono::milliseconds(500)), 15.0);
}

TEST(Turntable, StopsWhenTheUserTakesTheCamera) {
  Turntable turntable(CameraOrbit{CameraOrbit::Rate::per_frame, 2.0, 180});
  turntable.next_angle(Clock::now());
  turntable.stop();
  EXPECT_FALSE(turntable.playing());
  EXPECT_FALSE(turntable.next_angle(Clock::now()).has_value());
}

// The window's turn is the scene's orbit: soltex::orbited() of the scene's camera.
TEST(OrbitController, SetTurnIsTheScenesOrbit) {
  Camera camera;
  camera.position = {1.0, 2.0, 4.0};
  camera.target = {0.5, 0.0, -1.0};
  for (const double degrees : {0.0, 30.0, 90.0, -135.0, 360.0, 725.0}) {
    OrbitController controller(camera);
    controller.set_turn(degrees);
    const glm::dvec3 expected = orbited(camera, degrees).position;
    EXPECT_LT(glm::length(controller.camera().position - expected), 1e-9) << degrees;
  }
}

}  // namespace
}  // namespace soltex::view
