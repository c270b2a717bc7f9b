#pragma once

#include <vector>

#include "accuracy_setting.h"
#include "soltex/scene/scene.h"

namespace soltex::bench {

// The settings an accuracy sweep measures, the default first, each once. Not the Cartesian
// product of the knobs (thousands of settings): one knob at a time around the default
// (finest level, brick size, filter, MIP construction, octave cap, codec), plus the grid of
// finest level x filter, the two knobs that trade most directly against each other.
// Octave caps at or above the scene's own octaves change nothing and are left out; the
// finest level applies to the materials that do not set their own.
// `quick`: a handful of settings, enough to exercise every part of the sweep.
std::vector<AccuracySetting> accuracy_sweep(const Scene& scene, bool quick);

}  // namespace soltex::bench
