#pragma once

#include <cstdio>
#include <string>

namespace soltex {

// The progress line of the command-line tools (soltex-load, soltex-bench), on stderr while a
// long run goes on, e.g.
//   [#####...............] 12/40 level=7 filter=trilinear
//   [    3.0 s] 12345 bricks  4115 bricks/s  0 errors
// On a terminal the line is redrawn in place; into a file or a pipe (a test log) every update
// is a line of its own, since a carriage return there would hide all but the last.
class ProgressBar {
 public:
  // With a total, show(done, ...) draws a bar of done/total; without one, show(text) alone.
  explicit ProgressBar(int total = 0, std::FILE* out = stderr);

  // Replaces the line with `text`.
  void show(const std::string& text);
  // Replaces the line with a bar of `done` of the total and what is being worked on now.
  void show(int done, const std::string& working_on);
  // Ends the line: with a total, first shows everything finished. Once; later calls do nothing.
  void finish();

 private:
  int total_;
  std::FILE* out_;
  bool terminal_;
  bool open_ = false;  // a line is on a terminal, not yet ended
};

}  // namespace soltex
