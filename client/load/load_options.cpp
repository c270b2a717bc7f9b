#include "load_options.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "soltex/cli/tool_cli.h"
#include "soltex/common/spec_error.h"

namespace soltex::load {

const char* mix_name(MixKind mix) {
  switch (mix) {
    case MixKind::hot:
      return "hot";
    case MixKind::uniform:
      return "uniform";
    case MixKind::replay:
      return "replay";
  }
  return "?";
}

const char* pattern_kind_name(PatternKind pattern) {
  switch (pattern) {
    case PatternKind::marble:
      return "marble";
    case PatternKind::wood:
      return "wood";
    case PatternKind::turbulence:
      return "turbulence";
    case PatternKind::checker:
      return "checker";
  }
  return "?";
}

const char* codec_choice_name(CodecChoice codec) {
  switch (codec) {
    case CodecChoice::zstd:
      return "zstd";
    case CodecChoice::lz4:
      return "lz4";
    case CodecChoice::raw:
      return "raw";
  }
  return "?";
}

namespace {

// For unsigned options, checked as text: read as unsigned, -1 would become 2^64 - 1.
CLI::Validator not_negative() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return text.starts_with("-") ? "must not be negative" : "";
      },
      "");
}

void require(bool condition, const std::string& message) {
  if (!condition) throw LoadOptionsError(message);
}

// An enum option spelled by name: help shows "hot|uniform|replay" and the default's name.
template <typename Enum>
void add_choice(CLI::App& app, const char* name, Enum& value,
                const std::map<std::string, Enum>& names, const char* help,
                const char* default_name) {
  std::string choices;
  std::vector<std::string> keys;
  for (const auto& [text, unused] : names) {
    choices += (choices.empty() ? "" : "|") + text;
    keys.push_back(text);
  }
  // CLI11 runs the transform added last first: the membership check sees the text the user
  // typed, so a typo is answered with the names rather than with the name-to-value mapping.
  app.add_option(name, value, help)
      ->transform(CLI::Transformer(names, CLI::ignore_case).description(""))
      ->transform(CLI::IsMember(keys, CLI::ignore_case).description(""))
      ->type_name(choices)
      ->default_str(default_name);
}

}  // namespace

void resolve(LoadOptions& o) {
  using B = LoadBounds;
  require(!o.target.empty(), "--server HOST:PORT is required");
  require(o.connections >= 1 && o.connections <= B::kMaxConnections,
          "--connections " + std::to_string(o.connections) + ": must be in [1, " +
              std::to_string(B::kMaxConnections) + "]");
  require(o.streams >= 1 && o.streams <= B::kMaxStreams, "--streams " + std::to_string(o.streams) +
                                                             ": must be in [1, " +
                                                             std::to_string(B::kMaxStreams) + "]");
  if (o.duration_seconds) {
    require(*o.duration_seconds > 0.0 && *o.duration_seconds <= B::kMaxSeconds,
            "--duration-s " + spec_number_text(*o.duration_seconds) + ": must be in (0, " +
                spec_number_text(B::kMaxSeconds) + "] seconds");
  }
  if (o.count) {
    require(*o.count >= 1 && *o.count <= B::kMaxCount, "--count " + std::to_string(*o.count) +
                                                           ": must be in [1, " +
                                                           std::to_string(B::kMaxCount) + "]");
  }
  // Always bounded: a count alone still stops at the time cap.
  if (!o.duration_seconds && !o.count) o.duration_seconds = B::kDefaultDurationSeconds;
  require(o.warmup_seconds >= 0.0 && o.warmup_seconds <= B::kMaxSeconds,
          "--warmup-s " + spec_number_text(o.warmup_seconds) + ": must be in [0, " +
              spec_number_text(B::kMaxSeconds) + "] seconds");
  require(o.drain_timeout_seconds >= 0.0 && o.drain_timeout_seconds <= B::kMaxSeconds,
          "--drain-timeout-s " + spec_number_text(o.drain_timeout_seconds) + ": must be in [0, " +
              spec_number_text(B::kMaxSeconds) + "] seconds");
  require(o.in_flight >= 1 && o.in_flight <= B::kMaxInFlight,
          "--in-flight " + std::to_string(o.in_flight) + ": must be in [1, " +
              std::to_string(B::kMaxInFlight) + "]");
  if (o.rate) {
    require(*o.rate > 0.0 && *o.rate <= B::kMaxRate,
            "--rate " + spec_number_text(*o.rate) + ": must be in (0, " +
                spec_number_text(B::kMaxRate) + "] bricks per second");
    require(o.replay_speed == 0.0, "--rate and --replay-speed both set the send times; give one");
  }
  require(o.hot_set >= 1 && o.hot_set <= B::kMaxHotSet, "--hot-set " + std::to_string(o.hot_set) +
                                                            ": must be in [1, " +
                                                            std::to_string(B::kMaxHotSet) + "]");
  require(o.invalid_fraction >= 0.0 && o.invalid_fraction <= 1.0,
          "--invalid-fraction " + spec_number_text(o.invalid_fraction) + ": must be in [0, 1]");
  require(o.replay_speed >= 0.0 && std::isfinite(o.replay_speed),
          "--replay-speed " + spec_number_text(o.replay_speed) + ": must be >= 0");
  if (o.mix == MixKind::replay) {
    require(!o.replay_file.empty(), "--mix replay needs --replay-file FILE");
  } else {
    require(o.replay_file.empty(), "--replay-file is only used with --mix replay");
    require(o.replay_speed == 0.0, "--replay-speed is only used with --mix replay");
  }
  require(o.brick_size == 8 || o.brick_size == 16,
          "--brick-size " + std::to_string(o.brick_size) + ": must be 8 or 16");
  // The server enforces its own bound (GetServerInfo); this one only keeps the volume sane.
  require(o.finest_level >= 4 && o.finest_level <= 14,
          "--finest-level " + std::to_string(o.finest_level) + ": must be in [4, 14]");
  require((1 << o.finest_level) >= o.brick_size,
          "--finest-level " + std::to_string(o.finest_level) + ": 2^L must be at least " +
              "--brick-size " + std::to_string(o.brick_size));
  require(o.max_backlog_per_stream >= 1, "--max-backlog must be >= 1");
}

