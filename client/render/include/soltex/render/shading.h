#pragma once

#include <array>
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

// The lighting inputs of up to kCapacity pixels, one array per quantity, so that the lighting
// loops run across pixels (and vectorise) instead of over one pixel's three components.
// shade_batch() gives, lane by lane, exactly what shade() gives for the same inputs: the same
// IEEE operations in the same order (vector lanes round like scalars), the highlight's power
// included (one branch-free function for both).
struct ShadeBatch {
  static constexpr int kCapacity = 256;
  template <typename T>
  using Lanes = std::array<T, kCapacity>;

  int count = 0;
  alignas(64) Lanes<double> position_x, position_y, position_z;  // world space
  alignas(64) Lanes<float> normal_x, normal_y, normal_z;         // unit, facing the viewer
  alignas(64) Lanes<float> to_viewer_x, to_viewer_y, to_viewer_z;
  alignas(64) Lanes<float> albedo_r, albedo_g, albedo_b;
  alignas(64) Lanes<float> specular, shininess;
  alignas(64) Lanes<float> colour_r, colour_g, colour_b;  // out
  // Scratch of shade_batch().
  alignas(64) Lanes<float> light_x, light_y, light_z, radiance_r, radiance_g, radiance_b;
  alignas(64) Lanes<float> n_dot_l, n_dot_h, highlight;
};

// colour[i] = shade(lights, albedo[i], specular[i], shininess[i], position[i], normal[i],
// to_viewer[i]) for i in [0, batch.count), bit for bit.
void shade_batch(const PreparedLights& lights, ShadeBatch& batch);

}  // namespace soltex
