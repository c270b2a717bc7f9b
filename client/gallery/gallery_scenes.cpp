#include "gallery_scenes.h"

#include "soltex/materialx/example_graphs.h"

namespace soltex::gallery {

std::vector<NamedTexture> gallery_textures() {
  std::vector<NamedTexture> list;
  const auto add = [&](std::string name, std::string description, Pattern pattern) {
    TextureSpec spec;
    spec.pattern = std::move(pattern);
    list.push_back({std::move(name), std::move(description), validated(std::move(spec))});
  };
  add("stripes", "floor(A + x / s) mod 2, yellow and red", StripesParams{0.25, 0.0, Axis::x});
  add("checker-2d", "(floor(x / s) + floor(y / s)) mod 2",
      CheckerParams{glm::dvec3(0.25), 0.0, false});
  add("checker-3d", "(floor(x / s) + floor(y / s) + floor(z / s)) mod 2",
      CheckerParams{glm::dvec3(0.25), 0.0, true});
  add("colour-cube", "(1 - |2 fract(x) - 1|, same for y and z)", ColourCubeParams{1.0});
  add("rings", "floor(sqrt(x^2 + y^2) / M) mod 2", RingsParams{0.1, 0.0, 1.0});
  add("wood", "twisted, jittered rings with a thin dark grain", WoodParams{});
  add("value-noise", "lattice value noise, trilinear", NoiseParams{8.0, NoiseBasis::value});
  add("gradient-noise", "improved gradient noise (Perlin 2002)",
      NoiseParams{8.0, NoiseBasis::gradient});
  add("turbulence", "sum (1/2)^k noise(2^k s p), value noise, 6 octaves",
      TurbulenceParams{FractalParams{4.0, 0, 5, NoiseBasis::value, false}});
  add("turbulence-gradient", "sum (1/2)^k |gradient noise(2^k s p)|, 6 octaves",
      TurbulenceParams{FractalParams{4.0, 0, 5, NoiseBasis::gradient, false}});
  add("marble", "undulate(sin(2 pi x f + A turb(p)))", MarbleParams{});
  MarbleParams product;
  product.ripple = Ripple::product;
  product.frequency = 4.0;
  add("marble-xyz", "the slides' literal sin(2 pi x y z + A turb(p))", product);
  // The example node graphs (deploy/scenes/graphs/*.mtlx, built in).
  for (const materialx::ExampleGraph& example : materialx::example_graphs()) {
    TextureSpec spec;
    spec.graph = example.graph;
    list.push_back({"graph-" + example.name,
                    "node graph, deploy/scenes/graphs/" + example.name + ".mtlx",
                    validated(std::move(spec))});
  }
  return list;
}

}  // namespace soltex::gallery
