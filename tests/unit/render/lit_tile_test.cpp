// LitTile::light() (a tile's lit pixels lit in scan order from the G-buffer's planes) against
// the batch by index (SurfaceUnprojection::fill(), shade_batch(), LitPixels::write()): the same
// bytes in every pixel, lit or not.
#include <gtest/gtest.h>

#include <glm/matrix.hpp>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "lit_pixels.h"
#include "soltex/render/frame_renderer.h"

namespace soltex::render {
namespace {

constexpr int kWidth = 80, kHeight = 48;

// Depths across the view (some uncovered: +inf), normals of any length (some zero), some back
// faces.
GBuffer random_gbuffer(std::mt19937& rng) {
  GBuffer g;
  g.resize(kWidth, kHeight, false);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), signed_unit(-1.5f, 1.5f);
  for (std::size_t i = 0; i < g.pixel_count(); ++i) {
    const float pick = unit(rng);
    const bool covered = pick > 0.05f;
    g.depth[i] = covered ? 0.9f + 0.1f * unit(rng) : std::numeric_limits<float>::infinity();
    g.flags[i] = static_cast<uint8_t>((covered ? GBuffer::kCovered : 0) |
                                      (covered && pick > 0.8f ? GBuffer::kBackFace : 0));
    g.normal[i] = pick < 0.1f ? glm::vec3(0.0f)
                              : glm::vec3(signed_unit(rng), signed_unit(rng), signed_unit(rng));
  }
  return g;
}

SurfaceInputs random_surface(std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float opacity = unit(rng) < 0.3f ? unit(rng) : 1.0f;
  return {glm::vec3(1.2f * unit(rng), 1.2f * unit(rng), 1.2f * unit(rng)), opacity, unit(rng)};
}

PreparedLights lights(bool with_point) {
  PreparedLights l;
  l.ambient = glm::vec3(0.2f, 0.18f, 0.25f);
  l.directional.push_back({glm::normalize(glm::vec3(0.4f, 0.8f, 0.45f)), glm::vec3(0.9f)});
  if (with_point) l.point.push_back({glm::dvec3(1.0, 3.0, 2.0), glm::vec3(4.0f, 3.5f, 3.0f)});
  return l;
}

TEST(LitTile, LightsAsTheBatchByIndexBitForBit) {
  std::mt19937 rng(17);
  const GBuffer g = random_gbuffer(rng);
  Camera camera;
  camera.position = glm::dvec3(0.5, 2.0, 6.0);
  camera.target = glm::dvec3(0.0, -0.2, 0.0);
  const SurfaceUnprojection u(glm::inverse(view_projection(camera, kWidth, kHeight)),
                              camera.position, kWidth, kHeight);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (const bool with_point : {false, true}) {
    const PreparedLights l = lights(with_point);
    // Tiles at the image's edges too: full, narrow, short; rows with no lit pixel, rows with
    // every pixel lit, rows with gaps.
    for (const auto& [x0, y0, width, height] :
         {std::array{0, 0, 32, 32}, std::array{45, 7, 32, 29}, std::array{77, 40, 3, 8},
          std::array{10, 47, 20, 1}}) {
      auto tile = std::make_unique<LitTile>();
      auto batch = std::make_unique<LitPixels>();
      auto scratch = std::make_unique<ShadeBatch>();
      tile->x0 = x0;
      tile->y0 = y0;
      tile->width = width;
      tile->height = height;
      tile->first = g.index(x0, y0);
      tile->row_stride = static_cast<std::size_t>(g.width);
      Image by_tile(kWidth, kHeight);
      for (std::size_t i = 0; i < by_tile.rgb.size(); ++i) by_tile.rgb[i] = static_cast<uint8_t>(i);
      Image by_index = by_tile;
      const auto flush = [&] {
        u.fill(g, *batch);
        shade_batch(l, batch->batch);
        batch->write(by_index);
        batch->batch.count = 0;
      };
      for (int y = y0 + height - 1; y >= y0; --y) {  // any order: bottom up
        const float share = (y % 5 == 0) ? 0.0f : (y % 5 == 1 ? 1.0f : 0.6f);
        for (int x = x0; x < x0 + width; ++x) {
          if (unit(rng) >= share) continue;
          const SurfaceInputs surface = random_surface(rng);
          const float shininess = 1.0f + 99.0f * unit(rng);
          tile->add(tile->slot(x, y), surface, shininess);
          batch->add(batch->batch.count++, x, y, g.index(x, y), surface, shininess);
          if (batch->batch.count == ShadeBatch::kCapacity) flush();
        }
      }
      if (batch->batch.count > 0) flush();
      tile->light(u, l, g, *scratch, by_tile);
      EXPECT_EQ(by_tile.rgb, by_index.rgb)
          << "tile at " << x0 << ", " << y0 << " point light " << with_point;
      EXPECT_EQ(scratch->count, 0);
      for (std::size_t r = 0; r < static_cast<std::size_t>(LitTile::kSide); ++r) {
        EXPECT_EQ(tile->row_mask(r), 0u) << "row " << r << " still marked lit";
      }
    }
  }
}

}  // namespace
}  // namespace soltex::render
