#pragma once

#include <optional>

#include "soltex/scene/scene.h"

// Fewer turbulence octaves: cheaper bricks, less fine detail. The accuracy sweep caps them
// to see what the detail is worth against what it costs.
namespace soltex::bench {

// The largest octave_max of the scene's fractal textures (turbulence, marble); empty when no
// texture has octaves.
std::optional<int> max_fractal_octave(const Scene& scene);

// The scene with every fractal's octave_max lowered to `cap` (never below its octave_min);
// other textures and everything else unchanged. Throws SpecError if a result is invalid.
Scene with_octave_cap(Scene scene, int cap);

}  // namespace soltex::bench
