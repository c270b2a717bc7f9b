#include "metrics_exposition.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace soltex::server {
namespace {

bool name_char(char c, bool first, bool colon) {
  const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
  return letter || (colon && c == ':') || (!first && c >= '0' && c <= '9');
}

bool valid_name(std::string_view name, bool colon) {
  if (name.empty()) return false;
  for (std::size_t i = 0; i < name.size(); ++i) {
    if (!name_char(name[i], i == 0, colon)) return false;
  }
  return true;
}

const char* type_name(MetricType type) {
  switch (type) {
    case MetricType::counter:
      return "counter";
    case MetricType::gauge:
      return "gauge";
    case MetricType::histogram:
      return "histogram";
  }
  return "untyped";
}

// HELP text escapes backslash and newline; label values also escape the double quote.
void append_escaped(std::string& out, std::string_view text, bool quote) {
  for (char c : text) {
    if (c == '\\') {
      out += "\\\\";
    } else if (c == '\n') {
      out += "\\n";
    } else if (quote && c == '"') {
      out += "\\\"";
    } else {
      out += c;
    }
  }
}

}  // namespace

bool valid_metric_name(std::string_view name) {
  return valid_name(name, true);
}

bool valid_label_name(std::string_view name) {
  return valid_name(name, false) && !name.starts_with("__");
}

std::string format_metric_value(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

void Exposition::family(const MetricFamily& family) {
  if (!valid_metric_name(family.name)) {
    throw std::logic_error("metric name '" + std::string(family.name) + "' is not valid");
  }
  if (!written_.emplace(family.name).second) {
    throw std::logic_error("metric family '" + std::string(family.name) + "' written twice");
  }
  current_ = &family;
  out_ += "# HELP ";
  out_ += family.name;
  out_ += ' ';
  append_escaped(out_, family.help, false);
  out_ += "\n# TYPE ";
  out_ += family.name;
  out_ += ' ';
  out_ += type_name(family.type);
  out_ += '\n';
}

void Exposition::line(std::string_view suffix, MetricLabels labels, std::string_view extra_name,
                      std::string_view extra_value, double value) {
  out_ += current_->name;
  out_ += suffix;
  bool first = true;
  const auto label = [&](std::string_view name, std::string_view text) {
    if (!valid_label_name(name) || name == "le") {
      throw std::logic_error("label name '" + std::string(name) + "' of metric '" +
                             std::string(current_->name) + "' is not valid");
    }
    out_ += first ? '{' : ',';
    first = false;
    out_ += name;
    out_ += "=\"";
    append_escaped(out_, text, true);
    out_ += '"';
  };
  for (const auto& [name, text] : labels) label(name, text);
  if (!extra_name.empty()) {
    out_ += first ? '{' : ',';
    first = false;
    out_ += extra_name;
    out_ += "=\"";
    out_ += extra_value;
    out_ += '"';
  }
  if (!first) out_ += '}';
  out_ += ' ';
  out_ += format_metric_value(value);
  out_ += '\n';
}

void Exposition::sample(double value, MetricLabels labels) {
  if (current_ == nullptr || current_->type == MetricType::histogram) {
    throw std::logic_error("sample() needs a counter or gauge family first");
  }
  line("", labels, {}, {}, value);
}

void Exposition::histogram(std::span<const double> bounds, std::span<const uint64_t> cumulative,
                           uint64_t count, double sum, MetricLabels labels) {
  if (current_ == nullptr || current_->type != MetricType::histogram) {
    throw std::logic_error("histogram() needs a histogram family first");
  }
  if (bounds.size() != cumulative.size()) {
    throw std::logic_error("histogram '" + std::string(current_->name) +
                           "': " + std::to_string(bounds.size()) + " bounds but " +
                           std::to_string(cumulative.size()) + " bucket counts");
  }
  for (std::size_t i = 0; i < bounds.size(); ++i) {
    line("_bucket", labels, "le", format_metric_value(bounds[i]),
         static_cast<double>(cumulative[i]));
  }
  line("_bucket", labels, "le", "+Inf", static_cast<double>(count));
  line("_sum", labels, {}, {}, sum);
  line("_count", labels, {}, {}, static_cast<double>(count));
}

}  // namespace soltex::server
