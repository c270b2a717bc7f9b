#pragma once

#include <string>

#include "load_generator.h"
#include "load_result.h"

// A run's result as an operator reads it (text, in the manner of ghz) or as tools read it
// (JSON with every counter and the latency histogram's buckets; CSV: a header and one row,
// so the rows of several runs can be concatenated).
namespace soltex::load {

std::string format_text(const LoadResult& result);
std::string format_json(const LoadResult& result);
std::string format_csv(const LoadResult& result);
std::string format_result(const LoadResult& result, OutputFormat format);

// One progress line, e.g. "[   3.0 s] 12345 bricks  4115 bricks/s  0 errors".
std::string format_progress(const ProgressLine& line);

}  // namespace soltex::load
