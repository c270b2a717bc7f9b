#include "soltex/capability/capability.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/trigonometric.hpp>
#include <stdexcept>
#include <string>

#include "soltex/scene/default_scene.h"
#include "soltex/scene/scene_loader.h"

namespace soltex::capability {
namespace {

Capability strong_machine() {
  Capability c;
  c.pixels_per_second = 50e6;
  c.available_memory_mb = 16000;
  c.bytes_per_brick = 2500.0;
  return c;
}

// Two bursts of a link: 8 bricks and 64 bricks of 2500 bytes each.
LinkTiming timing(double bricks, double latency_s, double bytes_per_second) {
  const double bytes = bricks * 2500.0;
  return {bricks, bytes, latency_s + bytes / bytes_per_second};
}

TEST(ParseOverride, ReadsEachItemAndRefusesOneGivenTwice) {
  const CapabilityOverride o = parse_override("cpu=0.5,mem=512,bandwidth=2");
  EXPECT_EQ(o.cpu_factor, 0.5);
  EXPECT_EQ(o.memory_mb, 512u);
  EXPECT_EQ(o.bandwidth_mb_per_s, 2.0);
  try {
    (void)parse_override("cpu=1,cpu=2");
    FAIL() << "accepted cpu twice";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'cpu' is given twice"), std::string::npos) << e.what();
  }
}

TEST(FitLink, TellsLatencyFromBandwidth) {
  Capability c;
  fit_link(timing(8, 0.050, 100e6), timing(64, 0.050, 100e6), c);
  EXPECT_NEAR(c.brick_latency_ms, 50.0, 1e-6);
  EXPECT_NEAR(c.bandwidth_mb_per_s, 100.0, 1e-6);
  EXPECT_DOUBLE_EQ(c.bytes_per_brick, 2500.0);

  Capability slow;
  fit_link(timing(8, 0.001, 0.2e6), timing(64, 0.001, 0.2e6), slow);
  EXPECT_NEAR(slow.brick_latency_ms, 1.0, 1e-6);
  EXPECT_NEAR(slow.bandwidth_mb_per_s, 0.2, 1e-9);
}

// A link that answers every burst of wants `latency` late and then moves them at
// `bytes_per_second`; the burst arrives whole once its time is up (the probe waits for each).
// Bricks are 3000 bytes in zstd, which this client decodes at 1.5 ns per decoded byte, and
// kRawBrickBytes raw. Time is the link's own clock (clock()), which waiting moves on to the
// burst's arrival: no real sleeps, so a loaded machine cannot stretch a burst.
class FakeLink final : public net::BrickSource {
 public:
  using Time = std::chrono::steady_clock::time_point;

  FakeLink(std::chrono::milliseconds latency, double bytes_per_second)
      : latency_(latency), bytes_per_second_(bytes_per_second) {}

  ProbeClock clock() {
    return [this] { return now_; };
  }

  uint64_t register_texture(const TextureSpec&, const Volume&, int, const MipSettings&) override {
    return 42;
  }
  void set_codec(Codec codec) override { codec_ = codec; }
  void want(std::vector<net::BrickWant> wants) override {
    done_ = stats();  // the last burst is in: count on from it
    pending_ = wants.size();
    pending_codec_ = codec_;
    const double seconds = static_cast<double>(pending_) * brick_bytes() / bytes_per_second_;
    ready_ = now_ + latency_ +
             std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                 std::chrono::duration<double>(seconds));
  }
  bool idle() const override { return pending_ == 0 || now_ >= ready_; }
  bool wait_idle(std::chrono::milliseconds) override {
    now_ = std::max(now_, ready_);
    return true;
  }
  net::SourceStats stats() const override {
    net::SourceStats stats = done_;
    if (pending_ > 0 && idle()) {
      stats.received += pending_;
      stats.bytes += static_cast<uint64_t>(static_cast<double>(pending_) * brick_bytes());
      const auto c = static_cast<std::size_t>(pending_codec_);
      const double decoded = static_cast<double>(pending_) * (kRawBrickBytes - 28.0);
      stats.decoded_bytes[c] += static_cast<uint64_t>(decoded);
      if (pending_codec_ == Codec::zstd) stats.decode_seconds[c] += decoded * 1.5e-9;
    }
    return stats;
  }

