#include "orbit_controller.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

namespace soltex::view {
namespace {

constexpr double kMaxPitchDegrees = 89.0;
constexpr double kZoomPerStep = 0.9;

double radians(double degrees) {
  return degrees * std::numbers::pi / 180.0;
}
double degrees(double radians) {
  return radians * 180.0 / std::numbers::pi;
}

// Any unit vector perpendicular to `axis` (unit).
glm::dvec3 perpendicular_to(const glm::dvec3& axis) {
  const glm::dvec3 other = std::abs(axis.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0, 1, 0);
  return glm::normalize(glm::cross(axis, other));
}

}  // namespace

OrbitController::OrbitController(const Camera& camera) : initial_(camera) {
  reset();
}

void OrbitController::reset() {
  camera_ = initial_;
  up_ = glm::length(camera_.up) > 0.0 ? glm::normalize(camera_.up) : glm::dvec3(0.0, 1.0, 0.0);
  const glm::dvec3 offset = camera_.position - camera_.target;
  distance_ = glm::length(offset);
  if (!(distance_ > 0.0)) distance_ = 1.0;
  // The camera must stay between its clip planes, or the target would vanish when zooming.
  min_distance_ = std::max(2.0 * camera_.near, 1e-6);
  max_distance_ = std::max(0.5 * camera_.far, min_distance_);

  const glm::dvec3 direction = offset / distance_;
  const double height = std::clamp(glm::dot(direction, up_), -1.0, 1.0);
  const glm::dvec3 level = direction - height * up_;
  forward_ = glm::length(level) > 1e-9 ? glm::normalize(level) : perpendicular_to(up_);
  side_ = glm::cross(up_, forward_);
  yaw_degrees_ = 0.0;
  pitch_degrees_ = std::clamp(degrees(std::asin(height)), -kMaxPitchDegrees, kMaxPitchDegrees);
  update_position();
}

void OrbitController::rotate(double yaw_degrees, double pitch_degrees) {
  if (!std::isfinite(yaw_degrees) || !std::isfinite(pitch_degrees)) return;
  yaw_degrees_ = std::remainder(yaw_degrees_ + yaw_degrees, 360.0);
  pitch_degrees_ = std::clamp(pitch_degrees_ + pitch_degrees, -kMaxPitchDegrees, kMaxPitchDegrees);
  update_position();
}

void OrbitController::set_turn(double degrees) {
  if (!std::isfinite(degrees)) return;
  // Yaw is measured from the built-with camera about up_, in the sense orbited() turns.
  yaw_degrees_ = std::remainder(degrees, 360.0);
  update_position();
}

void OrbitController::zoom(double steps) {
  if (!std::isfinite(steps)) return;
  distance_ = std::clamp(distance_ * std::pow(kZoomPerStep, steps), min_distance_, max_distance_);
  update_position();
}

void OrbitController::update_position() {
  const double yaw = radians(yaw_degrees_);
  const double pitch = radians(pitch_degrees_);
  const glm::dvec3 level = std::cos(yaw) * forward_ + std::sin(yaw) * side_;
  const glm::dvec3 direction = std::cos(pitch) * level + std::sin(pitch) * up_;
  camera_.position = camera_.target + distance_ * direction;
}

}  // namespace soltex::view
