#pragma once

#include <memory>
#include <vector>

#include "accuracy_setting.h"
#include "brick_cost.h"
#include "recording_brick_source.h"
#include "soltex/common/brick_cache.h"
#include "soltex/net/local_brick_source.h"
#include "soltex/render/frame_renderer.h"
#include "soltex/render/image.h"
#include "soltex/render/prepared_scene.h"
#include "soltex/scene/scene.h"
#include "stopwatch.h"

namespace soltex::bench {

struct FrameSize {
  int width = 640;
  int height = 360;
};

// One setting's frame, drawn until it converged from its own cache (filled in-process, as
// soltexd would fill it) and kept ready to be drawn again: the sweep times every setting's
// frames in interleaved rounds, so that the shared machine's changing load spreads evenly over
// the settings instead of landing on whichever ran during a busy minute.
class FrameUnderTest {
 public:
  // Converges the frame; throws std::runtime_error when it does not within max_converge.
  FrameUnderTest(const Scene& scene, const AccuracySetting& setting, FrameSize size, int threads,
                 std::chrono::milliseconds max_converge);
  FrameUnderTest(const FrameUnderTest&) = delete;
  FrameUnderTest& operator=(const FrameUnderTest&) = delete;

  const AccuracySetting& setting() const { return setting_; }
  const Image& image() const { return image_; }  // the converged frame
  // Distinct bricks the frame asked for until it converged, all of them resident.
  const std::vector<BrickKey>& bricks() const { return bricks_; }
  uint64_t resident_bytes() const { return resident_bytes_; }
  // Of the converged frame: covered pixels, and those whose texture was evaluated per pixel.
  std::size_t covered_pixels() const { return covered_pixels_; }
  std::size_t evaluated_pixels() const { return evaluated_pixels_; }

  // Draws the frame once more and returns how long FrameRenderer::render took. Throws
  // std::runtime_error if it missed a brick (the cache is meant to be warm).
  Elapsed time_frame();

  // Measures what this frame's bricks cost to make and move with `codec`; the meter points
  // into this object, which must outlive it.
  BrickCostMeter brick_cost_meter(const CodecChoice& codec) const;

 private:
  AccuracySetting setting_;
  FrameSize size_;
  Scene scene_;  // the scene as drawn (octaves capped); prepared_ points into it
  TextureResolution resolution_;
  std::unique_ptr<BrickCache> cache_;
  std::unique_ptr<net::LocalBrickSource> local_;
  std::unique_ptr<RecordingBrickSource> source_;
  PreparedScene prepared_;
  std::unique_ptr<FrameRenderer> renderer_;
  Image image_;
  std::vector<BrickKey> bricks_;
  uint64_t resident_bytes_ = 0;
  std::size_t covered_pixels_ = 0, evaluated_pixels_ = 0;
};

}  // namespace soltex::bench
