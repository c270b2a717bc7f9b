#include "metrics_exposition.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "server_metrics.h"

namespace soltex::server {
namespace {

constexpr MetricFamily kRequests{"requests_total", MetricType::counter, "Requests.\nAll."};
constexpr MetricFamily kLatency{"latency_seconds", MetricType::histogram, "Latency."};

TEST(Exposition, HelpThenTypeThenSamplesUnderTheFamilyName) {
  Exposition e;
  e.family(kRequests);
  e.sample(3, {{"grpc_code", "OK"}, {"path", "a\"b\\c\nd"}});
  EXPECT_EQ(e.take(),
            "# HELP requests_total Requests.\\nAll.\n"
            "# TYPE requests_total counter\n"
            "requests_total{grpc_code=\"OK\",path=\"a\\\"b\\\\c\\nd\"} 3\n");
}

TEST(Exposition, HistogramGetsInfBucketSumAndCount) {
  Exposition e;
  e.family(kLatency);
  const double bounds[] = {0.001, 0.5};
  const uint64_t cumulative[] = {1, 4};
  e.histogram(bounds, cumulative, 5, 2.25);
  EXPECT_EQ(e.take(),
            "# HELP latency_seconds Latency.\n"
            "# TYPE latency_seconds histogram\n"
            "latency_seconds_bucket{le=\"0.001\"} 1\n"
            "latency_seconds_bucket{le=\"0.5\"} 4\n"
            "latency_seconds_bucket{le=\"+Inf\"} 5\n"
            "latency_seconds_sum 2.25\n"
            "latency_seconds_count 5\n");
}

TEST(Exposition, ValuesAsPrometheusSpellsThem) {
  EXPECT_EQ(format_metric_value(std::numeric_limits<double>::infinity()), "+Inf");
  EXPECT_EQ(format_metric_value(-std::numeric_limits<double>::infinity()), "-Inf");
  EXPECT_EQ(format_metric_value(std::nan("")), "NaN");
  EXPECT_EQ(format_metric_value(18446744073709551615.0), "18446744073709551616");
  EXPECT_EQ(format_metric_value(0.1), "0.1");
}

TEST(Exposition, MisuseIsRefused) {
  Exposition e;
  EXPECT_THROW(e.sample(1), std::logic_error);  // no family yet
  EXPECT_THROW(e.family({"bad-name", MetricType::gauge, "x"}), std::logic_error);
  e.family(kRequests);
  EXPECT_THROW(e.family(kRequests), std::logic_error);  // a family twice
  EXPECT_THROW(e.sample(1, {{"__reserved", "x"}}), std::logic_error);
  EXPECT_THROW(e.sample(1, {{"le", "x"}}), std::logic_error);
  e.family(kLatency);
  EXPECT_THROW(e.sample(1), std::logic_error);  // histograms take histogram()
}

TEST(MetricFamilies, NamesAreValidUniqueAndFollowConventions) {
  std::set<std::string_view> names;
  for (const MetricFamily& f : metric_families()) {
    EXPECT_TRUE(valid_metric_name(f.name)) << f.name;
    EXPECT_TRUE(names.insert(f.name).second) << f.name << " twice";
    EXPECT_FALSE(f.help.empty()) << f.name;
    EXPECT_EQ(f.type == MetricType::counter, f.name.ends_with("_total")) << f.name;
  }
}

TEST(ServerMetrics, RendersEveryFamilyOnceWithShared) {
  ServerMetrics metrics;
  const SharedCacheStats shared{};
  const std::string page = metrics.render({}, 1 << 20, RegistryStats{}, &shared, 0, {});
  for (const MetricFamily& f : metric_families()) {
    const std::string type_line = "# TYPE " + std::string(f.name) + " ";
    const auto at = page.find(type_line);
    ASSERT_NE(at, std::string::npos) << f.name;
    EXPECT_EQ(page.find(type_line, at + 1), std::string::npos) << f.name;
  }
}

}  // namespace
}  // namespace soltex::server
