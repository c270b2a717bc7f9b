#include "accuracy_plot.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <string>
#include <system_error>
#include <vector>

#include "number_format.h"

extern char** environ;

namespace soltex::bench {
namespace {

constexpr const char* kScript = "plot_accuracy.py";
constexpr int kNoMatplotlib = 3;  // plot_accuracy.py's exit code when matplotlib is missing

// Beside the binary (the build copies it there), in an installed tree's share/soltex, or in
// the source tree the binary was built from.
std::filesystem::path find_script() {
  std::error_code error;
  const std::filesystem::path binary = std::filesystem::read_symlink("/proc/self/exe", error);
  std::vector<std::filesystem::path> candidates;
  if (!error) {
    candidates.push_back(binary.parent_path() / kScript);
    candidates.push_back(binary.parent_path().parent_path() / "share" / "soltex" / kScript);
  }
  candidates.push_back(std::filesystem::path(SOLTEX_BENCH_SOURCE_DIR) / kScript);
  for (const std::filesystem::path& candidate : candidates) {
    if (std::filesystem::is_regular_file(candidate, error)) return candidate;
  }
  return {};
}

std::string point_text(const FrameTime& time, double psnr) {
  return fixed(time.median_ms, 3) + "," + fixed(time.q1_ms, 3) + "," + fixed(time.q3_ms, 3) + "," +
         fixed(psnr, 3);
}

// Runs `argv` (argv[0] a path) and returns its exit status; -1 when it could not be started.
int run_program(const std::vector<std::string>& argv) {
  std::vector<char*> pointers;
  for (const std::string& arg : argv) pointers.push_back(const_cast<char*>(arg.c_str()));
  pointers.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, pointers[0], nullptr, nullptr, pointers.data(), environ) != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  // The shell's convention: 127 when exec failed in the child.
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace

bool write_plot(const AccuracyRun& run, const std::filesystem::path& csv,
                const std::filesystem::path& plot) {
  const std::filesystem::path script = find_script();
  if (script.empty()) {
    std::fprintf(stderr, "soltex-bench: no plot: %s is neither beside soltex-bench nor in %s\n",
                 kScript, SOLTEX_BENCH_SOURCE_DIR);
    return false;
  }
  const bool cpu = run.options.front_clock == FrameClock::cpu;
  const std::vector<std::string> argv = {
      SOLTEX_PLOT_PYTHON,
      script.string(),
      csv.string(),
      plot.string(),
      "--clock",
      cpu ? "cpu" : "wall",
      "--title",
      "What accuracy costs: " + run.scene_name + ", " + std::to_string(run.options.size.width) +
          "x" + std::to_string(run.options.size.height),
      "--note",
      "PSNR against per-pixel evaluation, " + std::to_string(run.reference_supersample) + "x" +
          std::to_string(run.reference_supersample) + " supersampled.",
      "--note",
      "Shared machine: " + run.machine + "; 1-minute load average " + fixed(run.load_before, 1) +
          " at the start, " + fixed(run.load_after, 1) + " at the end.",
      "--per-pixel",
      point_text(per_pixel_front_time(run), run.per_pixel_error.psnr_db)};
  if (plot.has_parent_path()) std::filesystem::create_directories(plot.parent_path());
  const int status = run_program(argv);
  if (status == 0) return true;
  if (status == -1 || status == 127) {
    std::fprintf(stderr, "soltex-bench: no plot: cannot run %s (Debian: python3)\n",
                 SOLTEX_PLOT_PYTHON);
  } else if (status == kNoMatplotlib) {
    std::fprintf(stderr,
                 "soltex-bench: no plot: %s has no matplotlib (Debian: python3-matplotlib); "
                 "the table and the CSV are written\n",
                 SOLTEX_PLOT_PYTHON);
  } else {
    std::fprintf(stderr, "soltex-bench: no plot: %s %s failed with status %d\n", SOLTEX_PLOT_PYTHON,
                 script.c_str(), status);
  }
  return false;
}

}  // namespace soltex::bench
