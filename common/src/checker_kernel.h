#pragma once

#include <glm/vec3.hpp>
#include <span>

#include "soltex/common/texture_evaluator.h"
#include "soltex/common/texture_spec.h"

namespace soltex {

// The checker's field at each point, box-filtered over its footprint's box: out[i].field =
// fields::checker(c, points[i], footprints[i].box), bit for bit, for every point. Runtime-
// dispatched (checker_kernel.cpp): the branches of the scalar form become selects across the
// points, so a batch of pixels runs in vector lanes instead of mispredicting per axis.
void checker_fields(const CheckerParams& c, std::span<const glm::dvec3> points,
                    std::span<const SampleFootprint> footprints, std::span<Texel> out);

}  // namespace soltex