 private:
  static constexpr double kBrickBytes = 3000.0;
  double brick_bytes() const { return pending_codec_ == Codec::raw ? kRawBrickBytes : kBrickBytes; }
  Codec codec_ = Codec::zstd;
  Codec pending_codec_ = Codec::zstd;
  std::chrono::milliseconds latency_;
  double bytes_per_second_;
  std::size_t pending_ = 0;
  Time now_{};
  Time ready_{};
  net::SourceStats done_;
};

TEST(MeasureLink, FiftyMillisecondsAwayIsNotASlowLink) {
  FakeLink link(std::chrono::milliseconds(50), 200e6);
  Capability c = strong_machine();
  measure_link(link, TextureSpec{}, c, false, link.clock());
  // On the link's clock the bursts take what the link says, to the nanosecond the clock counts.
  EXPECT_NEAR(c.brick_latency_ms, 50.0, 1e-3);
  EXPECT_NEAR(c.bandwidth_mb_per_s, 200.0, 0.5)
      << c.bandwidth_mb_per_s << " MB/s: a 200 MB/s link measured as another";
  EXPECT_DOUBLE_EQ(c.bytes_per_brick, 3000.0);
  // At 640x360 the frame holds about 1,800 bricks: eight rounds of 256 at 50 ms fit the
  // window's 1.5 s (at 1280x720 four times as many would not: the start would be coarser).
  const Choice choice = choose(c, default_scene(), 640, 360);
  EXPECT_EQ(choice.start_level_log2, choice.finest_level_log2) << choice.reason;
}

// Loopback: zstd's CPU costs more than the bytes it saves would take; a thin link: the other
// way round. Either way the bursts' bandwidth is the link's, not the probe texture's.
TEST(MeasureLink, AFastLinkGetsRawBricksAThinOneZstd) {
  FakeLink fast(std::chrono::milliseconds(0), 1e15);  // bursts in as soon as asked for
  Capability near = strong_machine();
  measure_link(fast, TextureSpec{}, near, true, fast.clock());
  EXPECT_EQ(near.codec, Codec::raw) << near.raw_link_mb_per_s << " MB/s";
  EXPECT_NEAR(near.zstd_decode_ns_per_byte, 1.5, 1e-6);

  FakeLink thin(std::chrono::milliseconds(5), 2e6);
  Capability far = strong_machine();
  measure_link(thin, TextureSpec{}, far, true, thin.clock());
  EXPECT_EQ(far.codec, Codec::zstd);
  EXPECT_NEAR(far.raw_link_mb_per_s, 2.0, 0.01);

  Capability unasked = strong_machine();
  measure_link(fast, TextureSpec{}, unasked, false, fast.clock());
  EXPECT_EQ(unasked.codec, Codec::zstd);  // without choose_codec: as before, zstd
  EXPECT_EQ(unasked.raw_link_mb_per_s, 0.0);
}

TEST(CodecForLink, RawWhereTheSavedBytesCostLessThanCompressingThem) {
  // zstd shrinking 3 times saves 2/3 of a byte per byte, and costs 2.8 x 1.5 = 4.2 ns of CPU:
  // the bytes it saves take longer than that on links below (2/3) / 4.2 ns = 159 MB/s.
  EXPECT_EQ(codec_for_link(150.0, 3.0, 1.5), Codec::zstd);
  EXPECT_EQ(codec_for_link(170.0, 3.0, 1.5), Codec::raw);
  EXPECT_EQ(codec_for_link(1.0, 3.0, 1.5), Codec::zstd);
  EXPECT_EQ(codec_for_link(1e4, 3.0, 1.5), Codec::raw);
  // A slower decoder moves the line down: compressing costs more.
  EXPECT_EQ(codec_for_link(150.0, 3.0, 3.0), Codec::raw);
  // Nothing known, or nothing to gain: zstd, the protocol's default.
  EXPECT_EQ(codec_for_link(0.0, 3.0, 1.5), Codec::zstd);
  EXPECT_EQ(codec_for_link(1e4, 1.0, 1.5), Codec::zstd);
}

TEST(FitLink, ALargeBurstNoSlowerThanTheSmallOneIsUnlimitedBandwidth) {
  Capability c;
  fit_link({8, 20000, 0.051}, {64, 160000, 0.050}, c);
  EXPECT_EQ(c.bandwidth_mb_per_s, 0.0);
  EXPECT_NEAR(c.brick_latency_ms, 51.0, 1e-9);
}

TEST(FitLink, NothingMovedLeavesTheCapabilityAsItWas) {
  Capability c;
  c.bandwidth_mb_per_s = 7.0;
  fit_link({}, {}, c);
  EXPECT_EQ(c.bandwidth_mb_per_s, 7.0);
  EXPECT_EQ(c.brick_latency_ms, 0.0);
}

// 50 ms away but fast: the same start as a link next door while the frame's bricks take few
// rounds of requests (640x360: about 1,800 bricks). The latency costs rounds, not the picture.
TEST(Choose, LatencyAloneDoesNotMakeASlowLink) {
  const Scene scene = default_scene();
  Capability near = strong_machine();
  fit_link(timing(8, 0.0005, 100e6), timing(64, 0.0005, 100e6), near);
  Capability far = strong_machine();
  fit_link(timing(8, 0.050, 100e6), timing(64, 0.050, 100e6), far);
  const Choice near_choice = choose(near, scene, 640, 360);
  const Choice far_choice = choose(far, scene, 640, 360);
  EXPECT_EQ(far_choice.start_level_log2, near_choice.start_level_log2) << far_choice.reason;
  EXPECT_EQ(far_choice.start_level_log2, far_choice.finest_level_log2) << far_choice.reason;
}

// A thin link starts coarser, but ends where a fast one does: the capability sets the start.
TEST(Choose, ASlowLinkStartsCoarserAndEndsAtTheSameFinestLevel) {
  const Scene scene = default_scene();
  Capability fast = strong_machine();
  fast.bandwidth_mb_per_s = 500.0;
  Capability slow = strong_machine();
  slow.bandwidth_mb_per_s = 0.05;
  slow.brick_latency_ms = 50.0;
  const Choice fast_choice = choose(fast, scene, 1280, 720);
  const Choice slow_choice = choose(slow, scene, 1280, 720);
  EXPECT_LT(slow_choice.start_level_log2, fast_choice.start_level_log2) << slow_choice.reason;
  EXPECT_EQ(slow_choice.finest_level_log2, fast_choice.finest_level_log2);
  EXPECT_LE(slow_choice.start_level_log2, slow_choice.finest_level_log2);
}

// A headless run's start may take as long as its time limit allows (soltex-view gives it half
// of --max-time-s): a link the window starts coarser on starts a headless run at the finest.
TEST(Choose, ALongerFetchBudgetStartsFiner) {
  Capability c = strong_machine();
  fit_link(timing(8, 0.001, 4e6), timing(64, 0.001, 4e6), c);
  const Choice window = choose(c, default_scene(), 1280, 720);
  ChoiceLimits headless;
  headless.scale_frame = false;
  headless.fetch_seconds = 15.0;
  const Choice run = choose(c, default_scene(), 1280, 720, headless);
  EXPECT_LT(window.start_level_log2, window.finest_level_log2) << window.reason;
  EXPECT_EQ(run.start_level_log2, run.finest_level_log2) << run.reason;
  EXPECT_EQ(run.finest_level_log2, window.finest_level_log2);
}

// Too little memory for a frame at the finest level: the cache budget, not the link, lowers
// where the run starts; the finest level stays the scene's, to be reached as far as the cache
// holds what each next level needs. More texels a pixel (anti-aliasing, a finer level bias)
// lower the start as a smaller cache does.
TEST(Choose, TheCacheBudgetBoundsWhereARunStarts) {
  const Scene scene = default_scene();
  Capability roomy = strong_machine();
  Capability small = strong_machine();
  small.available_memory_mb = 64;  // a 32 MiB cache
  const Choice in_roomy = choose(roomy, scene, 1280, 720);
  const Choice in_small = choose(small, scene, 1280, 720);
  EXPECT_EQ(in_small.finest_level_log2, in_roomy.finest_level_log2);
  EXPECT_LT(in_small.start_level_log2, in_roomy.start_level_log2) << in_small.reason;
  EXPECT_NE(in_small.reason.find("refines while the cache holds the next level"), std::string::npos)
      << in_small.reason;

  ChoiceLimits sixteen_texels;
  sixteen_texels.texels_per_pixel = 16.0;  // --antialias 4, or --level-bias -2
  Capability medium = strong_machine();
  medium.available_memory_mb = 2048;  // a 256 MiB cache
  EXPECT_LT(choose(medium, scene, 1280, 720, sixteen_texels).start_level_log2,
            choose(medium, scene, 1280, 720).start_level_log2);
}

// A model written far from its origin and drawn where it was written (no translate) gets the
// level of the same model centred and translated there: what counts is where the mesh is.
TEST(Choose, TheFinestLevelFollowsWhereTheMeshIsNotItsOrigin) {
  Scene scene = default_scene();
  scene.objects.resize(1);
  SceneObject& object = scene.objects[0];
  const glm::dvec3 far{1e5, 0.0, 0.0};
  scene.camera.position = far + glm::dvec3(0.0, 0.0, 3.0);
  scene.camera.target = far;
  object.transform = {};
  object.transform.translate = far;
  Capability c = strong_machine();
  const Choice translated = choose(c, scene, 1280, 720);

  Mesh written_there = *object.mesh;
  for (glm::vec3& p : written_there.positions) p += glm::vec3(far);
  written_there.update_bounds();
  object.mesh = std::make_shared<const Mesh>(std::move(written_there));
  object.transform.translate = glm::dvec3(0.0);
  const Choice in_place = choose(c, scene, 1280, 720);
  EXPECT_EQ(in_place.finest_level_log2, translated.finest_level_log2) << in_place.reason;
  EXPECT_GT(in_place.finest_level_log2, 6) << in_place.reason;
}

// A 20-unit floor in world space under a camera 1.2 above it, looking down its length.
Scene floor_scene(double height, double fov_y_degrees) {
  return parse_scene(R"({"camera": {"position": [0, )" + std::to_string(height) +
                         R"(, 9.5], "target": [0, 0, -10], "fov_y_degrees": )" +
                         std::to_string(fov_y_degrees) + R"(, "far": 1000},
    "objects": [{"name": "floor", "mesh": {"plane": {"size": 20}},
                 "material": {"texture": {"marble": {}}, "space": "world"}}]})",
                     "<floor scene>");
}

