#include "soltex/common/latency_histogram.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace soltex {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

constexpr uint64_t kInt64Max = static_cast<uint64_t>(std::numeric_limits<int64_t>::max());

double relative_precision(int significant_digits) {
  return std::pow(10.0, -significant_digits);
}

std::string invalid_argument_message(const std::function<void()>& action) {
  try {
    action();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no std::invalid_argument thrown)";
}

TEST(LatencyHistogram, EmptyHistogramReportsZeros) {
  const LatencyHistogram histogram;
  EXPECT_EQ(histogram.count(), 0u);
  EXPECT_EQ(histogram.min(), 0u);
  EXPECT_EQ(histogram.max(), 0u);
  EXPECT_EQ(histogram.mean(), 0.0);
  EXPECT_EQ(histogram.overflow_count(), 0u);
  for (double p : {0.0, 50.0, 99.9, 100.0}) EXPECT_EQ(histogram.value_at_percentile(p), 0u) << p;
  EXPECT_EQ(histogram.cumulative_count_at_or_below(1'000'000), 0u);
  EXPECT_TRUE(histogram.buckets().empty());

  const LatencyHistogramSnapshot snapshot = histogram.snapshot();
  EXPECT_EQ(snapshot.count(), 0u);
  EXPECT_EQ(snapshot.min(), 0u);
  EXPECT_EQ(snapshot.max(), 0u);
  EXPECT_EQ(snapshot.mean(), 0.0);
  EXPECT_EQ(snapshot.value_at_percentile(50.0), 0u);
}

TEST(LatencyHistogram, DefaultsAreOneHourAndTwoDigits) {
  const LatencyHistogram histogram;
  EXPECT_EQ(histogram.highest_trackable_value(), 3'600'000'000'000u);
  EXPECT_EQ(histogram.significant_digits(), 2);
}

TEST(LatencyHistogram, RejectsBadConfigurations) {
  EXPECT_THAT(invalid_argument_message([] { LatencyHistogram(1000, 0); }),
              HasSubstr("significant_digits = 0: must be in [1, 3]"));
  EXPECT_THAT(invalid_argument_message([] { LatencyHistogram(1000, 4); }),
              HasSubstr("significant_digits = 4: must be in [1, 3]"));
  EXPECT_THAT(invalid_argument_message([] { LatencyHistogram(0, 2); }),
              HasSubstr("highest_trackable_value = 0: must be in [1, "));
  EXPECT_THAT(invalid_argument_message([] { LatencyHistogram(kInt64Max + 1, 2); }),
              HasSubstr("highest_trackable_value = 9223372036854775808"));
  EXPECT_NO_THROW(LatencyHistogram(kInt64Max, 3));
  EXPECT_NO_THROW(LatencyHistogram(1, 1));
}

// Every value belongs to exactly one bucket, the buckets tile [0, highest trackable value]
// without gaps, and each is narrower than the configured relative precision.
TEST(LatencyBucketLayout, BucketsTileTheRangeWithinThePrecision) {
  for (int digits = 1; digits <= 3; ++digits) {
    for (uint64_t highest : {uint64_t{1}, uint64_t{1000}, uint64_t{3'600'000'000'000}, kInt64Max}) {
      SCOPED_TRACE(testing::Message() << "digits " << digits << ", highest " << highest);
      const LatencyBucketLayout layout(highest, digits);
      const uint64_t scale = static_cast<uint64_t>(std::llround(std::pow(10.0, digits)));
      EXPECT_EQ(layout.lowest_value_at(0), 0u);
      for (std::size_t i = 0; i < layout.bucket_count(); ++i) {
        const uint64_t lowest = layout.lowest_value_at(i);
        const uint64_t highest_in_bucket = layout.highest_value_at(i);
        ASSERT_LE(lowest, highest_in_bucket) << i;
        ASSERT_EQ(layout.index_of(lowest), i);
        ASSERT_EQ(layout.index_of(highest_in_bucket), i);
        const uint64_t width = highest_in_bucket - lowest + 1;
        ASSERT_TRUE(width == 1 || width * scale <= lowest) << i << ": " << lowest << ".." << width;
        if (i + 1 < layout.bucket_count()) {
          ASSERT_EQ(layout.lowest_value_at(i + 1), highest_in_bucket + 1) << i;
        }
      }
      const std::size_t last = layout.bucket_count() - 1;
      EXPECT_EQ(layout.index_of(highest), last);
      EXPECT_GE(layout.highest_value_at(last), highest);
    }
  }
}

