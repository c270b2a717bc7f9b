#pragma once

#include <filesystem>
#include <string>

#include "accuracy_run.h"

namespace soltex::bench {

// The sweep as a Markdown page: how it was measured, a row per setting, and the Pareto front
// read as "for this frame-time budget, this setting". `command` is how to run it again;
// `plot` is shown on the page (linked relative to it). Throws std::runtime_error naming the
// path when it cannot be written.
void write_markdown(const AccuracyRun& run, const std::string& command,
                    const std::filesystem::path& path, const std::filesystem::path& plot);

// The sweep as CSV: a header, then a row per setting, in plain units (ms, µs, bytes).
void write_csv(const AccuracyRun& run, const std::filesystem::path& path);

}  // namespace soltex::bench
