#include "octave_cap.h"

#include <algorithm>
#include <variant>

#include "soltex/common/overloaded.h"

namespace soltex::bench {
namespace {

// The fractal inside a pattern, or nullptr for patterns without one.
FractalParams* fractal_of(Pattern& pattern) {
  return std::visit(Overloaded{[](TurbulenceParams& p) -> FractalParams* { return &p.fractal; },
                               [](MarbleParams& p) -> FractalParams* { return &p.turbulence; },
                               [](auto&) -> FractalParams* { return nullptr; }},
                    pattern);
}

}  // namespace

std::optional<int> max_fractal_octave(const Scene& scene) {
  std::optional<int> highest;
  for (const SceneObject& object : scene.objects) {
    Pattern pattern = object.material.texture.pattern;
    if (const FractalParams* fractal = fractal_of(pattern)) {
      highest = std::max(highest.value_or(fractal->octave_max), fractal->octave_max);
    }
  }
  return highest;
}

Scene with_octave_cap(Scene scene, int cap) {
  for (SceneObject& object : scene.objects) {
    TextureSpec& texture = object.material.texture;
    if (FractalParams* fractal = fractal_of(texture.pattern)) {
      fractal->octave_max = std::max(fractal->octave_min, std::min(fractal->octave_max, cap));
      texture = validated(texture);
    }
  }
  return scene;
}

}  // namespace soltex::bench
