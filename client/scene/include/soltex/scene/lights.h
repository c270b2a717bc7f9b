#pragma once

#include <glm/vec3.hpp>
#include <variant>

namespace soltex {

// Light from far away: parallel rays travelling along `direction` (unit length), e.g.
// (0, -1, 0) shines straight down.
struct DirectionalLight {
  glm::dvec3 direction{0.0, -1.0, 0.0};
  glm::vec3 colour{1.0f};
  float intensity = 1.0f;
};

// Light from a point; `intensity` is at distance 1 and falls off with the squared distance.
struct PointLight {
  glm::dvec3 position{0.0};
  glm::vec3 colour{1.0f};
  float intensity = 1.0f;
};

using Light = std::variant<DirectionalLight, PointLight>;

// Light reaching every surface equally, so faces turned away from every light are not black.
struct AmbientLight {
  glm::vec3 colour{1.0f};
  float intensity = 0.15f;
};

}  // namespace soltex
