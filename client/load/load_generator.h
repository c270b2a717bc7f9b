#pragma once

#include <functional>
#include <stdexcept>

#include "load_options.h"
#include "load_result.h"

namespace soltex::load {

// Once per second while a run goes on.
struct ProgressLine {
  double elapsed_seconds = 0.0;
  bool warmup = false;
  bool draining = false;           // past the stop, waiting for answers still owed
  uint64_t bricks = 0;             // whole run so far
  double bricks_per_second = 0.0;  // over the last interval
  uint64_t errors = 0;
};

using ProgressCallback = std::function<void(const ProgressLine&)>;

// The run could not start: no connection, registration refused, unreadable replay log.
class LoadSetupError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Connects, registers the texture, runs the load until its stop condition, drains (bounded
// by the drain timeout) and returns what was measured. Throws LoadOptionsError for invalid
// options and LoadSetupError when the run cannot start.
LoadResult run_load(LoadOptions options, const ProgressCallback& progress = {});

}  // namespace soltex::load
