#include "progress_bar.h"

#include <unistd.h>

#include <algorithm>

namespace soltex {
namespace {

constexpr int kBarWidth = 20;

}  // namespace

ProgressBar::ProgressBar(int total, std::FILE* out)
    : total_(std::max(total, 0)), out_(out), terminal_(isatty(fileno(out)) != 0) {}

void ProgressBar::show(const std::string& text) {
  // \033[K clears what a longer earlier line left to the right.
  std::fprintf(out_, terminal_ ? "\r%s\033[K" : "%s\n", text.c_str());
  std::fflush(out_);
  open_ = terminal_;
}

void ProgressBar::show(int done, const std::string& working_on) {
  const int total = std::max(total_, 1);
  const int filled = kBarWidth * std::clamp(done, 0, total) / total;
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "[" + std::string(...).
  std::string line = "[";
  line.append(static_cast<std::size_t>(filled), '#')
      .append(static_cast<std::size_t>(kBarWidth - filled), '.')
      .append("] ")
      .append(std::to_string(done))
      .append("/")
      .append(std::to_string(total_))
      .append(" ")
      .append(working_on);
  show(line);
}

void ProgressBar::finish() {
  if (total_ > 0) {
    show(total_, "done");
    total_ = 0;  // a second finish() shows nothing more
  }
  if (open_) std::fputc('\n', out_);
  open_ = false;
}

}  // namespace soltex
