#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <unordered_set>
#include <vector>

#include "soltex/common/brick_cache.h"
#include "soltex/common/brick_key.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/raster/gbuffer.h"
#include "soltex/raster/raster_stats.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/scene.h"

// Small scenes built in code (no files, no bounds of the scene format, so objects can sit at
// 1e9) and a renderer that draws them until every brick has arrived.
namespace soltex::stability {

// One object with a built-in shape and a validated texture; lit unless `unlit`.
SceneObject make_object(const std::string& name, const BuiltinShape& shape,
                        const TextureSpec& texture, TextureSpace space = TextureSpace::object,
                        bool unlit = false);

// A scene with ambient light and one directional light, looking from `eye` at `target`.
Scene make_scene(std::vector<SceneObject> objects, const glm::dvec3& eye, const glm::dvec3& target,
                 int width, int height);

struct ConvergedFrame {
  Frame frame;  // the last frame: complete, nothing missing
  int frames = 0;
  bool converged = false;
  std::unordered_set<BrickKey, BrickKeyHash> requested;  // every key any frame missed
};

// Draws frames, handing each frame's misses to the source, until a frame misses nothing and
// the source is idle, or `max_frames` frames were drawn.
ConvergedFrame render_until_converged(FrameRenderer& renderer, const PreparedScene& scene,
                                      const Camera& camera, int width, int height,
                                      net::BrickSource& source, int max_frames = 400);

// The G-buffer FrameRenderer::render() draws for this scene and camera: the same raster
// objects, the same view, so the same pixels (the rasterizer does not depend on threads).
// Kept in step with the renderer by hand, since the renderer does not expose its G-buffer.
GBuffer rasterize(const PreparedScene& scene, const Camera& camera, int width, int height,
                  RasterStats* stats = nullptr);

// Every covered pixel has a finite texture position and normal, a depth in [0, 1] and a
// footprint that is >= 0 and not NaN (it may be +inf); the first pixel that has not, named.
::testing::AssertionResult gbuffer_defined(const GBuffer& g);

// Everything one in-process render needs, owned together.
struct LocalRender {
  explicit LocalRender(std::size_t cache_bytes = std::size_t{256} << 20,
                       RenderOptions options = {});

  BrickCache cache;
  net::LocalBrickSource source;
  FrameRenderer renderer;
};

}  // namespace soltex::stability
