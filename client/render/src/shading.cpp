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

namespace {

// light_term() across the batch, for a light whose direction and radiance are in the batch's
// light_* and radiance_* lanes; adds it to the colour lanes.
void add_light_term(ShadeBatch& b) {
  const int count = b.count;
  // Diffuse, and the half vector's cosine, in vector loops.
  for (int i = 0; i < count; ++i) {
    const float n_dot_l = (b.normal_x[i] * b.light_x[i] + b.normal_y[i] * b.light_y[i]) +
                          b.normal_z[i] * b.light_z[i];
    const float hx = b.light_x[i] + b.to_viewer_x[i];
    const float hy = b.light_y[i] + b.to_viewer_y[i];
    const float hz = b.light_z[i] + b.to_viewer_z[i];
    const float inverse_length = 1.0f / std::sqrt((hx * hx + hy * hy) + hz * hz);
    b.n_dot_l[i] = n_dot_l;
    b.n_dot_h[i] = (b.normal_x[i] * (hx * inverse_length) + b.normal_y[i] * (hy * inverse_length)) +
                   b.normal_z[i] * (hz * inverse_length);
  }
  // The highlight's power in every lane (a vector loop), kept where light_term() computes it.
  for (int i = 0; i < count; ++i) {
    const float n_dot_h = b.n_dot_h[i];
    const float power = render_internal::specular_power(n_dot_h, b.shininess[i]);
    // & rather than &&: no branches, or the loop stays scalar.
    const bool wanted = (b.n_dot_l[i] > 0.0f) & (b.specular[i] > 0.0f) & (n_dot_h > 0.0f);
    b.highlight[i] = wanted ? b.specular[i] * power : 0.0f;
  }
  for (int i = 0; i < count; ++i) {
    const float n_dot_l = b.n_dot_l[i];
    const float r = b.albedo_r[i] * b.radiance_r[i] * n_dot_l;
    const float g = b.albedo_g[i] * b.radiance_g[i] * n_dot_l;
    const float bl = b.albedo_b[i] * b.radiance_b[i] * n_dot_l;
    // Every sum computed, then selected: additions under a condition would keep the loop scalar.
    // light_term() adds the highlight only where it computed one.
    const bool has_highlight = n_dot_l > 0.0f && b.specular[i] > 0.0f && b.n_dot_h[i] > 0.0f;
    const float r_total = has_highlight ? r + b.radiance_r[i] * b.highlight[i] : r;
    const float g_total = has_highlight ? g + b.radiance_g[i] * b.highlight[i] : g;
    const float b_total = has_highlight ? bl + b.radiance_b[i] * b.highlight[i] : bl;
    const bool lit = n_dot_l > 0.0f;
    b.colour_r[i] = lit ? b.colour_r[i] + r_total : b.colour_r[i];
    b.colour_g[i] = lit ? b.colour_g[i] + g_total : b.colour_g[i];
    b.colour_b[i] = lit ? b.colour_b[i] + b_total : b.colour_b[i];
  }
}

}  // namespace

void shade_batch(const PreparedLights& lights, ShadeBatch& b) {
  const int count = b.count;
  for (int i = 0; i < count; ++i) {
    b.colour_r[i] = b.albedo_r[i] * lights.ambient.r;
    b.colour_g[i] = b.albedo_g[i] * lights.ambient.g;
    b.colour_b[i] = b.albedo_b[i] * lights.ambient.b;
  }
  for (const auto& d : lights.directional) {
    for (int i = 0; i < count; ++i) {
      b.light_x[i] = d.to_light.x;
      b.light_y[i] = d.to_light.y;
      b.light_z[i] = d.to_light.z;
      b.radiance_r[i] = d.radiance.r;
      b.radiance_g[i] = d.radiance.g;
      b.radiance_b[i] = d.radiance.b;
    }
    add_light_term(b);
  }
  for (const auto& p : lights.point) {
    const glm::dvec3 light = p.position;
    const glm::vec3 radiance = p.radiance;
    for (int i = 0; i < count; ++i) {
      const double ox = light.x - b.position_x[i];
      const double oy = light.y - b.position_y[i];
      const double oz = light.z - b.position_z[i];
      const double dot = (ox * ox + oy * oy) + oz * oz;
      const double distance2 = dot < 1e-12 ? 1e-12 : dot;  // std::max(dot, 1e-12)
      const double distance = std::sqrt(distance2);
      b.light_x[i] = static_cast<float>(ox / distance);
      b.light_y[i] = static_cast<float>(oy / distance);
      b.light_z[i] = static_cast<float>(oz / distance);
      const auto d2 = static_cast<float>(distance2);
      b.radiance_r[i] = radiance.r / d2;
      b.radiance_g[i] = radiance.g / d2;
      b.radiance_b[i] = radiance.b / d2;
    }
    add_light_term(b);
  }
}

}  // namespace soltex
