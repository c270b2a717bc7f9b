#include "load_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "request_mix.h"
#include "soltex/common/texture_id.h"

namespace soltex::load {
namespace {

std::string printf_string(const char* format, auto... args) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, format, args...);
  return buffer;
}

double ms(double ns) {
  return ns * 1e-6;
}

std::string describe_load(const LoadResult& r) {
  const LoadOptions& o = r.options;
  std::string text;
  if (o.rate) {
    text = printf_string("open loop at %g bricks/s", *o.rate);
  } else if (o.replay_speed > 0.0) {
    text = printf_string("open loop at the recorded times x%g", o.replay_speed);
  } else {
    text = printf_string("closed loop, %d in flight per stream", o.in_flight);
  }
  text += printf_string(", %d stream(s) over %d connection(s), %s mix", o.streams, o.connections,
                        mix_name(o.mix));
  if (o.mix == MixKind::hot) text += printf_string(" (%d keys)", o.hot_set);
  if (o.mix == MixKind::uniform) {
    // How cold a uniform run stays depends on how many bricks there are to draw from.
    const TextureShape shape{r.texture_id, r.texture_levels, o.brick_size};
    text += printf_string(" (%llu bricks)", static_cast<unsigned long long>(shape.brick_count()));
  }
  if (o.mix == MixKind::replay) text += " (" + o.replay_file + ")";
  if (o.invalid_fraction > 0.0) text += printf_string(", %g invalid", o.invalid_fraction);
  return text;
}

std::string describe_stop(const LoadOptions& o) {
  std::string text;
  if (o.duration_seconds) text = printf_string("%g s", *o.duration_seconds);
  if (o.count) {
    text += (text.empty() ? "" : " or ") + std::to_string(*o.count) + " bricks";
  } else if (!o.duration_seconds) {
    text = "default";
  }
  if (o.warmup_seconds > 0.0) text += printf_string(" after %g s warmup", o.warmup_seconds);
  return text;
}

// Ten log-spaced bins from the smallest to the largest recorded latency: latencies spread
// over decades, and linear bins would put nearly everything in the first.
struct Bin {
  double upper_ns;
  uint64_t count;
};

std::vector<Bin> histogram_bins(const LatencySummary& latency) {
  constexpr int kBins = 10;
  std::vector<Bin> bins;
  if (latency.count == 0) return bins;
  const double low = std::max<double>(1.0, static_cast<double>(latency.min));
  const double high = std::max<double>(low, static_cast<double>(latency.max));
  const double ratio = high / low;
  for (int k = 1; k <= kBins; ++k) bins.push_back({low * std::pow(ratio, k / double(kBins)), 0});
  bins.back().upper_ns = high;
  for (const HistogramBucket& b : latency.buckets) {
    // A bucket is placed by its middle, clamped into the recorded range.
    const double middle = std::clamp(
        0.5 * (static_cast<double>(b.lower_bound) + static_cast<double>(b.upper_bound)), low, high);
    auto bin = std::find_if(bins.begin(), bins.end(),
                            [&](const Bin& candidate) { return middle <= candidate.upper_ns; });
    if (bin == bins.end()) bin = bins.end() - 1;
    bin->count += b.count;
  }
  return bins;
}

bool any(const CodeCounts& counts) {
  return std::any_of(counts.begin() + 1, counts.end(), [](uint64_t n) { return n > 0; });
}

}  // namespace

