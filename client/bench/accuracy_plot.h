#pragma once

#include <filesystem>

#include "accuracy_run.h"

namespace soltex::bench {

// Draws the sweep's plot from its CSV with plot_accuracy.py (matplotlib): PSNR against frame
// time, a point per distinct frame, the Pareto front and per-pixel evaluation for scale. The
// format follows the extension of `plot` (.svg, .png). Returns false, with the reason on stderr,
// when the plot could not be drawn: no Python, no matplotlib, no script, or the script failed.
bool write_plot(const AccuracyRun& run, const std::filesystem::path& csv,
                const std::filesystem::path& plot);

}  // namespace soltex::bench
