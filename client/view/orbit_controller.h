#pragma once

#include <glm/vec3.hpp>

#include "soltex/scene/camera.h"

namespace soltex::view {

// Turns and dollies a camera around its target, as a mouse drag and the wheel ask. Yaw turns
// about the camera's up axis through the target, pitch tilts towards it (kept short of the
// poles, where yaw would spin the view), zoom changes the distance to the target.
class OrbitController {
 public:
  explicit OrbitController(const Camera& camera);

  void rotate(double yaw_degrees, double pitch_degrees);
  // Positive steps move closer; each step is 10 % of the distance.
  void zoom(double steps);
  // Back to the camera it was built with.
  void reset();
  // The camera it was built with, turned by `degrees` about the axis through its target along
  // its up vector (soltex::orbited()), at the current distance: a turntable's frame.
  void set_turn(double degrees);

  const Camera& camera() const { return camera_; }
  double distance() const { return distance_; }

 private:
  void update_position();

  Camera initial_;
  Camera camera_;
  glm::dvec3 up_;       // unit
  glm::dvec3 forward_;  // unit, perpendicular to up_: the direction of yaw 0
  glm::dvec3 side_;     // up_ x forward_: the direction of yaw 90 degrees
  double yaw_degrees_ = 0.0;
  double pitch_degrees_ = 0.0;
  double distance_ = 1.0;
  double min_distance_ = 1e-3;
  double max_distance_ = 1e3;
};

}  // namespace soltex::view