std::string format_text(const LoadResult& r) {
  const LoadOptions& o = r.options;
  std::ostringstream out;
  out << "Summary:\n";
  out << "  Target:        " << o.target << " (" << r.server_workers << " server workers)\n";
  out << "  Texture:       "
      << printf_string("%s, L = %d, B = %d, %s, %d levels, id %s\n", pattern_kind_name(o.pattern),
                       o.finest_level, o.brick_size, codec_choice_name(o.codec), r.texture_levels,
                       texture_id_hex(r.texture_id).c_str());
  out << "  Load:          " << describe_load(r) << "\n";
  out << "  Stop:          " << describe_stop(o) << "\n";
  out << printf_string("  Elapsed:       %.3f s (measured %.3f s)\n", r.elapsed_seconds,
                       r.measured_seconds);
  out << printf_string("  Requests:      %llu\n", static_cast<unsigned long long>(r.requests));
  out << printf_string("  Bricks:        %llu\n", static_cast<unsigned long long>(r.bricks));
  out << printf_string("  Bricks/s:      %.1f\n", r.bricks_per_second());
  out << printf_string("  MB/s:          %.2f (encoded brick payload, 10^6 bytes)\n",
                       r.megabytes_per_second());
  out << printf_string("  Errors:        %llu\n",
                       static_cast<unsigned long long>(r.measured_errors()));
  if (r.stream_failures() > 0) {
    // The run was cut short: the figures above cover it only until the streams ended.
    out << printf_string("  Streams:       %llu of %d ended with an error (codes below)\n",
                         static_cast<unsigned long long>(r.stream_failures()), o.streams);
  }
  if (o.verify) {
    // Answers, so in Bricks above, but wrong ones: a reader of the summary must see them.
    out << printf_string("  Corrupt:       %llu bricks failed --verify (their checksum)%s\n",
                         static_cast<unsigned long long>(r.checksum_failures),
                         r.checksum_failures > 0 ? ", counted in Bricks above" : "");
  }
  if (o.open_loop()) {
    out << printf_string("  Send lag:      %.3f ms at most behind the schedule\n",
                         r.max_send_lag_seconds * 1e3);
  }

  const LatencySummary& l = r.latency;
  out << "\nLatency per brick (from the intended send time to the answer's arrival):\n";
  const std::pair<const char*, double> rows[] = {{"min", double(l.min)}, {"mean", l.mean},
                                                 {"p50", double(l.p50)}, {"p90", double(l.p90)},
                                                 {"p99", double(l.p99)}, {"p99.9", double(l.p999)},
                                                 {"max", double(l.max)}};
  if (r.bricks == 0) {
    out << "  (no bricks answered)\n";  // zeros would read as instant answers
  } else {
    for (const auto& [name, value] : rows) {
      out << printf_string("  %-6s %10.3f ms\n", name, ms(value));
    }
  }

  out << "\nLatency histogram (log-spaced bins, labelled by their upper edge):\n";
  const std::vector<Bin> bins = histogram_bins(l);
  uint64_t tallest = 0;
  for (const Bin& bin : bins) tallest = std::max(tallest, bin.count);
  for (const Bin& bin : bins) {
    const int width = tallest > 0 ? static_cast<int>(40 * bin.count / tallest) : 0;
    std::string bar;
    for (int i = 0; i < width; ++i) bar += "\u220e";
    out << printf_string("  %10.3f ms [%10llu] |", ms(bin.upper_ns),
                         static_cast<unsigned long long>(bin.count))
        << bar << "\n";
  }
  if (bins.empty()) out << "  (no bricks)\n";

  out << "\nErrors by status code (bricks: measured; requests and streams: whole run):\n";
  if (!any(r.brick_errors) && !any(r.request_errors) && !any(r.stream_status)) {
    out << "  none\n";
  } else {
    out << printf_string("  %-20s %10s %10s %10s\n", "code", "bricks", "requests", "streams");
    for (int code = 1; code < 17; ++code) {
      const auto c = static_cast<std::size_t>(code);
      if (r.brick_errors[c] + r.request_errors[c] + r.stream_status[c] == 0) continue;
      out << printf_string("  %-20s %10llu %10llu %10llu\n", status_code_name(code),
                           static_cast<unsigned long long>(r.brick_errors[c]),
                           static_cast<unsigned long long>(r.request_errors[c]),
                           static_cast<unsigned long long>(r.stream_status[c]));
    }
  }
  out << printf_string("  streams ended OK: %llu of %d\n",
                       static_cast<unsigned long long>(r.stream_status[0]), o.streams);
  const std::pair<const char*, uint64_t> client_side[] = {
      {"unanswered at the end", r.unanswered},
      {"streams let go at the drain timeout", r.streams_let_go},
      {"dropped, backlog full", r.dropped_backlog},
      {"unexpected answers", r.unexpected},
      {"checksum failures", r.checksum_failures}};
  for (const auto& [name, count] : client_side) {
    if (count > 0) {
      out << printf_string("  %s: %llu\n", name, static_cast<unsigned long long>(count));
    }
  }
  if (o.warmup_seconds > 0.0) {
    out << printf_string("\nWhole run including warmup: %llu requests, %llu bricks\n",
                         static_cast<unsigned long long>(r.total_requests),
                         static_cast<unsigned long long>(r.total_bricks));
  }
  return out.str();
}

