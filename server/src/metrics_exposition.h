#pragma once

#include <cstdint>
#include <initializer_list>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <utility>

namespace soltex::server {

enum class MetricType { counter, gauge, histogram };

// One metric family: its name, type and help text. Every family soltexd exposes is declared
// in one table (server_metrics.cpp), so a HELP or TYPE line is never written by hand.
struct MetricFamily {
  std::string_view name;
  MetricType type;
  std::string_view help;
};

using MetricLabels = std::initializer_list<std::pair<std::string_view, std::string_view>>;

// Writes the Prometheus text exposition format (version 0.0.4). A family's HELP and TYPE come
// first and once; its samples take the family's name, so no sample can land under another
// family's TYPE. Names are checked against the format's grammar, label values and help text
// are escaped, and +Inf, -Inf and NaN are spelled as Prometheus reads them. Misuse (an
// invalid name, a family twice, a sample before its family) throws std::logic_error: it is a
// programming error that the unit tests catch.
class Exposition {
 public:
  void family(const MetricFamily& family);

  // A sample of the current counter or gauge family.
  void sample(double value, MetricLabels labels = {});

  // The current histogram family: `bounds` ascending (the +Inf bucket is added),
  // `cumulative[i]` the observations at or below bounds[i].
  void histogram(std::span<const double> bounds, std::span<const uint64_t> cumulative,
                 uint64_t count, double sum, MetricLabels labels = {});

  std::string take() { return std::move(out_); }

 private:
  void line(std::string_view suffix, MetricLabels labels, std::string_view extra_name,
            std::string_view extra_value, double value);

  std::string out_;
  const MetricFamily* current_ = nullptr;
  std::set<std::string, std::less<>> written_;
};

// Whether `name` is a valid metric name ([a-zA-Z_:][a-zA-Z0-9_:]*).
bool valid_metric_name(std::string_view name);
// Whether `name` is a valid label name ([a-zA-Z_][a-zA-Z0-9_]*, not starting with "__").
bool valid_label_name(std::string_view name);
// A sample value as the text format spells it: shortest round-trip decimal, +Inf, -Inf, NaN.
std::string format_metric_value(double value);

}  // namespace soltex::server
