#include "level_bias_controller.h"

#include <gtest/gtest.h>

#include <limits>

namespace soltex::view {
namespace {

LevelBiasSettings test_settings() {
  LevelBiasSettings settings;
  settings.target_frame_ms = 30.0;
  settings.fast_fraction = 0.5;
  settings.step = 0.25;
  settings.max_bias = 1.0;
  settings.frames_per_decision = 2;
  return settings;
}

// Starts an interaction (its first frame only resumes the interaction bias) and records
// `frames` frames of `frame_ms` each; returns the bias after them.
double interact(LevelBiasController& controller, int frames, double frame_ms) {
  double bias = controller.bias();
  for (int i = 0; i < frames; ++i) bias = controller.record_frame(frame_ms, true);
  return bias;
}

TEST(LevelBiasController, StartsAtFullDetail) {
  const LevelBiasController controller(test_settings());
  EXPECT_EQ(controller.bias(), 0.0);
  EXPECT_EQ(controller.interaction_bias(), 0.0);
}

TEST(LevelBiasController, SlowFramesRaiseTheBiasOneStepPerDecision) {
  LevelBiasController controller(test_settings());
  controller.record_frame(100.0, true);  // the interaction starts
  EXPECT_EQ(controller.record_frame(100.0, true), 0.0) << "one frame is not a decision";
  EXPECT_EQ(controller.record_frame(100.0, true), 0.25);
  EXPECT_EQ(controller.record_frame(100.0, true), 0.25);
  EXPECT_EQ(controller.record_frame(100.0, true), 0.5);
}

TEST(LevelBiasController, NeverRisesAboveTheMaximum) {
  LevelBiasController controller(test_settings());
  EXPECT_EQ(interact(controller, 1 + 40, 1000.0), 1.0);
}

TEST(LevelBiasController, FastFramesLowerTheBiasButNeverBelowZero) {
  LevelBiasController controller(test_settings());
  ASSERT_EQ(interact(controller, 1 + 8, 100.0), 1.0);
  EXPECT_EQ(interact(controller, 2, 5.0), 0.75);
  EXPECT_EQ(interact(controller, 2, 5.0), 0.5);
  EXPECT_EQ(interact(controller, 40, 5.0), 0.0);
}

TEST(LevelBiasController, HoldsTheBiasBetweenSlowAndFast) {
  LevelBiasController controller(test_settings());
  ASSERT_EQ(interact(controller, 1 + 4, 100.0), 0.5);
  // 20 ms: within the 30 ms target but not below half of it.
  EXPECT_EQ(interact(controller, 20, 20.0), 0.5);
}

TEST(LevelBiasController, DecidesOnTheMeanOfTheFramesMeasured) {
  LevelBiasController controller(test_settings());
  controller.record_frame(0.0, true);
  controller.record_frame(10.0, true);
  EXPECT_EQ(controller.record_frame(55.0, true), 0.25) << "mean 32.5 ms is over 30 ms";
  controller.record_frame(10.0, true);
  EXPECT_EQ(controller.record_frame(45.0, true), 0.25) << "mean 27.5 ms holds";
}

TEST(LevelBiasController, StillViewIsDrawnAtFullDetailAndTheInteractionBiasComesBack) {
  LevelBiasController controller(test_settings());
  ASSERT_EQ(interact(controller, 1 + 4, 100.0), 0.5);
  EXPECT_EQ(controller.record_frame(500.0, false), 0.0) << "still views may be slow";
  EXPECT_EQ(controller.record_frame(500.0, false), 0.0);
  EXPECT_EQ(controller.interaction_bias(), 0.5);
  EXPECT_EQ(controller.record_frame(500.0, true), 0.5)
      << "the first interacting frame was drawn at the still bias and decides nothing";
  EXPECT_EQ(controller.record_frame(100.0, true), 0.5);
  EXPECT_EQ(controller.record_frame(100.0, true), 0.75);
}

TEST(LevelBiasController, FramesOfAnEarlierInteractionDoNotCountInTheNext) {
  LevelBiasController controller(test_settings());
  controller.record_frame(100.0, true);
  controller.record_frame(100.0, true);  // one slow frame measured, no decision yet
  controller.record_frame(0.0, false);
  controller.record_frame(5.0, true);
  EXPECT_EQ(controller.record_frame(100.0, true), 0.0) << "one frame of this interaction";
  EXPECT_EQ(controller.record_frame(100.0, true), 0.25);
}

TEST(LevelBiasController, IgnoresFrameTimesThatAreNotNumbers) {
  LevelBiasController controller(test_settings());
  controller.record_frame(1.0, true);
  controller.record_frame(std::numeric_limits<double>::quiet_NaN(), true);
  controller.record_frame(-5.0, true);
  controller.record_frame(std::numeric_limits<double>::infinity(), true);
  EXPECT_EQ(controller.record_frame(100.0, true), 0.0);
  EXPECT_EQ(controller.record_frame(100.0, true), 0.25);
}

TEST(LevelBiasController, ResetForgetsTheInteractionBias) {
  LevelBiasController controller(test_settings());
  ASSERT_EQ(interact(controller, 1 + 4, 100.0), 0.5);
  controller.reset();
  EXPECT_EQ(controller.bias(), 0.0);
  EXPECT_EQ(controller.interaction_bias(), 0.0);
  EXPECT_EQ(controller.record_frame(100.0, true), 0.0);
}

TEST(LevelBiasController, DefaultsHoldThirtyThreeMilliseconds) {
  LevelBiasController controller;
  EXPECT_DOUBLE_EQ(controller.settings().target_frame_ms, 33.0);
  controller.record_frame(0.0, true);
  double bias = 0.0;
  for (int i = 0; i < 100; ++i) bias = controller.record_frame(50.0, true);
  EXPECT_GT(bias, 0.0);
  EXPECT_LE(bias, controller.settings().max_bias);
}

}  // namespace
}  // namespace soltex::view
