// libFuzzer target for the request-log reader: any input either throws RequestLogError or
// gives requests that keep the format's rules (times finite, non-negative and non-decreasing,
// levels non-negative, at most kMaxRecordedRequests). What was read must survive a round trip
// through RequestLogWriter: written and read again, it gives the same requests, with each time
// rounded to the microsecond as the format documents.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "request_log.h"

namespace {

using soltex::load::RecordedRequest;
using soltex::load::RequestLogError;

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "request_log_fuzz: %s\n", what.c_str());
  std::abort();
}

void check_rules(const std::vector<RecordedRequest>& requests) {
  if (requests.size() > soltex::load::kMaxRecordedRequests) fail("more than kMaxRecordedRequests");
  double last_seconds = 0.0;
  for (const RecordedRequest& request : requests) {
    if (!std::isfinite(request.seconds) || request.seconds < last_seconds) {
      fail("a time that is not finite or decreases");
    }
    if (request.level < 0) fail("a negative level");
    last_seconds = request.seconds;
  }
}

std::string written(const std::vector<RecordedRequest>& requests) {
  std::ostringstream out;
  soltex::load::RequestLogWriter writer(out);
  for (const RecordedRequest& request : requests) writer.append(request);
  return out.str();
}

std::vector<RecordedRequest> read(const std::string& text, const char* source) {
  std::istringstream in(text);
  return soltex::load::read_request_log(in, source);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  std::vector<RecordedRequest> requests;
  try {
    requests = read(std::string(reinterpret_cast<const char*>(data), size), "fuzz");
  } catch (const RequestLogError&) {
    return 0;
  }
  check_rules(requests);

  // From here on a RequestLogError escapes and is a finding: the writer must accept and the
  // reader must read back whatever the reader accepted.
  const std::string text = written(requests);
  const std::vector<RecordedRequest> again = read(text, "fuzz round trip");
  if (again.size() != requests.size()) fail("the round trip changed the number of requests");
  for (std::size_t i = 0; i < requests.size(); ++i) {
    RecordedRequest expected = requests[i];
    char rounded[512];
    std::snprintf(rounded, sizeof rounded, "%.6f", expected.seconds);
    expected.seconds = std::strtod(rounded, nullptr);
    if (again[i] != expected) {
      fail("request " + std::to_string(i) + " changed in the round trip: time " +
           std::to_string(requests[i].seconds) + " read back as " +
           std::to_string(again[i].seconds));
    }
  }
  // Written once, a log is a fixed point.
  if (written(again) != text) fail("writing the log read back gives different text");
  return 0;
}
