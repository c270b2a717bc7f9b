#include "load_result.h"

namespace soltex::load {

const char* status_code_name(int code) {
  static const char* const kNames[17] = {"OK",
                                         "CANCELLED",
                                         "UNKNOWN",
                                         "INVALID_ARGUMENT",
                                         "DEADLINE_EXCEEDED",
                                         "NOT_FOUND",
                                         "ALREADY_EXISTS",
                                         "PERMISSION_DENIED",
                                         "RESOURCE_EXHAUSTED",
                                         "FAILED_PRECONDITION",
                                         "ABORTED",
                                         "OUT_OF_RANGE",
                                         "UNIMPLEMENTED",
                                         "INTERNAL",
                                         "UNAVAILABLE",
                                         "DATA_LOSS",
                                         "UNAUTHENTICATED"};
  return code >= 0 && code < 17 ? kNames[code] : "UNKNOWN";
}

LatencySummary LatencySummary::of(const LatencyHistogramSnapshot& snapshot) {
  LatencySummary s;
  s.count = snapshot.count();
  s.min = snapshot.min();
  s.mean = snapshot.mean();
  s.p50 = snapshot.value_at_percentile(50.0);
  s.p90 = snapshot.value_at_percentile(90.0);
  s.p99 = snapshot.value_at_percentile(99.0);
  s.p999 = snapshot.value_at_percentile(99.9);
  s.max = snapshot.max();
  s.buckets = snapshot.buckets();
  return s;
}

double LoadResult::bricks_per_second() const {
  return measured_seconds > 0.0 ? static_cast<double>(bricks) / measured_seconds : 0.0;
}

double LoadResult::megabytes_per_second() const {
  return measured_seconds > 0.0 ? static_cast<double>(bytes) / measured_seconds * 1e-6 : 0.0;
}

uint64_t LoadResult::measured_errors() const {
  uint64_t total = 0;
  for (uint64_t n : brick_errors) total += n;
  return total;
}

uint64_t LoadResult::stream_failures() const {
  uint64_t total = 0;
  for (std::size_t code = 1; code < stream_status.size(); ++code) total += stream_status[code];
  return total;
}

}  // namespace soltex::load
