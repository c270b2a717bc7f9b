#include "turntable.h"

namespace soltex::view {

Turntable::Turntable(std::optional<CameraOrbit> orbit) : orbit_(orbit) {
  restart();
}

void Turntable::restart() {
  next_frame_ = 0;
  stopped_ = false;
  started_ = {};
}

std::optional<double> Turntable::next_angle(Clock::time_point now) {
  if (!playing()) return std::nullopt;
  // The clock starts with the first frame shown, not with the window: setting up (the
  // capability probe, the first bricks) is no part of the animation.
  if (next_frame_ == 0) started_ = now;
  const double seconds = std::chrono::duration<double>(now - started_).count();
  return orbit_angle_degrees(*orbit_, next_frame_++, seconds);
}

}  // namespace soltex::view