TEST(LatencyBucketLayout, SmallValuesAreExact) {
  const LatencyBucketLayout layout(LatencyHistogram::kDefaultHighestTrackableValue, 2);
  for (uint64_t value = 0; value < 256; ++value) {
    EXPECT_EQ(layout.lowest_equivalent_value(value), value);
    EXPECT_EQ(layout.highest_equivalent_value(value), value);
  }
  EXPECT_EQ(layout.lowest_equivalent_value(1001), 1000u);
  EXPECT_EQ(layout.highest_equivalent_value(1001), 1003u);
}

TEST(LatencyHistogram, UniformOneToAMillion) {
  LatencyHistogram histogram;
  constexpr uint64_t kN = 1'000'000;
  for (uint64_t value = 1; value <= kN; ++value) histogram.record(value);
  EXPECT_EQ(histogram.count(), kN);
  EXPECT_EQ(histogram.min(), 1u);
  EXPECT_EQ(histogram.max(), kN);
  EXPECT_EQ(histogram.mean(), 500'000.5);

  const LatencyHistogramSnapshot snapshot = histogram.snapshot();
  const LatencyBucketLayout& layout = snapshot.layout();
  struct Expectation {
    double p;
    uint64_t exact;  // the value at that percentile of 1..1e6
  };
  for (const Expectation& e :
       {Expectation{1, 10'000}, Expectation{10, 100'000}, Expectation{25, 250'000},
        Expectation{50, 500'000}, Expectation{75, 750'000}, Expectation{90, 900'000},
        Expectation{99, 990'000}, Expectation{99.9, 999'000}, Expectation{99.99, 999'900},
        Expectation{100, kN}}) {
    const uint64_t reported = snapshot.value_at_percentile(e.p);
    EXPECT_EQ(reported, std::min(layout.highest_equivalent_value(e.exact), kN)) << e.p;
    EXPECT_GE(reported, e.exact) << e.p;
    EXPECT_LE(static_cast<double>(reported - e.exact), 0.01 * static_cast<double>(e.exact)) << e.p;
    EXPECT_EQ(histogram.value_at_percentile(e.p), reported) << e.p;
  }
  EXPECT_EQ(snapshot.value_at_percentile(0), 1u);
}

// 99.9 / 100 * 1000 is 999.0000000000001 in binary floating point; the rank must still be 999
// (value 999, bucket [996, 999]) and not 1000 (bucket [1000, 1003]).
TEST(LatencyHistogram, DecimalPercentilesGiveTheirExactRank) {
  LatencyHistogram histogram;
  for (uint64_t value = 1; value <= 1000; ++value) histogram.record(value);
  EXPECT_EQ(histogram.value_at_percentile(99.9), 999u);
  EXPECT_EQ(histogram.value_at_percentile(90.1), 903u);  // rank 901 in bucket [900, 903]
  EXPECT_EQ(histogram.value_at_percentile(100), 1000u);  // bucket [1000, 1003], but the max
}

TEST(LatencyHistogram, ConstantValue) {
  LatencyHistogram histogram;
  constexpr uint64_t kValue = 1'234'567;
  histogram.record(kValue, 1000);
  EXPECT_EQ(histogram.count(), 1000u);
  EXPECT_EQ(histogram.min(), kValue);
  EXPECT_EQ(histogram.max(), kValue);
  EXPECT_EQ(histogram.mean(), static_cast<double>(kValue));
  // The bucket's bounds lie around the value, but no percentile reads outside [min, max].
  const LatencyBucketLayout& layout = histogram.layout();
  EXPECT_LT(layout.lowest_equivalent_value(kValue), kValue);
  EXPECT_GT(layout.highest_equivalent_value(kValue), kValue);
  for (double p : {0.0, 0.001, 1.0, 50.0, 99.0, 100.0}) {
    EXPECT_EQ(histogram.value_at_percentile(p), kValue) << p;
  }
}

TEST(LatencyHistogram, TwoPointDistribution) {
  LatencyHistogram histogram;
  histogram.record(100, 900);
  histogram.record(1'000'000, 100);
  EXPECT_EQ(histogram.count(), 1000u);
  EXPECT_EQ(histogram.min(), 100u);
  EXPECT_EQ(histogram.max(), 1'000'000u);
  EXPECT_EQ(histogram.mean(), 100'090.0);  // (900 * 100 + 100 * 1e6) / 1000
  const uint64_t high = histogram.layout().highest_equivalent_value(1'000'000);
  EXPECT_EQ(histogram.value_at_percentile(50), 100u);
  EXPECT_EQ(histogram.value_at_percentile(90), 100u);  // rank 900: the last low value
  // The top bucket reaches past the max; a percentile stops at it.
  EXPECT_EQ(histogram.value_at_percentile(90.1), 1'000'000u);
  EXPECT_EQ(histogram.value_at_percentile(99), 1'000'000u);
  EXPECT_EQ(histogram.value_at_percentile(100), 1'000'000u);
  EXPECT_THAT(histogram.buckets(),
              ElementsAre(HistogramBucket{100, 100, 900},
                          HistogramBucket{histogram.layout().lowest_equivalent_value(1'000'000),
                                          high, 100}));
}

// Percentiles of random log-uniform data against the exact order statistics: the reported value
// is never below the exact one and above it by at most the configured relative precision.
TEST(LatencyHistogram, PercentilesAreWithinTheConfiguredPrecision) {
  for (int digits = 1; digits <= 3; ++digits) {
    SCOPED_TRACE(testing::Message() << "digits " << digits);
    std::mt19937_64 rng(1234 + digits);
    std::uniform_real_distribution<double> log_value(0.0, std::log(1e12));
    LatencyHistogram histogram(LatencyHistogram::kDefaultHighestTrackableValue, digits);
    std::vector<uint64_t> values(20'000);
    for (uint64_t& value : values) {
      value = static_cast<uint64_t>(std::exp(log_value(rng)));
      histogram.record(value);
    }
    std::sort(values.begin(), values.end());
    EXPECT_EQ(histogram.min(), values.front());
    EXPECT_EQ(histogram.max(), values.back());
    const LatencyHistogramSnapshot snapshot = histogram.snapshot();
    // In basis points, so that the exact rank is integer arithmetic.
    for (uint64_t basis_points : {50, 1000, 3330, 5000, 9000, 9900, 9990, 9999, 10000}) {
      const double p = static_cast<double>(basis_points) / 100.0;
      const uint64_t rank = (basis_points * values.size() + 9999) / 10000;
      const uint64_t exact = values[rank - 1];
      const uint64_t reported = snapshot.value_at_percentile(p);
      EXPECT_GE(reported, exact) << p;
      EXPECT_LE(static_cast<double>(reported - exact),
                relative_precision(digits) * static_cast<double>(exact))
          << p << ": exact " << exact << ", reported " << reported;
    }
  }
}

TEST(LatencyHistogram, RejectsBadPercentiles) {
  LatencyHistogram histogram;
  histogram.record(10);
  EXPECT_THAT(invalid_argument_message([&] { histogram.value_at_percentile(-1); }),
              HasSubstr("p = -1: must be in [0, 100]"));
  EXPECT_THAT(invalid_argument_message([&] { histogram.value_at_percentile(100.5); }),
              HasSubstr("p = 100.5: must be in [0, 100]"));
  EXPECT_THAT(invalid_argument_message([&] { histogram.value_at_percentile(std::nan("")); }),
              HasSubstr("p = nan: must be in [0, 100]"));
  EXPECT_THAT(invalid_argument_message(
                  [&] { histogram.value_at_percentile(std::numeric_limits<double>::infinity()); }),
              HasSubstr("p = inf"));
  // Just above 100 is still outside, and the message shows it is.
  EXPECT_THAT(invalid_argument_message(
                  [&] { histogram.snapshot().value_at_percentile(std::nextafter(100.0, 200.0)); }),
              HasSubstr("p = 100.00000000000001"));
  EXPECT_EQ(histogram.value_at_percentile(-0.0), 10u);
}

TEST(LatencyHistogram, ClampsValuesAboveTheHighestTrackableValue) {
  LatencyHistogram histogram(1'000'000);
  histogram.record(10);
  histogram.record(5'000'000, 3);
  histogram.record(std::numeric_limits<uint64_t>::max());
  EXPECT_EQ(histogram.count(), 5u);
  EXPECT_EQ(histogram.overflow_count(), 4u);
  EXPECT_EQ(histogram.max(), 1'000'000u);
  EXPECT_EQ(histogram.mean(), (10.0 + 4 * 1'000'000.0) / 5);
  EXPECT_EQ(histogram.value_at_percentile(100), 1'000'000u);
  EXPECT_EQ(histogram.cumulative_count_at_or_below(1'000'000), 5u);

  LatencyHistogram default_histogram;
  default_histogram.record(std::numeric_limits<uint64_t>::max());
  EXPECT_EQ(default_histogram.max(), LatencyHistogram::kDefaultHighestTrackableValue);
  EXPECT_EQ(default_histogram.overflow_count(), 1u);
}

TEST(LatencyHistogram, RecordsZeroAndIgnoresZeroCounts) {
  LatencyHistogram histogram;
  histogram.record(7, 0);
  EXPECT_EQ(histogram.count(), 0u);
  EXPECT_EQ(histogram.min(), 0u);
  EXPECT_EQ(histogram.max(), 0u);
  histogram.record(0);
  histogram.record(3);
  EXPECT_EQ(histogram.count(), 2u);
  EXPECT_EQ(histogram.min(), 0u);
  EXPECT_EQ(histogram.max(), 3u);
  EXPECT_EQ(histogram.value_at_percentile(50), 0u);
}

TEST(LatencyHistogram, ListsNonEmptyBucketsInOrder) {
  LatencyHistogram histogram;
  histogram.record(1'001, 3);
  histogram.record(1);
  EXPECT_THAT(histogram.buckets(),
              ElementsAre(HistogramBucket{1, 1, 1}, HistogramBucket{1000, 1003, 3}));
}

TEST(LatencyHistogram, CumulativeCountCountsWholeBuckets) {
  LatencyHistogram histogram;
  for (uint64_t value = 1; value <= 1000; ++value) histogram.record(value);
  EXPECT_EQ(histogram.cumulative_count_at_or_below(0), 0u);
  EXPECT_EQ(histogram.cumulative_count_at_or_below(100), 100u);  // exact below 256
  // 500 shares the bucket [500, 501]: exact at the bucket's upper bound.
  EXPECT_EQ(histogram.cumulative_count_at_or_below(501), 501u);
  EXPECT_EQ(histogram.cumulative_count_at_or_below(500), 501u);
  EXPECT_EQ(histogram.cumulative_count_at_or_below(1000), 1000u);
  EXPECT_EQ(histogram.cumulative_count_at_or_below(std::numeric_limits<uint64_t>::max()), 1000u);

  // As a Prometheus exposition would use it: counts never decrease along the boundaries.
  const LatencyHistogramSnapshot snapshot = histogram.snapshot();
  uint64_t previous = 0;
  for (uint64_t le : {1, 5, 10, 50, 100, 250, 500, 1000}) {
    const uint64_t at_or_below =
        snapshot.cumulative_count_at_or_below(snapshot.layout().highest_equivalent_value(le));
    EXPECT_GE(at_or_below, previous) << le;
    previous = at_or_below;
  }
  EXPECT_EQ(previous, snapshot.count());
}

TEST(LatencyHistogram, MergeAddsRecordings) {
  LatencyHistogram a;
  LatencyHistogram b;
  LatencyHistogram both;
  for (uint64_t value = 1; value <= 5000; value += 7) {
    a.record(value);
    both.record(value);
  }
  for (uint64_t value = 20; value <= 90'000'000; value = value * 3 / 2) {
    b.record(value, 2);
    both.record(value, 2);
  }
  b.record(std::numeric_limits<uint64_t>::max());
  both.record(std::numeric_limits<uint64_t>::max());

  a.merge(b);
  EXPECT_EQ(a.count(), both.count());
  EXPECT_EQ(a.min(), both.min());
  EXPECT_EQ(a.max(), both.max());
  EXPECT_EQ(a.mean(), both.mean());
  EXPECT_EQ(a.overflow_count(), 1u);
  EXPECT_EQ(a.buckets(), both.buckets());
  for (double p : {0.0, 50.0, 99.0, 100.0}) {
    EXPECT_EQ(a.value_at_percentile(p), both.value_at_percentile(p)) << p;
  }

  // An empty histogram merged in changes nothing, and merging into an empty one copies.
  const LatencyHistogram empty;
  a.merge(empty);
  EXPECT_EQ(a.min(), both.min());
  EXPECT_EQ(a.buckets(), both.buckets());
  LatencyHistogram copy;
  copy.merge(both);
  EXPECT_EQ(copy.min(), both.min());
  EXPECT_EQ(copy.max(), both.max());
  EXPECT_EQ(copy.buckets(), both.buckets());
}

TEST(LatencyHistogram, MergeRequiresTheSameConfiguration) {
  LatencyHistogram histogram;
  const LatencyHistogram other_digits(LatencyHistogram::kDefaultHighestTrackableValue, 3);
  const LatencyHistogram other_range(1'000'000, 2);
  EXPECT_THAT(invalid_argument_message([&] { histogram.merge(other_digits); }),
              HasSubstr("significant_digits 2 vs 3"));
  EXPECT_THAT(invalid_argument_message([&] { histogram.merge(other_range); }),
              HasSubstr("highest_trackable_value 3600000000000 vs 1000000"));
}

TEST(LatencyHistogram, ResetForgetsEverything) {
  LatencyHistogram histogram(1000);
  histogram.record(5);
  histogram.record(5000);
  histogram.reset();
  EXPECT_EQ(histogram.count(), 0u);
  EXPECT_EQ(histogram.min(), 0u);
  EXPECT_EQ(histogram.max(), 0u);
  EXPECT_EQ(histogram.mean(), 0.0);
  EXPECT_EQ(histogram.overflow_count(), 0u);
  EXPECT_TRUE(histogram.buckets().empty());
  histogram.record(42);
  EXPECT_EQ(histogram.min(), 42u);
  EXPECT_EQ(histogram.max(), 42u);
}

TEST(LatencyHistogram, SnapshotIsACopy) {
  LatencyHistogram histogram;
  histogram.record(10);
  const LatencyHistogramSnapshot snapshot = histogram.snapshot();
  histogram.record(1'000'000);
  EXPECT_EQ(snapshot.count(), 1u);
  EXPECT_EQ(snapshot.max(), 10u);
  EXPECT_EQ(snapshot.value_at_percentile(100), 10u);
  EXPECT_EQ(histogram.count(), 2u);
}

TEST(LatencyHistogram, ConcurrentRecordingLosesNothing) {
  LatencyHistogram histogram;
  constexpr int kThreads = 4;
  constexpr uint64_t kPerThread = 100'000;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&histogram, t] {
      // Each thread covers 1..kPerThread, shifted by its index, so hot buckets are shared.
      for (uint64_t i = 1; i <= kPerThread; ++i) histogram.record(i + static_cast<uint64_t>(t));
    });
  }
  for (std::thread& thread : threads) thread.join();

  EXPECT_EQ(histogram.count(), kThreads * kPerThread);
  EXPECT_EQ(histogram.min(), 1u);
  EXPECT_EQ(histogram.max(), kPerThread + kThreads - 1);
  // Sum over threads of (sum 1..n + t * n) = 4 * n(n+1)/2 + 6n.
  const double sum = kThreads * (kPerThread * (kPerThread + 1) / 2.0) + 6.0 * kPerThread;
  EXPECT_EQ(histogram.mean(), sum / (kThreads * kPerThread));
  uint64_t bucket_total = 0;
  for (const HistogramBucket& bucket : histogram.buckets()) bucket_total += bucket.count;
  EXPECT_EQ(bucket_total, kThreads * kPerThread);
  EXPECT_EQ(histogram.cumulative_count_at_or_below(3), 1u + 2u + 3u);  // 1; 2, 2; 3, 3, 3
}

}  // namespace
}  // namespace soltex