void add_load_options(CLI::App& app, LoadOptions& o) {
  const std::map<std::string, MixKind> mixes = {
      {"hot", MixKind::hot}, {"uniform", MixKind::uniform}, {"replay", MixKind::replay}};
  const std::map<std::string, PatternKind> patterns = {{"marble", PatternKind::marble},
                                                       {"wood", PatternKind::wood},
                                                       {"turbulence", PatternKind::turbulence},
                                                       {"checker", PatternKind::checker}};
  const std::map<std::string, CodecChoice> codecs = {
      {"zstd", CodecChoice::zstd}, {"lz4", CodecChoice::lz4}, {"raw", CodecChoice::raw}};
  const std::map<std::string, OutputFormat> formats = {
      {"text", OutputFormat::text}, {"json", OutputFormat::json}, {"csv", OutputFormat::csv}};

  // --target, --duration, --warmup and --drain-timeout are the old names, kept for scripts:
  // every tool now calls the server --server and names a flag's unit at its end.
  app.add_option("--server,--target", o.target, "soltexd gRPC address HOST:PORT")
      ->check(soltex::cli::ServerAddress())
      ->required();
  app.add_flag("--http", o.http,
               "load soltexd's HTTP bricks (--http-listen, or a cache in front) instead of gRPC: "
               "--connections keep-alive connections, one request at a time each, plain HTTP "
               "(the bearer token is sent; the --tls options are refused)");
  app.add_option("--connections", o.connections,
                 "gRPC channels (separate TCP connections); with --http, HTTP connections")
      ->check(soltex::cli::IntegerIn(1, LoadBounds::kMaxConnections))
      ->capture_default_str();
  app.add_option("--streams", o.streams, "StreamBricks streams, spread over the connections")
      ->check(soltex::cli::IntegerIn(1, LoadBounds::kMaxStreams))
      ->capture_default_str();

  app.add_option("--duration-s,--duration", o.duration_seconds,
                 "seconds of measured load after the warmup (default 10 unless --count)");
  app.add_option("--count", o.count, "stop after this many measured brick requests")
      ->check(not_negative());
  app.add_option("--warmup-s,--warmup", o.warmup_seconds,
                 "seconds of load first, left out of the results")
      ->capture_default_str();
  app.add_option("--drain-timeout-s,--drain-timeout", o.drain_timeout_seconds,
                 "seconds to wait for outstanding answers after the stop; the rest are cancelled")
      ->capture_default_str();

  app.add_option("--in-flight", o.in_flight,
                 "closed loop: bricks outstanding per stream (ignored with --rate)")
      ->check(soltex::cli::IntegerIn(1, LoadBounds::kMaxInFlight))
      ->capture_default_str();
  app.add_option("--rate", o.rate,
                 "open loop: bricks per second over all streams, sent at fixed intervals; latency "
                 "counts from each request's intended send time");

  add_choice(app, "--mix", o.mix, mixes,
             "hot: a small repeated key set (cache hits); uniform: random bricks of every "
             "level (mostly cold); replay: a recorded request log",
             mix_name(o.mix));
  app.add_option("--hot-set", o.hot_set, "distinct keys of the hot mix")
      ->check(soltex::cli::IntegerIn(1, LoadBounds::kMaxHotSet))
      ->capture_default_str();
  app.add_option(
      "--replay-file", o.replay_file,
      "request log for --mix replay: a '# soltex-request-log 1' header, then one line per "
      "request: seconds level x y z priority");
  app.add_option("--replay-speed", o.replay_speed,
                 "replay open loop at the recorded times divided by this (0: ignore the times)")
      ->capture_default_str();
  app.add_option("--invalid-fraction", o.invalid_fraction,
                 "fraction of requests for invalid keys: half out of range, half of an unknown "
                 "texture")
      ->capture_default_str();

  add_choice(app, "--pattern", o.pattern, patterns, "texture registered for the run",
             pattern_kind_name(o.pattern));
  app.add_option("--finest-level", o.finest_level, "L: 2^L cells per axis at level 0")
      ->check(soltex::cli::IntegerIn(4, 14))
      ->capture_default_str();
  app.add_option("--brick-size", o.brick_size, "B: 8 or 16 cells per brick edge")
      ->capture_default_str();
  add_choice(app, "--codec", o.codec, codecs, "brick codec to ask for", codec_choice_name(o.codec));

  // Checked as text: an unsigned option would read -1 as 2^64 - 1.
  app.add_option("--seed", o.seed, "random seed of the key choices")
      ->check(not_negative())
      ->capture_default_str();
  app.add_flag("--verify", o.verify,
               "decode every brick and check its checksum (costs client CPU)");
  app.add_option("--max-backlog", o.max_backlog_per_stream,
                 "unsent requests a stream may hold when the server pushes back")
      ->capture_default_str();
  add_choice(app, "--format", o.format, formats, "result format", "text");
  app.add_flag_callback(
      "--no-progress", [&o] { o.progress = false; }, "no progress line on stderr");
}

}  // namespace soltex::load
