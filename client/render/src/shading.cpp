#include "soltex/render/shading.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "specular_power.h"

namespace soltex {

PreparedLights prepare_lights(const Scene& scene) {
  PreparedLights lights;
  lights.ambient = scene.ambient.colour * scene.ambient.intensity;
  for (const Light& light : scene.lights) {
    if (const auto* d = std::get_if<DirectionalLight>(&light)) {
      lights.directional.push_back(
          {glm::vec3(-glm::normalize(d->direction)), d->colour * d->intensity});
    } else {
      const auto& p = std::get<PointLight>(light);
      lights.point.push_back({p.position, p.colour * p.intensity});
    }
  }
  return lights;
}

namespace {

// One light's contribution. The highlight's power through specular_power(), which the batched
// loop below shares.
inline glm::vec3 light_term(const glm::vec3& albedo, float specular, float shininess,
                            const glm::vec3& normal, const glm::vec3& to_viewer,
                            const glm::vec3& to_light, const glm::vec3& radiance) {
  const float n_dot_l = glm::dot(normal, to_light);
  if (!(n_dot_l > 0.0f)) return glm::vec3(0.0f);
  glm::vec3 colour = albedo * radiance * n_dot_l;
  if (specular > 0.0f) {
    const glm::vec3 half = glm::normalize(to_light + to_viewer);
    const float n_dot_h = glm::dot(normal, half);
    if (n_dot_h > 0.0f) {
      colour += radiance * (specular * render_internal::specular_power(n_dot_h, shininess));
    }
  }
  return colour;
}

}  // namespace

glm::vec3 shade(const PreparedLights& lights, const glm::vec3& albedo, float specular,
                float shininess, const glm::dvec3& position, const glm::vec3& normal,
                const glm::vec3& to_viewer) {
  glm::vec3 colour = albedo * lights.ambient;
  for (const auto& d : lights.directional) {
    colour += light_term(albedo, specular, shininess, normal, to_viewer, d.to_light, d.radiance);
  }
  for (const auto& p : lights.point) {
    const glm::dvec3 offset = p.position - position;
    const double distance2 = std::max(glm::dot(offset, offset), 1e-12);
    const glm::vec3 to_light(offset / std::sqrt(distance2));
    colour += light_term(albedo, specular, shininess, normal, to_viewer, to_light,
                         p.radiance / static_cast<float>(distance2));
  }
  return colour;
}

}  // namespace soltex
