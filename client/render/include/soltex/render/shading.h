#pragma once

#include <glm/vec3.hpp>
#include <vector>

#include "soltex/scene/scene.h"

namespace soltex {

// A scene's lights, prepared once per frame: directions normalised, radiance premultiplied,
// so per-pixel shading does no variant dispatch and no normalisation of constants.
struct PreparedLights {
  glm::vec3 ambient{0.0f};
  struct Directional {
    glm::vec3 to_light;
    glm::vec3 radiance;
  };
  struct Point {
    glm::dvec3 position;
    glm::vec3 radiance;  // at distance 1
  };
  std::vector<Directional> directional;
  std::vector<Point> point;
};

PreparedLights prepare_lights(const Scene& scene);

// Lambert diffuse + Blinn-Phong specular with the texture as albedo. `normal` and
// `to_viewer` are unit world-space vectors; `position` is the world-space point (for point
// lights).
glm::vec3 shade(const PreparedLights& lights, const glm::vec3& albedo, float specular,
                float shininess, const glm::dvec3& position, const glm::vec3& normal,
                const glm::vec3& to_viewer);

}  // namespace soltex
