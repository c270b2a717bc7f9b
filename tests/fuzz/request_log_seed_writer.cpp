// Writes the starting corpus of request_log_fuzz: logs recorded with RequestLogWriter (as
// `soltex-view --record` writes them) and hand-written ones with what the reader also accepts:
// comments, blank lines, tabs, CRLF line ends, extreme 32-bit values and times in exponent form.
//
//   request_log_seed_writer <corpus-dir>
//
// It needs only the request-log format, so it builds wherever the fuzz target does.

#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "request_log.h"
#include "seed_file.h"

namespace {

using soltex::load::RecordedRequest;

std::string recorded(const std::vector<RecordedRequest>& requests) {
  std::ostringstream out;
  soltex::load::RequestLogWriter writer(out);
  for (const RecordedRequest& request : requests) writer.append(request);
  return out.str();
}

// A viewer's first frames: the coarsest brick, then finer ones around it.
std::vector<RecordedRequest> frames() {
  std::vector<RecordedRequest> requests;
  requests.push_back({0.0, 4, 0, 0, 0, 100});
  for (int frame = 1; frame <= 4; ++frame) {
    const double seconds = 0.016712 * frame;
    for (int brick = 0; brick < 3; ++brick) {
      requests.push_back({seconds, 4 - frame, brick, frame % 2, brick ^ frame, 100 - 10 * frame});
    }
  }
  return requests;
}

std::vector<RecordedRequest> extremes() {
  constexpr int32_t kMin = std::numeric_limits<int32_t>::min();
  constexpr int32_t kMax = std::numeric_limits<int32_t>::max();
  return {{0.0, 0, kMin, kMax, -1, kMin},
          {1e-6, kMax, 0, 0, 0, kMax},
          {86400.123456, 13, 8191, -8192, 4095, 0}};
}

struct NamedText {
  const char* name;
  std::string text;
};

}  // namespace

int main(int argc, char** argv) {
  return soltex::fuzz::seed_writer_main(argc, argv, {"corpus-dir"}, [](const auto& dirs) {
    const std::filesystem::path& dir = dirs[0];
    const std::string header = soltex::load::kRequestLogHeader;
    const NamedText seeds[] = {
        {"recorded-frames", recorded(frames())},
        {"recorded-extremes", recorded(extremes())},
        {"header-only", recorded({})},
        {"hand-written",
         header + "\n# seconds level x y z priority\n\n0 0 0 0 0 0\n  # indented comment\n"
                  "0.5\t1\t-2\t3\t-4\t5\n1e0 2 1 1 1 1\n2.5E+1   3 0 0 0 -7   \n"},
        {"crlf", header + "\r\n0.000000 4 0 0 0 100\r\n0.016712 3 1 0 1 40\r\n"},
        {"no-final-newline", header + "\n0.25 1 2 3 4 5"},
    };
    for (const NamedText& seed : seeds)
      soltex::fuzz::write_seed_file(dir / (std::string("seed-") + seed.name), seed.text);
    std::printf("wrote %zu seed logs to %s\n", std::size(seeds), dir.c_str());
  });
}
