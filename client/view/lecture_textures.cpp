#include "lecture_textures.h"

#include <utility>

#include "soltex/materialx/example_graphs.h"

namespace soltex::view {
namespace {

std::vector<NamedTexture> make_lecture_textures() {
  std::vector<NamedTexture> list;
  const auto add = [&](std::string name, Pattern pattern) {
    TextureSpec spec;
    spec.pattern = std::move(pattern);
    list.push_back({std::move(name), validated(std::move(spec))});
  };
  MarbleParams marble;
  marble.frequency = 1.5;
  marble.turbulence.scale = 2.0;
  marble.turbulence.octave_max = 6;
  add("marble", marble);
  add("wood", WoodParams{});
  add("checker 3D", CheckerParams{glm::dvec3(0.4), 0.5, true});
  add("rings", RingsParams{0.1, 0.0, 1.0});
  add("turbulence", TurbulenceParams{FractalParams{2.0, 0, 6, NoiseBasis::value, false}});
  add("colour cube", ColourCubeParams{1.0});
  add("stripes", StripesParams{0.25, 0.0, Axis::x});
  add("gradient noise", NoiseParams{6.0, NoiseBasis::gradient});
  MarbleParams product;
  product.ripple = Ripple::product;
  product.frequency = 4.0;
  product.turbulence.basis = NoiseBasis::gradient;
  add("marble xyz", product);
  // The example graphs, after the patterns: Tab reaches them.
  for (const materialx::ExampleGraph& example : materialx::example_graphs()) {
    TextureSpec spec;
    spec.graph = example.graph;
    list.push_back({example.name + " (graph)", validated(std::move(spec))});
  }
  return list;
}

}  // namespace

const std::vector<NamedTexture>& lecture_textures() {
  static const std::vector<NamedTexture> textures = make_lecture_textures();
  return textures;
}

}  // namespace soltex::view
