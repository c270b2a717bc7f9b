#pragma once

#include <glm/vec3.hpp>

#include "soltex/scene/scene.h"

namespace soltex {

// Lambert diffuse + Blinn-Phong specular with the texture as albedo. `normal` and
// `to_viewer` are unit world-space vectors; `position` is the world-space point (for point
// lights). Lights the scene does not have cost nothing.
glm::vec3 shade(const Scene& scene, const glm::vec3& albedo, float specular, float shininess,
                const glm::dvec3& position, const glm::dvec3& normal, const glm::dvec3& to_viewer);

}  // namespace soltex
