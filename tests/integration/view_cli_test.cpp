// soltex-view as a user runs it, against a real soltexd on loopback: what it writes and the
// exit code it ends with (README.md, "Exit codes").
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "soltexd_process.h"

#ifndef SOLTEX_VIEW_BINARY
#error "SOLTEX_VIEW_BINARY must name the soltex-view executable"
#endif

namespace soltex {
namespace {

using testing::SoltexdProcess;

struct ViewRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr
  std::filesystem::path image;
};

class ViewCli : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() /
                 ("soltex-view-cli-" + std::to_string(getpid()) + "-" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  // Runs soltex-view with `args` (and --out NAME.png) until it exits (at most 120 s).
  ViewRun view(const std::string& name, std::vector<std::string> args) {
    ViewRun run;
    run.image = directory_ / (name + ".png");
    const std::filesystem::path log = directory_ / (name + ".log");
    args.insert(args.begin(), SOLTEX_VIEW_BINARY);
    args.push_back("--out");
    args.push_back(run.image.string());
    pid_t pid = testing::spawn_process(args, log.string());
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    int status = 0;
    while (waitpid(pid, &status, WNOHANG) != pid) {
      if (std::chrono::steady_clock::now() > deadline) {
        testing::kill_and_reap(pid);
        ADD_FAILURE() << "soltex-view " << name << " did not finish within 120 s";
        return run;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(log);
    run.output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return run;
  }

  std::filesystem::path directory_;
};

std::vector<uint8_t> file_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A PNG's size from its IHDR chunk (bytes 16..23, big-endian); {0, 0} when not a PNG.
std::pair<uint32_t, uint32_t> png_size(const std::filesystem::path& path) {
  const std::vector<uint8_t> bytes = file_bytes(path);
  if (bytes.size() < 24 || bytes[1] != 'P' || bytes[2] != 'N' || bytes[3] != 'G') return {0, 0};
  const auto be32 = [&](std::size_t at) {
    return (uint32_t{bytes[at]} << 24) | (uint32_t{bytes[at + 1]} << 16) |
           (uint32_t{bytes[at + 2]} << 8) | uint32_t{bytes[at + 3]};
  };
  return {be32(16), be32(20)};
}

const std::vector<std::string> kSmall = {"--headless", "--width",      "160", "--height",
                                         "90",         "--max-time-s", "90"};

std::vector<std::string> against(const SoltexdProcess& server,
                                 std::vector<std::string> extra = {}) {
  std::vector<std::string> args = kSmall;
  args.push_back("--server");
  args.push_back(server.grpc_address());
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// Every brick 50 ms late: the client starts coarser, refines once idle, and converges to the
// picture a fast server gives, byte for byte; so does a client told its link is very thin.
TEST_F(ViewCli, ADelayedServerConvergesToTheUndelayedPicture) {
  SoltexdProcess fast;
  const ViewRun undelayed = view("undelayed", against(fast));
  ASSERT_EQ(undelayed.exit_code, 0) << undelayed.output;

  SoltexdProcess slow({"--fault-delay-ms", "50"});
  const ViewRun delayed = view("delayed", against(slow));
  ASSERT_EQ(delayed.exit_code, 0) << delayed.output;
  EXPECT_TRUE(file_bytes(delayed.image) == file_bytes(undelayed.image)) << delayed.output;

  const ViewRun thin = view("thin", against(slow, {"--capability", "bandwidth=0.01"}));
  ASSERT_EQ(thin.exit_code, 0) << thin.output;
  EXPECT_NE(thin.output.find("levels:     started at 2^"), std::string::npos) << thin.output;
  EXPECT_TRUE(file_bytes(thin.image) == file_bytes(undelayed.image)) << thin.output;
}

// Every codec brings the same samples: the picture is the same byte for byte whichever the
// link probe picks (auto) or --codec forces, and the log says which travelled.
TEST_F(ViewCli, EveryCodecConvergesToTheSamePicture) {
  SoltexdProcess server;
  const ViewRun zstd = view("codec-zstd", against(server, {"--codec", "zstd"}));
  ASSERT_EQ(zstd.exit_code, 0) << zstd.output;
  EXPECT_NE(zstd.output.find("codec: zstd (--codec)"), std::string::npos) << zstd.output;
  for (const char* codec : {"auto", "lz4", "raw"}) {
    const ViewRun run = view(std::string("codec-") + codec, against(server, {"--codec", codec}));
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_TRUE(file_bytes(run.image) == file_bytes(zstd.image)) << run.output;
  }
}

// --timeline prints the start's steps in the order they happened: the stream, the first frame
// and the requests for its misses, the batches of bricks, the converged frame.
TEST_F(ViewCli, TimelineShowsTheStartStepByStep) {
  SoltexdProcess server;
  const ViewRun run = view("timeline", against(server, {"--timeline"}));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string& out = run.output;
  std::size_t at = 0;
  EXPECT_NE(out.find("brick stream open"), std::string::npos) << out;
  for (const char* step :
       {"timeline: origin at", "frame 1 starts", "frame 1 ends", "frame 2 starts", "converged"}) {
    const std::size_t found = out.find(step, at);
    ASSERT_NE(found, std::string::npos) << "no '" << step << "' after byte " << at << ":\n" << out;
    at = found;
  }
  // The first frame's misses are asked for while it is drawn (the writer thread may get to
  // them only after it ends); bricks come in during it or after.
  const std::size_t first_frame = out.find("frame 1 starts");
  EXPECT_NE(out.find("bricks wanted", first_frame), std::string::npos) << out;
  EXPECT_NE(out.find("batch received", first_frame), std::string::npos) << out;
  const ViewRun quiet = view("no-timeline", against(server));
  ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find("timeline:"), std::string::npos) << quiet.output;
}

// The output is the size asked for, however slow this machine measures.
TEST_F(ViewCli, HeadlessKeepsTheRequestedImageSize) {
  const ViewRun scene_size = view(
      "scene-size", {"--headless", "--local", "--capability", "cpu=0.001", "--finest-level", "6"});
  ASSERT_EQ(scene_size.exit_code, 0) << scene_size.output;
  EXPECT_EQ(png_size(scene_size.image), std::make_pair(1280u, 720u));  // the default scene's

  const ViewRun asked = view("asked", {"--headless", "--local", "--capability", "cpu=0.001",
                                       "--width", "123", "--height", "45"});
  ASSERT_EQ(asked.exit_code, 0) << asked.output;
  EXPECT_EQ(png_size(asked.image), std::make_pair(123u, 45u));
}

// Every brick arrives corrupt: the picture is written from what it has, and the run fails.
TEST_F(ViewCli, BricksFailingForGoodExitThree) {
  SoltexdProcess corrupt({"--fault-corrupt-every", "1"});
  const ViewRun run = view("corrupt", against(corrupt));
  EXPECT_EQ(run.exit_code, 3) << run.output;
  EXPECT_NE(run.output.find("NOT converged"), std::string::npos) << run.output;
  EXPECT_TRUE(std::filesystem::exists(run.image));
}

TEST_F(ViewCli, RunningOutOfTimeExitsThree) {
  const ViewRun run =
      view("timeout", {"--headless", "--local", "--finest-level", "10", "--max-time-s", "0.1"});
  EXPECT_EQ(run.exit_code, 3) << run.output;
  EXPECT_NE(run.output.find("NOT converged within"), std::string::npos) << run.output;
}

// The log names the level the run uses: --finest-level's, with the machine's choice beside it.
TEST_F(ViewCli, TheLogSaysTheFinestLevelTheRunUses) {
  const ViewRun run = view("finest-9", {"--headless", "--local", "--width", "160", "--height", "90",
                                        "--finest-level", "9"});
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("choice: finest level 2^9: --finest-level (this machine's choice"),
            std::string::npos)
      << run.output;
}

// A material's own finest level is the scene's: the summary names it beside the client's, and
// --finest-level says it is not used where every material sets one.
TEST_F(ViewCli, LevelsTheSceneSetsAreNamedAndKept) {
  const auto scene_with = [&](const std::string& name, const std::string& second_volume) {
    const std::filesystem::path scene = directory_ / (name + ".json");
    std::ofstream(scene) << R"({"camera": {"position": [0, 1, 4], "target": [0, 0, 0]},
      "objects": [
        {"mesh": {"sphere": {}}, "transform": {"translate": [-1.2, 0, 0]},
         "material": {"texture": {"marble": {}}, "volume": {"finest_level_log2": 6}}},
        {"mesh": {"sphere": {}}, "transform": {"translate": [1.2, 0, 0]},
         "material": {"texture": {"checker": {}})"
                         << second_volume << "}}]}";
    return scene.string();
  };
  const std::vector<std::string> small = {"--headless", "--local", "--width",        "96",
                                          "--height",   "64",      "--finest-level", "7"};
  std::vector<std::string> every = small;
  every.insert(every.end(),
               {"--scene", scene_with("every", R"(, "volume": {"finest_level_log2": 5})")});
  const ViewRun pinned = view("every", every);
  EXPECT_EQ(pinned.exit_code, 0) << pinned.output;
  EXPECT_NE(pinned.output.find("finest level 2^5, 2^6, set by every material"), std::string::npos)
      << pinned.output;
  EXPECT_NE(pinned.output.find("--finest-level 7 is not used"), std::string::npos) << pinned.output;
  std::vector<std::string> one = small;
  one.insert(one.end(), {"--scene", scene_with("one", "")});
  const ViewRun mixed = view("one", one);
  EXPECT_EQ(mixed.exit_code, 0) << mixed.output;
  EXPECT_NE(mixed.output.find("finest level 2^7; 2^6 where a material sets its own"),
            std::string::npos)
      << mixed.output;
  EXPECT_EQ(mixed.output.find("is not used"), std::string::npos) << mixed.output;
}

// Options typed for a run that does not read them are named in a warning; the run goes on.
TEST_F(ViewCli, OptionsThisRunDoesNotReadAreNamed) {
  const ViewRun run = view("unused", {"--headless", "--local", "--width", "64", "--height", "48",
                                      "--supersample", "2", "--codec", "raw"});
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("without --reference it is not used"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("--local draws without a server: --codec is not used"),
            std::string::npos)
      << run.output;
}

std::string file_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST_F(ViewCli, BadInputExitsTwo) {
  EXPECT_EQ(view("brick-size", {"--headless", "--local", "--brick-size", "12"}).exit_code, 2);
  EXPECT_EQ(view("unknown", {"--headless", "--local", "--no-such-option"}).exit_code, 2);
  EXPECT_EQ(view("no-scene", {"--headless", "--local", "--scene", "/no/such/scene.json"}).exit_code,
            2);
  EXPECT_EQ(view("no-server", {"--headless"}).exit_code, 2);
  EXPECT_EQ(view("capability", {"--headless", "--local", "--capability", "cpu=-1"}).exit_code, 2);
  // Below one brick of 16 on a side; 3 is one brick of 8.
  const ViewRun coarse = view("finest-level", {"--headless", "--local", "--finest-level", "3"});
  EXPECT_EQ(coarse.exit_code, 2);
  EXPECT_NE(coarse.output.find("--brick-size 16, 4"), std::string::npos) << coarse.output;

  const std::filesystem::path scene = directory_ / "bad.json";
  std::ofstream(scene)
      << R"({"image": {"width": 64, "height": 64}, "objects": [{"mesh": "cube"}]})";
  const ViewRun bad_scene = view("bad-scene", {"--headless", "--local", "--scene", scene.string()});
  EXPECT_EQ(bad_scene.exit_code, 2) << bad_scene.output;

  // Files the run would lose: --record over the scene it reads or the image it writes.
  const std::string scene_before = file_text(scene);
  const ViewRun record_scene = view("record-scene", {"--headless", "--local", "--scene",
                                                     scene.string(), "--record", scene.string()});
  EXPECT_EQ(record_scene.exit_code, 2) << record_scene.output;
  EXPECT_EQ(file_text(scene), scene_before) << "the scene was overwritten";
  const std::string png = (directory_ / "same.png").string();
  EXPECT_EQ(view("record-out", {"--headless", "--local", "--out", png, "--record", png}).exit_code,
            2);
  // A client certificate without its key, or without TLS: the command line's fault.
  const ViewRun half_tls =
      view("half-tls", {"--headless", "--server", "127.0.0.1:1", "--tls-cert", scene.string()});
  EXPECT_EQ(half_tls.exit_code, 2) << half_tls.output;
  EXPECT_NE(half_tls.output.find("--tls-cert and --tls-key go together"), std::string::npos)
      << half_tls.output;
  // Sub-pixels beyond the rasterizer's side, refused naming the option and what fits.
  const ViewRun huge = view(
      "huge", {"--headless", "--local", "--width", "4097", "--height", "100", "--antialias", "4"});
  EXPECT_EQ(huge.exit_code, 2) << huge.output;
  EXPECT_NE(huge.output.find("give --antialias 3 or less"), std::string::npos) << huge.output;

  EXPECT_EQ(view("help", {"--help"}).exit_code, 0);
}

}  // namespace
}  // namespace soltex