// The finest level gives a texel per pixel where the floor comes nearest (straight below the
// camera), not where its centre is: the texture volume's side (20 units padded by 1/16) over
// a pixel's width at that distance.
TEST(Choose, ATexelPerPixelWhereTheObjectComesNearest) {
  Capability c = strong_machine();
  ChoiceLimits headless;
  headless.scale_frame = false;
  for (const double height : {1.2, 12.0}) {
    const Choice choice = choose(c, floor_scene(height, 40.0), 480, 270, headless);
    const double pixel = 2.0 * height * std::tan(glm::radians(20.0)) / 270.0;
    const int expected = static_cast<int>(std::ceil(std::log2(20.0 * (1.0 + 2.0 / 32.0) / pixel)));
    EXPECT_EQ(choice.finest_level_log2, expected) << choice.reason;
  }
  // 1.2 above the floor: 2^13, where its centre's distance (about 10) would give 2^10.
  EXPECT_EQ(choose(c, floor_scene(1.2, 40.0), 480, 270, headless).finest_level_log2, 13);
}

// No finer than the format allows, however near the camera comes.
TEST(Choose, TheFinestLevelStaysWithinTheFormat) {
  Capability c = strong_machine();
  const Choice choice = choose(c, floor_scene(1e-3, 40.0), 1280, 720);
  EXPECT_EQ(choice.finest_level_log2, SpecLimits::kMaxFinestLevelLog2) << choice.reason;
  EXPECT_NE(choice.reason.find("at most 2^14"), std::string::npos) << choice.reason;
}

// A material that names its own finest level keeps it and does not set the others'.
TEST(Choose, AMaterialsOwnLevelDoesNotDriveTheChoice) {
  Capability c = strong_machine();
  Scene scene = floor_scene(1.2, 40.0);
  scene.objects[0].material.volume.finest_level_log2 = 9;
  EXPECT_EQ(choose(c, scene, 480, 270).finest_level_log2, 4);
}

TEST(Choose, HeadlessKeepsTheSizeAskedForAWindowShrinksToTheMachine) {
  const Scene scene = default_scene();
  Capability slow_cpu = strong_machine();
  slow_cpu.pixels_per_second = 2e6;  // 200000 pixels in the 100 ms a frame may take
  ChoiceLimits headless;
  headless.scale_frame = false;
  const Choice kept = choose(slow_cpu, scene, 1280, 720, headless);
  EXPECT_EQ(kept.width, 1280);
  EXPECT_EQ(kept.height, 720);
  const Choice window = choose(slow_cpu, scene, 1280, 720);
  EXPECT_LT(window.width, 1280);
  EXPECT_LT(window.height, 720);
}

}  // namespace
}  // namespace soltex::capability
