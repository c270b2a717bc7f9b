#pragma once

#include <array>
#include <cstddef>
#include <glm/mat3x3.hpp>

#include "soltex/common/texture_evaluator.h"

// What TextureEvaluator::sample() reads for a batch of pixels evaluated per pixel: each
// pixel's point moved inward (inset()) and its box (surface_footprint()), from the G-buffer's
// texture position, normal and footprint, made in vector lanes (evaluated_inputs.cpp,
// dispatched per batch). Every lane does what texture_surface.h does for one pixel, the same
// IEEE operations in the same order: the same bits.
namespace soltex::render {

struct EvaluatedLanes {
  static constexpr std::size_t kCapacity = 64;
  template <typename T>
  using Lanes = std::array<T, kCapacity>;

  // In: the G-buffer's texture position, world normal and footprint.
  alignas(64) Lanes<double> position_x, position_y, position_z;
  alignas(64) Lanes<float> normal_x, normal_y, normal_z, footprint;
  // Out.
  std::array<glm::dvec3, kCapacity> points;
  std::array<SampleFootprint, kCapacity> footprints;
};

// `normal_from_world`: the object's TextureSurface map.
void evaluated_inputs(const glm::dmat3& normal_from_world, EvaluatedLanes& lanes,
                      std::size_t count);

}  // namespace soltex::render
