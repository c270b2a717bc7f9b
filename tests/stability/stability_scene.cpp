#include "stability_scene.h"

#include <chrono>
#include <cmath>

#include "soltex/common/texture_spec.h"
#include "soltex/raster/rasterizer.h"

namespace soltex::stability {

SceneObject make_object(const std::string& name, const BuiltinShape& shape,
                        const TextureSpec& texture, TextureSpace space, bool unlit) {
  SceneObject object;
  object.name = name;
  object.source = shape;
  object.mesh = std::make_shared<const Mesh>(make_mesh(shape));
  object.material.texture = validated(texture);
  object.material.space = space;
  object.material.unlit = unlit;
  return object;
}

Scene make_scene(std::vector<SceneObject> objects, const glm::dvec3& eye, const glm::dvec3& target,
                 int width, int height) {
  Scene scene;
  scene.name = "<stability scene>";
  scene.image = {width, height};
  scene.camera.position = eye;
  scene.camera.target = target;
  scene.camera.near = 0.05;
  scene.camera.far = 100.0;
  scene.ambient.intensity = 0.2f;
  scene.lights.push_back(DirectionalLight{{-0.5, -1.0, -0.7}, glm::vec3(1.0f), 0.9f});
  scene.objects = std::move(objects);
  return scene;
}

ConvergedFrame render_until_converged(FrameRenderer& renderer, const PreparedScene& scene,
                                      const Camera& camera, int width, int height,
                                      net::BrickSource& source, int max_frames) {
  ConvergedFrame result;
  while (result.frames < max_frames) {
    result.frame = renderer.render(scene, camera, width, height);
    ++result.frames;
    for (const net::BrickWant& want : result.frame.misses) result.requested.insert(want.key);
    if (result.frame.complete() && source.idle()) {
      result.converged = true;
      break;
    }
    source.want(result.frame.misses);
    // Lets some bricks arrive before the next frame; the frame count, not time, bounds the loop.
    source.wait_idle(std::chrono::milliseconds(50));
  }
  return result;
}

GBuffer rasterize(const PreparedScene& scene, const Camera& camera, int width, int height,
                  RasterStats* stats) {
  // The renderer's own G-buffer: exactly what a frame is drawn from (eye-relative world).
  BrickCache cache(1u << 20);
  FrameRenderer renderer(cache, RenderOptions{.keep_gbuffer = true});
  const Frame frame = renderer.render(scene, camera, width, height);
  if (stats != nullptr) *stats = frame.stats.raster;
  return renderer.last_gbuffer();
}

::testing::AssertionResult gbuffer_defined(const GBuffer& g) {
  const auto finite = [](const auto& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  for (std::size_t i = 0; i < g.pixel_count(); ++i) {
    if (!g.covered(i)) continue;
    const char* problem = nullptr;
    if (!finite(g.texture_position[i])) problem = "texture position not finite";
    if (!finite(g.normal[i])) problem = "normal not finite";
    if (!(g.depth[i] >= 0.0f && g.depth[i] <= 1.0f)) problem = "depth outside [0, 1]";
    if (!(g.footprint[i] >= 0.0f)) problem = "footprint negative or NaN";
    if (problem != nullptr) {
      return ::testing::AssertionFailure()
             << "pixel (" << i % static_cast<std::size_t>(g.width) << ", "
             << i / static_cast<std::size_t>(g.width) << "): " << problem;
    }
  }
  return ::testing::AssertionSuccess();
}

LocalRender::LocalRender(std::size_t cache_bytes, RenderOptions options)
    : cache(cache_bytes), source(cache), renderer(cache, options) {}

}  // namespace soltex::stability
