#pragma once

#include <glm/vec3.hpp>

namespace soltex {

// A perspective camera looking from `position` at `target`.
struct Camera {
  glm::dvec3 position{0.0, 0.0, 5.0};
  glm::dvec3 target{0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};  // need not be orthogonal to the view direction
  double fov_y_degrees = 45.0;   // vertical field of view
  double near = 0.1;
  double far = 100.0;
};

// A turntable animation: the camera circles its target about the axis through the target
// along `up`. Positive angles turn counter-clockwise seen from above.
struct CameraOrbit {
  enum class Rate { per_frame, per_second };
  Rate rate = Rate::per_frame;
  double degrees = 2.0;  // per frame or per second
  int frames = 180;
};

// The orbit's angle at a frame: degrees * frame, or degrees * seconds for a timed orbit.
double orbit_angle_degrees(const CameraOrbit& orbit, int frame, double seconds);

// The camera turned by `degrees` about the axis through its target along its up vector.
Camera orbited(const Camera& camera, double degrees);

}  // namespace soltex