std::string format_json(const LoadResult& r) {
  using json = nlohmann::ordered_json;
  const LoadOptions& o = r.options;
  const auto codes = [](const CodeCounts& counts, bool with_ok) {
    json object = json::object();
    for (int code = with_ok ? 0 : 1; code < 17; ++code) {
      const uint64_t n = counts[static_cast<std::size_t>(code)];
      if (n > 0) object[status_code_name(code)] = n;
    }
    return object;
  };
  json options = {{"target", o.target},
                  {"connections", o.connections},
                  {"streams", o.streams},
                  {"open_loop", o.open_loop()},
                  {"in_flight", o.open_loop() ? json(nullptr) : json(o.in_flight)},
                  {"rate", o.rate ? json(*o.rate) : json(nullptr)},
                  {"replay_speed", o.replay_speed},
                  {"duration_seconds", o.duration_seconds ? json(*o.duration_seconds) : json()},
                  {"count", o.count ? json(*o.count) : json(nullptr)},
                  {"warmup_seconds", o.warmup_seconds},
                  {"mix", mix_name(o.mix)},
                  {"hot_set", o.hot_set},
                  {"replay_file", o.replay_file},
                  {"invalid_fraction", o.invalid_fraction},
                  {"pattern", pattern_kind_name(o.pattern)},
                  {"finest_level", o.finest_level},
                  {"brick_size", o.brick_size},
                  {"codec", codec_choice_name(o.codec)},
                  {"seed", o.seed},
                  {"verify", o.verify}};
  json histogram = json::array();
  for (const HistogramBucket& b : r.latency.buckets) {
    histogram.push_back(
        {{"lower_ns", b.lower_bound}, {"upper_ns", b.upper_bound}, {"count", b.count}});
  }
  const LatencySummary& l = r.latency;
  json result = {{"options", options},
                 {"texture", {{"id", texture_id_hex(r.texture_id)}, {"levels", r.texture_levels}}},
                 {"server_workers", r.server_workers},
                 {"elapsed_seconds", r.elapsed_seconds},
                 {"measured_seconds", r.measured_seconds},
                 {"requests", r.requests},
                 {"bricks", r.bricks},
                 {"bytes", r.bytes},
                 {"bricks_per_second", r.bricks_per_second()},
                 {"megabytes_per_second", r.megabytes_per_second()},
                 {"latency_ns",
                  {{"min", l.min},
                   {"mean", l.mean},
                   {"p50", l.p50},
                   {"p90", l.p90},
                   {"p99", l.p99},
                   {"p99_9", l.p999},
                   {"max", l.max}}},
                 {"histogram", histogram},
                 {"errors",
                  {{"bricks", codes(r.brick_errors, false)},
                   {"requests", codes(r.request_errors, false)},
                   {"streams", codes(r.stream_status, false)}}},
                 {"stream_status", codes(r.stream_status, true)},
                 {"totals",
                  {{"requests", r.total_requests},
                   {"bricks", r.total_bricks},
                   {"bytes", r.total_bytes},
                   {"brick_errors", codes(r.total_brick_errors, false)}}},
                 {"unanswered", r.unanswered},
                 {"streams_let_go", r.streams_let_go},
                 {"dropped_backlog", r.dropped_backlog},
                 {"unexpected", r.unexpected},
                 {"checksum_failures", r.checksum_failures},
                 {"max_send_lag_seconds", r.max_send_lag_seconds},
                 {"injected",
                  {{"out_of_range", r.injected_out_of_range},
                   {"unknown_texture", r.injected_unknown_texture}}}};
  return result.dump(2) + "\n";
}

std::string format_csv(const LoadResult& r) {
  const LoadOptions& o = r.options;
  std::string errors;  // "CODE:n;CODE:n", per-brick errors of measured requests
  for (int code = 1; code < 17; ++code) {
    const uint64_t n = r.brick_errors[static_cast<std::size_t>(code)];
    if (n == 0) continue;
    if (!errors.empty()) errors += ';';
    errors += std::string(status_code_name(code)) + ":" + std::to_string(n);
  }
  const uint64_t stream_failures = r.stream_failures();
  std::string out =
      "target,mix,pattern,brick_size,codec,connections,streams,mode,in_flight,rate,warmup_s,"
      "measured_s,requests,bricks,bricks_per_s,mb_per_s,min_ms,mean_ms,p50_ms,p90_ms,p99_ms,"
      "p99_9_ms,max_ms,errors,brick_errors_by_code,stream_failures,unanswered\n";
  const LatencySummary& l = r.latency;
  out += printf_string("%s,%s,%s,%d,%s,%d,%d,%s,", o.target.c_str(), mix_name(o.mix),
                       pattern_kind_name(o.pattern), o.brick_size, codec_choice_name(o.codec),
                       o.connections, o.streams, o.open_loop() ? "open" : "closed");
  out += o.open_loop() ? std::string() : std::to_string(o.in_flight);
  out += ",";
  out += o.rate ? printf_string("%g", *o.rate) : std::string();
  out += printf_string(",%g,%.6f,%llu,%llu,%.3f,%.4f,", o.warmup_seconds, r.measured_seconds,
                       static_cast<unsigned long long>(r.requests),
                       static_cast<unsigned long long>(r.bricks), r.bricks_per_second(),
                       r.megabytes_per_second());
  out += printf_string("%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,", ms(double(l.min)), ms(l.mean),
                       ms(double(l.p50)), ms(double(l.p90)), ms(double(l.p99)), ms(double(l.p999)),
                       ms(double(l.max)));
  out += printf_string("%llu,%s,%llu,%llu\n", static_cast<unsigned long long>(r.measured_errors()),
                       errors.c_str(), static_cast<unsigned long long>(stream_failures),
                       static_cast<unsigned long long>(r.unanswered));
  return out;
}

std::string format_result(const LoadResult& result, OutputFormat format) {
  switch (format) {
    case OutputFormat::json:
      return format_json(result);
    case OutputFormat::csv:
      return format_csv(result);
    case OutputFormat::text:
      break;
  }
  return format_text(result);
}

std::string format_progress(const ProgressLine& line) {
  return printf_string("[%7.1f s]%s %llu bricks  %.0f bricks/s  %llu errors", line.elapsed_seconds,
                       line.warmup ? " warmup" : (line.draining ? " drain" : ""),
                       static_cast<unsigned long long>(line.bricks), line.bricks_per_second,
                       static_cast<unsigned long long>(line.errors));
}

}  // namespace soltex::load
