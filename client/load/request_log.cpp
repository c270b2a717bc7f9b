#include "request_log.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <istream>
#include <ostream>
#include <sstream>

namespace soltex::load {
namespace {

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

// Splits on spaces and tabs.
std::vector<std::string_view> columns(std::string_view line) {
  std::vector<std::string_view> result;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) result.push_back(line.substr(start, i - start));
  }
  return result;
}

template <typename T>
bool parse_number(std::string_view text, T& value) {
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  return result.ec == std::errc() && result.ptr == text.data() + text.size();
}

}  // namespace

RequestLogWriter::RequestLogWriter(std::ostream& out) : out_(out) {
  out_ << kRequestLogHeader << "\n# seconds level x y z priority\n";
  if (!out_) throw RequestLogError("request log: cannot write the header");
}

void RequestLogWriter::append(const RecordedRequest& request) {
  if (!(request.seconds >= last_seconds_) || !(request.seconds <= kMaxRecordedSeconds)) {
    throw RequestLogError(
        "request log: time " + std::to_string(request.seconds) +
        " s must be in [previous time, 1e9] (previous: " + std::to_string(last_seconds_) + " s)");
  }
  if (request.level < 0) {
    throw RequestLogError("request log: level " + std::to_string(request.level) + " must be >= 0");
  }
  last_seconds_ = request.seconds;
  char line[128];
  std::snprintf(line, sizeof line, "%.6f %d %d %d %d %d\n", request.seconds, request.level,
                request.x, request.y, request.z, request.priority);
  out_ << line;
  if (!out_) throw RequestLogError("request log: write failed");
}

std::vector<RecordedRequest> read_request_log(std::istream& in, const std::string& source) {
  std::vector<RecordedRequest> requests;
  std::string line;
  std::size_t number = 0;
  const auto fail = [&](const std::string& what) {
    throw RequestLogFormatError(source + ":" + std::to_string(number) + ": " + what);
  };
  if (!std::getline(in, line)) {
    number = 1;
    fail("empty; the first line must be \"" + std::string(kRequestLogHeader) + "\"");
  }
  number = 1;
  if (trim(line) != kRequestLogHeader) {
    fail("the first line must be \"" + std::string(kRequestLogHeader) + "\" (format version 1)");
  }
  double last_seconds = 0.0;
  while (std::getline(in, line)) {
    ++number;
    const std::string_view text = trim(line);
    if (text.empty() || text.front() == '#') continue;
    const std::vector<std::string_view> fields = columns(text);
    if (fields.size() != 6) {
      fail("expected 6 columns (seconds level x y z priority), found " +
           std::to_string(fields.size()));
    }
    RecordedRequest request;
    if (!parse_number(fields[0], request.seconds) || !(request.seconds >= 0.0) ||
        !(request.seconds <= kMaxRecordedSeconds)) {
      fail("seconds \"" + std::string(fields[0]) + "\" must be a number in [0, 1e9]");
    }
    if (request.seconds < last_seconds) {
      fail("seconds " + std::string(fields[0]) + " is below the previous line's " +
           std::to_string(last_seconds) + "; times must not decrease");
    }
    last_seconds = request.seconds;
    const char* names[] = {"level", "x", "y", "z", "priority"};
    int32_t* targets[] = {&request.level, &request.x, &request.y, &request.z, &request.priority};
    for (int i = 0; i < 5; ++i) {
      if (!parse_number(fields[static_cast<std::size_t>(i) + 1], *targets[i])) {
        fail(std::string(names[i]) + " \"" + std::string(fields[static_cast<std::size_t>(i) + 1]) +
             "\" must be a 32-bit integer");
      }
    }
    if (request.level < 0) fail("level " + std::to_string(request.level) + " must be >= 0");
    if (requests.size() >= kMaxRecordedRequests) {
      fail("more than " + std::to_string(kMaxRecordedRequests) +
           " requests (kMaxRecordedRequests)");
    }
    requests.push_back(request);
  }
  if (in.bad()) fail("read error");
  return requests;
}

std::vector<RecordedRequest> read_request_log_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw RequestLogError(path + ": cannot open for reading");
  return read_request_log(in, path);
}

void write_request_log_file(const std::string& path, const std::vector<RecordedRequest>& requests) {
  std::ofstream out(path);
  if (!out) throw RequestLogError(path + ": cannot open for writing");
  RequestLogWriter writer(out);
  for (const RecordedRequest& request : requests) writer.append(request);
  out.flush();
  if (!out) throw RequestLogError(path + ": write failed");
}

}  // namespace soltex::load
