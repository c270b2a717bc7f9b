#include "level_bias_controller.h"

#include <algorithm>
#include <cmath>

namespace soltex::view {

LevelBiasController::LevelBiasController(LevelBiasSettings settings) : settings_(settings) {
  settings_.step = std::max(settings_.step, 0.0);
  settings_.max_bias = std::max(settings_.max_bias, 0.0);
  settings_.frames_per_decision = std::max(settings_.frames_per_decision, 1);
}

void LevelBiasController::reset() {
  bias_ = 0.0;
  interaction_bias_ = 0.0;
  was_interacting_ = false;
  start_measuring();
}

void LevelBiasController::start_measuring() {
  measured_frames_ = 0;
  measured_ms_ = 0.0;
}

double LevelBiasController::record_frame(double frame_ms, bool interacting) {
  if (!interacting) {
    // A still view may take its time: show it at full detail.
    if (was_interacting_) start_measuring();
    was_interacting_ = false;
    bias_ = 0.0;
    return bias_;
  }
  if (!was_interacting_) {
    // This frame was drawn at the still view's bias, so it says nothing about the
    // interaction bias: resume that and measure afresh.
    was_interacting_ = true;
    bias_ = interaction_bias_;
    start_measuring();
    return bias_;
  }
  // A frame time that is not a number (a clock hiccup) must not decide anything.
  if (!std::isfinite(frame_ms) || frame_ms < 0.0) return bias_;
  measured_ms_ += frame_ms;
  if (++measured_frames_ < settings_.frames_per_decision) return bias_;

  const double mean_ms = measured_ms_ / measured_frames_;
  if (mean_ms > settings_.target_frame_ms) {
    bias_ = std::min(bias_ + settings_.step, settings_.max_bias);
  } else if (mean_ms < settings_.fast_fraction * settings_.target_frame_ms) {
    bias_ = std::max(bias_ - settings_.step, 0.0);
  }
  interaction_bias_ = bias_;
  start_measuring();
  return bias_;
}

}  // namespace soltex::view
