#include "soltex/common/latency_histogram.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace soltex {
namespace {

constexpr auto kRelaxed = std::memory_order_relaxed;

// min_ before anything is recorded; no recorded value can equal it (values are clamped to
// highest_trackable_value() <= INT64_MAX).
constexpr uint64_t kNoMinimum = std::numeric_limits<uint64_t>::max();

constexpr uint64_t kMaxHighestTrackableValue =
    static_cast<uint64_t>(std::numeric_limits<int64_t>::max());

// Shortest text that reads back as the same double, so a message shows 100.00000000000001 as
// such rather than as a rounded "100".
std::string shortest_text(double value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

uint64_t pow10(int exponent) {
  uint64_t result = 1;
  for (int i = 0; i < exponent; ++i) result *= 10;
  return result;
}

}  // namespace

// ---- LatencyBucketLayout -------------------------------------------------------------------

LatencyBucketLayout::LatencyBucketLayout(uint64_t highest_trackable_value, int significant_digits)
    : highest_trackable_value_(highest_trackable_value), significant_digits_(significant_digits) {
  if (significant_digits < 1 || significant_digits > 3) {
    throw std::invalid_argument("LatencyHistogram: significant_digits = " +
                                std::to_string(significant_digits) + ": must be in [1, 3]");
  }
  if (highest_trackable_value < 1 || highest_trackable_value > kMaxHighestTrackableValue) {
    throw std::invalid_argument(
        "LatencyHistogram: highest_trackable_value = " + std::to_string(highest_trackable_value) +
        ": must be in [1, " + std::to_string(kMaxHighestTrackableValue) + "]");
  }
  // As HdrHistogram: single-unit resolution up to 2 * 10^d gives every wider bucket a width
  // of at most 10^-d of its lowest value.
  const uint64_t largest_exact_value = 2 * pow10(significant_digits);
  const int sub_bucket_count_magnitude = std::bit_width(largest_exact_value - 1);
  sub_bucket_half_count_magnitude_ = sub_bucket_count_magnitude - 1;
  sub_bucket_half_count_ = uint64_t{1} << sub_bucket_half_count_magnitude_;
  sub_bucket_mask_ = (uint64_t{1} << sub_bucket_count_magnitude) - 1;
  bucket_count_ = index_of(highest_trackable_value) + 1;
}

std::size_t LatencyBucketLayout::index_of(uint64_t value) const {
  // The power-of-two group: 0 for values kept exactly, then one per doubling.
  const int group =
      63 - sub_bucket_half_count_magnitude_ - std::countl_zero(value | sub_bucket_mask_);
  const uint64_t sub_bucket = value >> group;  // in [half count, 2 * half count) when group > 0
  return (static_cast<std::size_t>(group + 1) << sub_bucket_half_count_magnitude_) +
         static_cast<std::size_t>(sub_bucket - sub_bucket_half_count_);
}

uint64_t LatencyBucketLayout::lowest_value_at(std::size_t index) const {
  const int group = static_cast<int>(index >> sub_bucket_half_count_magnitude_) - 1;
  const uint64_t sub_bucket = (index & (sub_bucket_half_count_ - 1)) + sub_bucket_half_count_;
  // Group 0 spans both halves of the sub-bucket range at unit width.
  if (group < 0) return sub_bucket - sub_bucket_half_count_;
  return sub_bucket << group;
}

uint64_t LatencyBucketLayout::highest_value_at(std::size_t index) const {
  const int group = std::max(static_cast<int>(index >> sub_bucket_half_count_magnitude_) - 1, 0);
  return lowest_value_at(index) + ((uint64_t{1} << group) - 1);
}

uint64_t LatencyBucketLayout::lowest_equivalent_value(uint64_t value) const {
  return lowest_value_at(index_of(value));
}

uint64_t LatencyBucketLayout::highest_equivalent_value(uint64_t value) const {
  return highest_value_at(index_of(value));
}

// ---- LatencyHistogramSnapshot --------------------------------------------------------------

LatencyHistogramSnapshot::LatencyHistogramSnapshot(const LatencyBucketLayout& layout)
    : layout_(layout), counts_(layout.bucket_count(), 0) {}

double LatencyHistogramSnapshot::mean() const {
  if (total_count_ == 0) return 0.0;
  return static_cast<double>(sum_) / static_cast<double>(total_count_);
}

uint64_t LatencyHistogramSnapshot::value_at_percentile(double p) const {
  if (!(p >= 0.0 && p <= 100.0)) {
    throw std::invalid_argument("LatencyHistogram::value_at_percentile: p = " + shortest_text(p) +
                                ": must be in [0, 100]");
  }
  if (total_count_ == 0) return 0;
  // The rank of the wanted value, rounded up so that p% of the values are at or below it.
  // Shaved by a few ulps first: p is decimal, and 99.9% of 1000 must give rank 999, not the
  // 1000 that binary rounding of 999.0000000000001 would.
  const double exact_rank = p / 100.0 * static_cast<double>(total_count_);
  const double rank = std::ceil(exact_rank * (1.0 - 4 * std::numeric_limits<double>::epsilon()));
  const uint64_t wanted = std::clamp(static_cast<uint64_t>(rank), uint64_t{1}, total_count_);
  uint64_t seen = 0;
  for (std::size_t i = 0; i < counts_.size(); ++i) {
    seen += counts_[i];
    if (seen < wanted) continue;
    // A bucket's bound, but never past the values recorded: the top bucket's bound is above
    // the largest value, which a p99 must not report as more than the max.
    const uint64_t bound = p == 0.0 ? layout_.lowest_value_at(i) : layout_.highest_value_at(i);
    return std::clamp(bound, min(), max());
  }
  return layout_.highest_value_at(counts_.size() - 1);  // unreachable: counts sum to the total
}

uint64_t LatencyHistogramSnapshot::cumulative_count_at_or_below(uint64_t value) const {
  if (value >= layout_.highest_trackable_value()) return total_count_;
  const std::size_t last = layout_.index_of(value);
  uint64_t total = 0;
  for (std::size_t i = 0; i <= last; ++i) total += counts_[i];
  return total;
}

std::vector<HistogramBucket> LatencyHistogramSnapshot::buckets() const {
  std::vector<HistogramBucket> result;
  for (std::size_t i = 0; i < counts_.size(); ++i) {
    if (counts_[i] == 0) continue;
    result.push_back({layout_.lowest_value_at(i), layout_.highest_value_at(i), counts_[i]});
  }
  return result;
}

// ---- LatencyHistogram ----------------------------------------------------------------------

LatencyHistogram::LatencyHistogram(uint64_t highest_trackable_value, int significant_digits)
    : layout_(highest_trackable_value, significant_digits),
      counts_(std::make_unique<std::atomic<uint64_t>[]>(layout_.bucket_count())),
      min_(kNoMinimum) {}  // make_unique value-initialises: the counters start at zero

void LatencyHistogram::record(uint64_t value, uint64_t count) noexcept {
  if (count == 0) return;
  if (value > layout_.highest_trackable_value()) {
    value = layout_.highest_trackable_value();
    overflow_count_.fetch_add(count, kRelaxed);
  }
  counts_[layout_.index_of(value)].fetch_add(count, kRelaxed);
  sum_.fetch_add(value * count, kRelaxed);
  update_min(value);
  update_max(value);
}

void LatencyHistogram::update_min(uint64_t value) noexcept {
  uint64_t current = min_.load(kRelaxed);
  while (value < current && !min_.compare_exchange_weak(current, value, kRelaxed)) {
  }
}

void LatencyHistogram::update_max(uint64_t value) noexcept {
  uint64_t current = max_.load(kRelaxed);
  while (value > current && !max_.compare_exchange_weak(current, value, kRelaxed)) {
  }
}

void LatencyHistogram::merge(const LatencyHistogram& other) {
  if (!(layout_ == other.layout_)) {
    throw std::invalid_argument(
        "LatencyHistogram::merge: configurations differ: highest_trackable_value " +
        std::to_string(highest_trackable_value()) + " vs " +
        std::to_string(other.highest_trackable_value()) + ", significant_digits " +
        std::to_string(significant_digits()) + " vs " + std::to_string(other.significant_digits()) +
        "; both must be equal");
  }
  for (std::size_t i = 0; i < layout_.bucket_count(); ++i) {
    const uint64_t count = other.counts_[i].load(kRelaxed);
    if (count != 0) counts_[i].fetch_add(count, kRelaxed);
  }
  sum_.fetch_add(other.sum_.load(kRelaxed), kRelaxed);
  overflow_count_.fetch_add(other.overflow_count_.load(kRelaxed), kRelaxed);
  const uint64_t other_min = other.min_.load(kRelaxed);
  if (other_min != kNoMinimum) {
    update_min(other_min);
    update_max(other.max_.load(kRelaxed));
  }
}

void LatencyHistogram::reset() noexcept {
  for (std::size_t i = 0; i < layout_.bucket_count(); ++i) counts_[i].store(0, kRelaxed);
  min_.store(kNoMinimum, kRelaxed);
  max_.store(0, kRelaxed);
  sum_.store(0, kRelaxed);
  overflow_count_.store(0, kRelaxed);
}

uint64_t LatencyHistogram::count() const {
  uint64_t total = 0;
  for (std::size_t i = 0; i < layout_.bucket_count(); ++i) total += counts_[i].load(kRelaxed);
  return total;
}

uint64_t LatencyHistogram::min() const {
  const uint64_t minimum = min_.load(kRelaxed);
  return minimum == kNoMinimum ? 0 : minimum;
}

uint64_t LatencyHistogram::max() const {
  return max_.load(kRelaxed);
}

double LatencyHistogram::mean() const {
  const uint64_t total = count();
  if (total == 0) return 0.0;
  return static_cast<double>(sum_.load(kRelaxed)) / static_cast<double>(total);
}

uint64_t LatencyHistogram::value_at_percentile(double p) const {
  return snapshot().value_at_percentile(p);
}

uint64_t LatencyHistogram::cumulative_count_at_or_below(uint64_t value) const {
  return snapshot().cumulative_count_at_or_below(value);
}

std::vector<HistogramBucket> LatencyHistogram::buckets() const {
  return snapshot().buckets();
}

LatencyHistogramSnapshot LatencyHistogram::snapshot() const {
  LatencyHistogramSnapshot result(layout_);
  for (std::size_t i = 0; i < layout_.bucket_count(); ++i) {
    result.counts_[i] = counts_[i].load(kRelaxed);
    result.total_count_ += result.counts_[i];
  }
  result.min_ = min();
  result.max_ = max();
  result.sum_ = sum_.load(kRelaxed);
  result.overflow_count_ = overflow_count();
  return result;
}

}  // namespace soltex
