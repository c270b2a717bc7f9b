#include "progress_bar.h"

#include <unistd.h>

#include <algorithm>

namespace soltex::bench {
namespace {

constexpr int kBarWidth = 20;

}  // namespace

ProgressBar::ProgressBar(int total, std::FILE* out)
    : total_(std::max(total, 1)), out_(out), terminal_(isatty(fileno(out)) != 0) {}

void ProgressBar::show(int done, const std::string& working_on) {
  const int filled = kBarWidth * std::clamp(done, 0, total_) / total_;
  const std::string bar = std::string(static_cast<std::size_t>(filled), '#') +
                          std::string(static_cast<std::size_t>(kBarWidth - filled), '.');
  std::fprintf(out_, terminal_ ? "\r[%s] %d/%d %s\033[K" : "[%s] %d/%d %s\n", bar.c_str(), done,
               total_, working_on.c_str());
  std::fflush(out_);
}

void ProgressBar::finish() {
  show(total_, "done");
  if (terminal_) std::fputc('\n', out_);
}

}  // namespace soltex::bench
