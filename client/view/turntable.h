#pragma once

#include <chrono>
#include <optional>

#include "soltex/scene/camera.h"

namespace soltex::view {

// The scene's `camera.orbit` (docs/SCENES.md) as the window plays it: the camera turns about
// the axis through its target along its up vector, counter-clockwise seen from above, by
// degrees_per_frame for each frame drawn (or degrees_per_second of the clock), for the
// orbit's `frames` frames; then it holds still, and the still view refines. Frame k of the
// animation shows orbit_angle_degrees(orbit, k, seconds since it began), as a rendered
// turntable movie's frame k would. The user taking the camera (drag, wheel) stops it; the
// camera reset (R) plays it again.
class Turntable {
 public:
  using Clock = std::chrono::steady_clock;

  explicit Turntable(std::optional<CameraOrbit> orbit);

  // Whether frames still turn the camera.
  bool playing() const { return orbit_.has_value() && !stopped_ && next_frame_ < orbit_->frames; }
  // The turn (degrees from the scene's camera) for the frame about to be drawn at `now`, and
  // advances the animation by that frame; nullopt when not playing.
  std::optional<double> next_angle(Clock::time_point now);
  void stop() { stopped_ = true; }
  void restart();

 private:
  std::optional<CameraOrbit> orbit_;
  int next_frame_ = 0;
  Clock::time_point started_{};
  bool stopped_ = false;
};

}  // namespace soltex::view
