#pragma once

#include <filesystem>

#include "accuracy_run.h"

namespace soltex::bench {

// The sweep as an SVG scatter plot, written by hand (no plotting dependency): PSNR (up is
// better) against warm ms/frame (left is faster), a labelled point per distinct frame, the
// Pareto front drawn as a line through its marked points, and per-pixel evaluation without
// the cache as a separate marker for scale. Throws std::runtime_error naming the path when it
// cannot be written.
void write_plot(const AccuracyRun& run, const std::filesystem::path& path);

}  // namespace soltex::bench
