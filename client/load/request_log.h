#pragma once

#include <cstdint>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

// A recorded sequence of brick requests, as `soltex-view --record FILE` writes it and
// `soltex-load --mix replay --replay-file FILE` plays it back.
//
// Format (text, one request per line, whitespace-separated columns):
//
//   # soltex-request-log 1
//   # seconds level x y z priority
//   0.000000 4 0 0 0 100
//   0.016712 3 1 0 1 40
//
// - The first line is the header `# soltex-request-log 1` (1 is the format version).
// - Every other line is a request or a comment (`#` first) or empty.
// - seconds: time since the start of the recording, >= 0 and non-decreasing, written with
//   microsecond resolution (so a time reads back as the double nearest to its rounded value);
//   level: MIP level, 0 = finest; x, y, z: brick coordinate at that
//   level; priority: the BrickWant priority (larger is sooner).
// Texture ids are not recorded: a replay asks for the same bricks of whatever texture the
// replaying tool registered, so a log is not tied to one server.
namespace soltex::load {

struct RecordedRequest {
  double seconds = 0.0;
  int32_t level = 0;
  int32_t x = 0;
  int32_t y = 0;
  int32_t z = 0;
  int32_t priority = 0;

  friend bool operator==(const RecordedRequest&, const RecordedRequest&) = default;
};

inline constexpr const char* kRequestLogHeader = "# soltex-request-log 1";
// Times beyond this (about 31 years) are refused: they cannot come from a recording, and a
// bounded value always fits its column.
inline constexpr double kMaxRecordedSeconds = 1e9;
// A log is read whole into memory; this bounds what a file can make the reader hold.
inline constexpr std::size_t kMaxRecordedRequests = 10'000'000;

// A log that cannot be read or written; the message names the source and why.
class RequestLogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A malformed log, a tool's bad input: the message names the source, the line and what was
// wrong with it.
class RequestLogFormatError : public RequestLogError {
 public:
  using RequestLogError::RequestLogError;
};

// Writes the header at construction and one line per append().
class RequestLogWriter {
 public:
  explicit RequestLogWriter(std::ostream& out);
  // Throws RequestLogError when `request` breaks the rules above (negative or decreasing time,
  // negative level) or the stream fails.
  void append(const RecordedRequest& request);

 private:
  std::ostream& out_;
  double last_seconds_ = 0.0;
};

// Reads a whole log; `source` names it in error messages. Throws RequestLogFormatError for
// malformed contents, RequestLogError for a file that cannot be read.
std::vector<RecordedRequest> read_request_log(std::istream& in, const std::string& source);
std::vector<RecordedRequest> read_request_log_file(const std::string& path);
void write_request_log_file(const std::string& path, const std::vector<RecordedRequest>& requests);

}  // namespace soltex::load
