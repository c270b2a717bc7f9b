#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

// A log-linear latency histogram in the manner of HdrHistogram: integer values (nanoseconds)
// from 0 up to a configurable highest trackable value, with a configurable number of
// significant decimal digits.
//
// Layout: values are grouped by power of two, and each power-of-two range [2^k, 2^(k+1)) is
// split linearly into sub-buckets of equal width, as many as it takes to keep every bucket
// narrower than 10^-d of its lowest value (d = significant digits): 16 sub-buckets per range
// for d = 1, 128 for d = 2, 1024 for d = 3. Values below twice that count are kept exactly.
// A value and every value of its bucket are "equivalent": queries cannot tell them apart, so
// a reported value is within a relative 10^-d of a recorded one (1% at the default 2 digits).
//
// Recording is lock-free (relaxed std::atomic<uint64_t> counters), so many threads may record
// into one histogram. Queries on a histogram that is being recorded into see each counter at
// some recent value but not all counters at the same instant; take a snapshot() to ask several
// questions of one consistent state.
//
// An empty histogram reports count 0, min 0, max 0, mean 0 and 0 for every percentile.
namespace soltex {

// Values in [lower_bound, upper_bound] (both inclusive) are counted together.
struct HistogramBucket {
  uint64_t lower_bound = 0;
  uint64_t upper_bound = 0;
  uint64_t count = 0;

  friend bool operator==(const HistogramBucket&, const HistogramBucket&) = default;
};

// The bucket boundaries of a histogram configuration: maps values to counter indices and back.
class LatencyBucketLayout {
 public:
  // Throws std::invalid_argument unless 1 <= highest_trackable_value <= INT64_MAX and
  // 1 <= significant_digits <= 3.
  LatencyBucketLayout(uint64_t highest_trackable_value, int significant_digits);

  uint64_t highest_trackable_value() const { return highest_trackable_value_; }
  int significant_digits() const { return significant_digits_; }

  // Number of counters: enough for every value up to highest_trackable_value().
  std::size_t bucket_count() const { return bucket_count_; }

  // The counter a value falls in; value must be <= highest_trackable_value().
  std::size_t index_of(uint64_t value) const;
  uint64_t lowest_value_at(std::size_t index) const;
  uint64_t highest_value_at(std::size_t index) const;

  uint64_t lowest_equivalent_value(uint64_t value) const;
  uint64_t highest_equivalent_value(uint64_t value) const;

  friend bool operator==(const LatencyBucketLayout& a, const LatencyBucketLayout& b) {
    return a.highest_trackable_value_ == b.highest_trackable_value_ &&
           a.significant_digits_ == b.significant_digits_;
  }

 private:
  uint64_t highest_trackable_value_;
  int significant_digits_;
  int sub_bucket_half_count_magnitude_;  // log2 of the sub-buckets per power-of-two range
  uint64_t sub_bucket_half_count_;
  uint64_t sub_bucket_mask_;  // values under twice the half count are kept exactly
  std::size_t bucket_count_;
};

// A plain, non-atomic copy of a LatencyHistogram at one moment, for reporting.
class LatencyHistogramSnapshot {
 public:
  const LatencyBucketLayout& layout() const { return layout_; }

  uint64_t count() const { return total_count_; }
  uint64_t min() const { return total_count_ == 0 ? 0 : min_; }
  uint64_t max() const { return total_count_ == 0 ? 0 : max_; }
  // Exact: from the sum of the recorded (clamped) values, not from the buckets.
  double mean() const;
  uint64_t overflow_count() const { return overflow_count_; }

  // The smallest value v such that at least p% of the recorded values are equivalent to or
  // below v, reported as the highest value equivalent to it (HdrHistogram semantics), but
  // clamped to [min(), max()]: a report never shows a p99 above its max. p = 0 reports the
  // lowest value equivalent to min(), that is min(). Throws std::invalid_argument when p is NaN
  // or outside [0, 100].
  uint64_t value_at_percentile(double p) const;

  // Recorded values at or below `value`, counting whole buckets: values equivalent to `value`
  // count as below it. Exact when `value` is the upper bound of its bucket, so fixed boundaries
  // (Prometheus `le`) are best chosen with LatencyBucketLayout::highest_equivalent_value().
  uint64_t cumulative_count_at_or_below(uint64_t value) const;

  // The non-empty buckets in ascending order.
  std::vector<HistogramBucket> buckets() const;

 private:
  friend class LatencyHistogram;
  explicit LatencyHistogramSnapshot(const LatencyBucketLayout& layout);

  LatencyBucketLayout layout_;
  std::vector<uint64_t> counts_;
  uint64_t total_count_ = 0;
  uint64_t min_ = 0;
  uint64_t max_ = 0;
  uint64_t sum_ = 0;
  uint64_t overflow_count_ = 0;
};

class LatencyHistogram {
 public:
  static constexpr uint64_t kDefaultHighestTrackableValue = 3'600'000'000'000;  // 1 h in ns
  static constexpr int kDefaultSignificantDigits = 2;

  // Throws std::invalid_argument as LatencyBucketLayout does.
  explicit LatencyHistogram(uint64_t highest_trackable_value = kDefaultHighestTrackableValue,
                            int significant_digits = kDefaultSignificantDigits);
  LatencyHistogram(const LatencyHistogram&) = delete;
  LatencyHistogram& operator=(const LatencyHistogram&) = delete;

  const LatencyBucketLayout& layout() const { return layout_; }
  uint64_t highest_trackable_value() const { return layout_.highest_trackable_value(); }
  int significant_digits() const { return layout_.significant_digits(); }

  // Records `count` occurrences of `value`. A value above highest_trackable_value() is
  // recorded as highest_trackable_value() and also counted in overflow_count(). Safe to call
  // from any number of threads at once. The exact sum behind mean() wraps after 2^64 ns
  // (584 years) of recorded time.
  void record(uint64_t value, uint64_t count = 1) noexcept;

  // Adds other's recordings to this one. Throws std::invalid_argument unless both have the
  // same highest trackable value and significant digits. Safe alongside record() on either.
  void merge(const LatencyHistogram& other);

  // Forgets everything recorded. Not atomic: a record() running concurrently may be partly
  // kept (e.g. counted in its bucket but not in min()).
  void reset() noexcept;

  // The queries below read the live counters; see the note at the top of this file.
  uint64_t count() const;
  uint64_t min() const;
  uint64_t max() const;
  double mean() const;
  uint64_t overflow_count() const { return overflow_count_.load(std::memory_order_relaxed); }
  // As LatencyHistogramSnapshot's namesakes.
  uint64_t value_at_percentile(double p) const;
  uint64_t cumulative_count_at_or_below(uint64_t value) const;
  std::vector<HistogramBucket> buckets() const;

  LatencyHistogramSnapshot snapshot() const;

 private:
  void update_min(uint64_t value) noexcept;
  void update_max(uint64_t value) noexcept;

  LatencyBucketLayout layout_;
  std::unique_ptr<std::atomic<uint64_t>[]> counts_;
  std::atomic<uint64_t> min_;
  std::atomic<uint64_t> max_{0};
  std::atomic<uint64_t> sum_{0};
  std::atomic<uint64_t> overflow_count_{0};
};

}  // namespace soltex
