#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "soltex/net/channel_security.h"

namespace CLI {
class App;
}

// What one soltex-load run does, and how it is spelled on the command line.
namespace soltex::load {

enum class MixKind { hot, uniform, replay };
enum class OutputFormat { text, json, csv };
enum class PatternKind { marble, wood, turbulence, checker };
enum class CodecChoice { zstd, lz4, raw };

const char* mix_name(MixKind mix);
const char* pattern_kind_name(PatternKind pattern);
const char* codec_choice_name(CodecChoice codec);

// Every run stops by itself: these bound what the options can ask for.
struct LoadBounds {
  static constexpr double kDefaultDurationSeconds = 10.0;  // when neither duration nor count
  static constexpr double kMaxSeconds = 3600.0;            // duration, warmup, drain timeout
  static constexpr uint64_t kMaxCount = 1'000'000'000;
  static constexpr int kMaxConnections = 1024;
  static constexpr int kMaxStreams = 16384;
  static constexpr int kMaxInFlight = 65536;
  static constexpr double kMaxRate = 10'000'000.0;
  static constexpr int kMaxHotSet = 1'000'000;
  // Requests a stream may hold unsent when the server pushes back (open loop); beyond it a
  // request is dropped and counted, so an open-loop run cannot exhaust the client's memory.
  static constexpr std::size_t kDefaultMaxBacklogPerStream = 1'000'000;
};

struct LoadOptions {
  std::string target;  // --server HOST:PORT
  bool http = false;   // --http: the HTTP brick path (http_load.h) instead of gRPC streams
  net::ChannelSecurity security;
  int connections = 1;
  int streams = 1;

  // Stop conditions; resolve() fills `duration_seconds` when neither is given.
  std::optional<double> duration_seconds;
  std::optional<uint64_t> count;
  double warmup_seconds = 0.0;
  double drain_timeout_seconds = 10.0;  // after the stop: time for answers still owed

  // Closed loop: `in_flight` bricks outstanding per stream. Open loop when `rate` is set.
  int in_flight = 8;
  std::optional<double> rate;  // bricks per second over all streams

  MixKind mix = MixKind::hot;
  int hot_set = 64;
  std::string replay_file;
  double replay_speed = 0.0;  // > 0: open loop at the recorded times divided by this
  double invalid_fraction = 0.0;

  PatternKind pattern = PatternKind::marble;
  int finest_level = 8;
  int brick_size = 16;
  CodecChoice codec = CodecChoice::zstd;

  uint64_t seed = 1;
  bool verify = false;  // decode every brick and check its checksum
  std::size_t max_backlog_per_stream = LoadBounds::kDefaultMaxBacklogPerStream;

  OutputFormat format = OutputFormat::text;
  bool progress = true;  // a line on stderr once per second

  bool open_loop() const { return rate.has_value() || replay_speed > 0.0; }
};

class LoadOptionsError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Checks every combination the command line cannot check one option at a time, and applies
// the default stop condition. Throws LoadOptionsError naming the option and the bound.
void resolve(LoadOptions& options);

// Declares every option on `app`, writing into `options` (CLI11 keeps the reference).
void add_load_options(CLI::App& app, LoadOptions& options);

}  // namespace soltex::load
