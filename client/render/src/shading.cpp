#include "soltex/render/shading.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace soltex {

glm::vec3 shade(const Scene& scene, const glm::vec3& albedo, float specular, float shininess,
                const glm::dvec3& position, const glm::dvec3& normal, const glm::dvec3& to_viewer) {
  glm::vec3 colour = albedo * scene.ambient.colour * scene.ambient.intensity;
  for (const Light& light : scene.lights) {
    glm::dvec3 to_light;
    glm::vec3 radiance;
    if (const auto* d = std::get_if<DirectionalLight>(&light)) {
      to_light = -glm::normalize(d->direction);
      radiance = d->colour * d->intensity;
    } else {
      const auto& p = std::get<PointLight>(light);
      const glm::dvec3 offset = p.position - position;
      const double distance2 = std::max(glm::dot(offset, offset), 1e-12);
      to_light = offset / std::sqrt(distance2);
      radiance = p.colour * (p.intensity / static_cast<float>(distance2));
    }
    const double n_dot_l = glm::dot(normal, to_light);
    if (!(n_dot_l > 0.0)) continue;
    colour += albedo * radiance * static_cast<float>(n_dot_l);
    if (specular > 0.0f) {
      const glm::dvec3 half = glm::normalize(to_light + to_viewer);
      const double n_dot_h = std::max(glm::dot(normal, half), 0.0);
      colour += radiance * (specular * static_cast<float>(std::pow(n_dot_h, shininess)));
    }
  }
  return colour;
}

}  // namespace soltex
