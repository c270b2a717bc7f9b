#pragma once

#include <cstdio>
#include <string>

namespace soltex::bench {

// A progress line on stderr while a long sweep runs, e.g.
//   [#####...............] 12/40 level=7 filter=trilinear
// redrawn in place on a terminal; into a file or pipe (a test log) one line per step.
class ProgressBar {
 public:
  ProgressBar(int total, std::FILE* out = stderr);

  // Shows `done` of the total finished and what is being worked on now.
  void show(int done, const std::string& working_on);
  // Shows everything finished and ends the line.
  void finish();

 private:
  int total_;
  std::FILE* out_;
  bool terminal_;
};

}  // namespace soltex::bench
