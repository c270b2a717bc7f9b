#include "soltex/scene/camera.h"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>

namespace soltex {

double orbit_angle_degrees(const CameraOrbit& orbit, int frame, double seconds) {
  return orbit.rate == CameraOrbit::Rate::per_frame ? orbit.degrees * frame
                                                    : orbit.degrees * seconds;
}

Camera orbited(const Camera& camera, double degrees) {
  const glm::dmat4 rotation =
      glm::rotate(glm::dmat4(1.0), glm::radians(degrees), glm::normalize(camera.up));
  Camera result = camera;
  result.position =
      camera.target + glm::dvec3(rotation * glm::dvec4(camera.position - camera.target, 0.0));
  return result;
}

}  // namespace soltex
