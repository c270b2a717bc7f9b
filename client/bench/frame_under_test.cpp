#include "frame_under_test.h"

#include <stdexcept>
#include <string>

#include "headless_session.h"
#include "octave_cap.h"

namespace soltex::bench {
namespace {

// Large enough that nothing a frame uses is evicted: eviction would tie the frame time to
// the budget, which is another question than accuracy.
constexpr std::size_t kCacheBudget = std::size_t{8} << 30;

}  // namespace

FrameUnderTest::FrameUnderTest(const Scene& scene, const AccuracySetting& setting, FrameSize size,
                               int threads, std::chrono::milliseconds max_converge)
    : setting_(setting),
      size_(size),
      scene_(setting.octave_cap ? with_octave_cap(scene, *setting.octave_cap) : scene),
      resolution_{setting.finest_level, setting.brick_size, MipSettings{setting.mip, 2}},
      cache_(std::make_unique<BrickCache>(kCacheBudget)),
      local_(std::make_unique<net::LocalBrickSource>(*cache_)),
      source_(std::make_unique<RecordingBrickSource>(*local_)),
      prepared_(prepare_scene(scene_, resolution_, *source_)) {
  RenderOptions options;
  options.filter = setting.filter;
  options.threads = threads;
  options.access = setting.access;
  options.antialias = setting.antialias;
  options.anisotropy = setting.anisotropy;
  renderer_ = std::make_unique<FrameRenderer>(*cache_, options);
  view::HeadlessOptions converge;
  converge.max_time = max_converge;
  view::HeadlessResult converged = view::render_until_converged(
      *renderer_, prepared_, scene_.camera, size.width, size.height, *source_, converge);
  if (converged.converged_ms < 0.0) {
    throw std::runtime_error(setting.label() + ": the frame did not converge in " +
                             std::to_string(max_converge.count() / 1000) + " s");
  }
  image_ = std::move(converged.image);
  // Not source statistics: the in-process source may evaluate a brick twice when a frame asks
  // for it again while it is being made; a fetcher would not, and a server would not send it.
  for (const BrickKey& key : source_->wanted()) {
    if (cache_->contains(key)) bricks_.push_back(key);
  }
  resident_bytes_ = cache_->stats().resident_bytes;
  const FrameStats stats =
      renderer_->render(prepared_, scene_.camera, size.width, size.height).stats;
  covered_pixels_ = stats.covered_pixels;
  evaluated_pixels_ = stats.evaluated_pixels;
}

Elapsed FrameUnderTest::time_frame() {
  const Stopwatch stopwatch;
  const Frame frame = renderer_->render(prepared_, scene_.camera, size_.width, size_.height);
  const Elapsed elapsed = stopwatch.elapsed();
  if (!frame.complete()) {
    throw std::runtime_error(setting_.label() + ": a warm frame missed bricks");
  }
  return elapsed;
}

BrickCostMeter FrameUnderTest::brick_cost_meter(const CodecChoice& codec) const {
  return BrickCostMeter(prepared_, resolution_.mip, bricks_, codec);
}

}  // namespace soltex::bench
