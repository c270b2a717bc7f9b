// soltex-load against a real soltexd on loopback: what the tool counts agrees with what the
// server counts, errors arrive by code, open-loop latency shows queueing, and request logs
// read back as written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "http_load.h"
#include "load_generator.h"
#include "load_options.h"
#include "load_report.h"
#include "request_log.h"
#include "soltexd_process.h"

namespace soltex::load {
namespace {

using testing::http_get;
using testing::metric_value;
using testing::SoltexdProcess;

constexpr std::size_t kOutOfRange = 11;
constexpr std::size_t kNotFound = 5;

LoadOptions options_for(const SoltexdProcess& server) {
  LoadOptions options;
  options.target = server.grpc_address();
  options.progress = false;
  options.drain_timeout_seconds = 20.0;
  return options;
}

double metric(const SoltexdProcess& server, const std::string& name) {
  return metric_value(http_get(server.metrics_port(), "/metrics"), name);
}

std::string errors_metric(const char* code) {
  return std::string("soltex_errors_total{grpc_code=\"") + code + "\"}";
}

std::string temporary_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          (name + "-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed())))
      .string();
}

TEST(SoltexLoad, BricksReceivedEqualBricksServed) {
  SoltexdProcess server;
  LoadOptions options = options_for(server);
  options.mix = MixKind::hot;
  options.connections = 2;
  options.streams = 4;
  options.in_flight = 8;
  options.warmup_seconds = 0.3;
  options.duration_seconds = 1.0;
  const double served_before = metric(server, "soltex_bricks_served_total");
  const double requested_before = metric(server, "soltex_bricks_requested_total");

  const LoadResult result = run_load(options);

  // The drain ends every stream cleanly, so whatever the server sent was received.
  EXPECT_EQ(result.stream_status[0], 4u);
  EXPECT_EQ(result.stream_failures(), 0u);
  EXPECT_EQ(result.unanswered, 0u);
  EXPECT_EQ(result.measured_errors(), 0u);
  EXPECT_EQ(metric(server, "soltex_bricks_served_total") - served_before,
            static_cast<double>(result.total_bricks));
  EXPECT_EQ(metric(server, "soltex_bricks_requested_total") - requested_before,
            static_cast<double>(result.total_requests));
  EXPECT_EQ(result.total_bricks, result.total_requests);
  // The warmup is counted in the totals only.
  EXPECT_GT(result.bricks, 0u);
  EXPECT_LT(result.bricks, result.total_bricks);
  EXPECT_EQ(result.latency.count, result.bricks);
  // A hot mix is made of cache hits: each of its keys was evaluated once at most.
  EXPECT_LE(metric(server, "soltex_bricks_evaluated_total"), 64.0);
}

TEST(SoltexLoad, CountStopsAtExactlyThatManyBricks) {
  SoltexdProcess server;
  LoadOptions options = options_for(server);
  options.mix = MixKind::uniform;
  options.streams = 3;
  options.in_flight = 5;
  options.count = 500;
  const LoadResult result = run_load(options);
  EXPECT_EQ(result.requests, 500u);
  EXPECT_EQ(result.bricks, 500u);
  EXPECT_EQ(metric(server, "soltex_bricks_served_total"), 500.0);
}

// A server whose messages are small: the tool reads its bound and writes many small requests
// instead of one that would end the stream.
TEST(SoltexLoad, RequestsFitTheServersMessageBound) {
  SoltexdProcess server({"--max-message-bytes", "1024"});
  LoadOptions options = options_for(server);
  options.mix = MixKind::uniform;
  options.in_flight = 512;
  options.count = 2000;
  const LoadResult result = run_load(options);
  EXPECT_EQ(result.stream_failures(), 0u);
  EXPECT_EQ(result.bricks, 2000u);
  EXPECT_EQ(result.unanswered, 0u);
  EXPECT_EQ(metric(server, "soltex_bricks_served_total"), 2000.0);
}

// Streams still owed bricks at --drain-timeout-s are cancelled by the tool itself: a run that
// finished, its unanswered bricks in the report, not a stream that failed.
TEST(SoltexLoad, StreamsLetGoAtTheDrainTimeoutAreNoFailure) {
  SoltexdProcess server({"--fault-delay-ms", "300", "--threads", "1"});
  LoadOptions options = options_for(server);
  options.mix = MixKind::uniform;
  options.in_flight = 8;
  options.warmup_seconds = 0.0;
  options.duration_seconds = 0.5;
  options.drain_timeout_seconds = 0.2;
  const LoadResult result = run_load(options);
  EXPECT_EQ(result.stream_failures(), 0u);
  EXPECT_EQ(result.streams_let_go, 1u);
  EXPECT_GT(result.unanswered, 0u);
}

// Over HTTP, --count sends exactly that many measured requests over all connections: the
// server's count of bricks served agrees with the report. Against a server gone, every
// exchange fails at the connection, which the result counts (soltex-load then exits 1).
TEST(SoltexLoad, HttpCountIsExactAndAGoneServerIsCounted) {
  std::optional<SoltexdProcess> server(std::in_place,
                                       std::vector<std::string>{"--http-listen", "127.0.0.1:0"});
  LoadOptions options = options_for(*server);
  options.target = "127.0.0.1:" + std::to_string(server->http_port());
  options.http = true;
  options.mix = MixKind::uniform;
  options.connections = 8;
  options.warmup_seconds = 0.0;
  options.count = 100;
  const HttpLoadResult counted = run_http_load(options);
  EXPECT_EQ(counted.requests, 100u);
  EXPECT_EQ(metric(*server, "soltex_http_bricks_served_total"), 100.0);

  options.count.reset();
  options.duration_seconds = 1.0;
  std::thread stop([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    server->kill_now();
  });
  const HttpLoadResult gone = run_http_load(options);
  stop.join();
  EXPECT_GT(gone.connection_errors, 0u);
  // Backing off, not spinning on connect(): a few tries per connection, not thousands.
  EXPECT_LT(gone.connection_errors, 8u * 20u);
}

// The server keeps a key at most once in a stream's queue, so the tool must not ask for a key
// it already waits for: with a single hot key every request waits for the one before it.
TEST(SoltexLoad, RepeatedKeysAreAnsweredOneByOne) {
  SoltexdProcess server;
  LoadOptions options = options_for(server);
  options.mix = MixKind::hot;
  options.hot_set = 1;
  options.in_flight = 4;
  options.count = 200;
  const LoadResult closed = run_load(options);
  EXPECT_EQ(closed.bricks, 200u);
  EXPECT_EQ(closed.unanswered, 0u);
  EXPECT_EQ(closed.unexpected, 0u);

  options.in_flight = 8;
  options.count.reset();
  options.rate = 20000.0;  // open loop: requests for the busy key pile up and are parked
  options.duration_seconds = 0.1;
  const LoadResult open = run_load(options);
  EXPECT_GT(open.requests, 100u);
  EXPECT_EQ(open.bricks, open.requests);
  EXPECT_EQ(open.unanswered, 0u);
  EXPECT_EQ(metric(server, "soltex_bricks_served_total"),
            static_cast<double>(closed.total_bricks + open.total_bricks));
}

TEST(SoltexLoad, InvalidKeysAreCountedByStatusCode) {
  SoltexdProcess server;
  LoadOptions options = options_for(server);
  options.mix = MixKind::uniform;
  options.streams = 4;
  options.count = 800;
  options.invalid_fraction = 0.25;

  const LoadResult result = run_load(options);

  EXPECT_GT(result.injected_out_of_range, 0u);
  EXPECT_GT(result.injected_unknown_texture, 0u);
  EXPECT_EQ(result.brick_errors[kOutOfRange], result.injected_out_of_range);
  EXPECT_EQ(result.brick_errors[kNotFound], result.injected_unknown_texture);
  EXPECT_EQ(result.measured_errors(),
            result.injected_out_of_range + result.injected_unknown_texture);
  EXPECT_EQ(result.bricks + result.measured_errors(), 800u);
  EXPECT_EQ(metric(server, errors_metric("OUT_OF_RANGE")),
            static_cast<double>(result.injected_out_of_range));
  EXPECT_EQ(metric(server, errors_metric("NOT_FOUND")),
            static_cast<double>(result.injected_unknown_texture));
  EXPECT_EQ(result.stream_failures(), 0u);

  const nlohmann::json json = nlohmann::json::parse(format_json(result));
  EXPECT_EQ(json["errors"]["bricks"]["OUT_OF_RANGE"].get<uint64_t>(), result.injected_out_of_range);
  EXPECT_EQ(json["errors"]["bricks"]["NOT_FOUND"].get<uint64_t>(), result.injected_unknown_texture);
  EXPECT_NE(format_text(result).find("OUT_OF_RANGE"), std::string::npos);
}

TEST(SoltexLoad, CorruptBricksShowInTheSummaryBesideTheErrors) {
  SoltexdProcess server({"--fault-corrupt-every", "3"});
  LoadOptions options = options_for(server);
  options.mix = MixKind::uniform;
  options.count = 300;
  options.verify = true;

  const LoadResult result = run_load(options);

  EXPECT_EQ(static_cast<double>(result.checksum_failures),
            metric(server, "soltex_faults_corrupted_total"));
  EXPECT_GE(result.checksum_failures, 300u / 3 - 1);
  const std::string text = format_text(result);
  EXPECT_NE(text.find("Corrupt:       " + std::to_string(result.checksum_failures) +
                      " bricks failed --verify"),
            std::string::npos)
      << text;
}

TEST(SoltexLoad, NoAnswerPrintsNoLatencies) {
  SoltexdProcess server({"--fault-delay-ms", "5000"});
  LoadOptions options = options_for(server);
  options.duration_seconds = 0.3;
  options.drain_timeout_seconds = 0.2;

  const LoadResult result = run_load(options);

  ASSERT_EQ(result.bricks, 0u);
  const std::string text = format_text(result);
  EXPECT_NE(text.find("(no bricks answered)"), std::string::npos) << text;
  EXPECT_EQ(text.find("p50"), std::string::npos) << text;
}

// Above saturation an open-loop client keeps sending on schedule, so the server's queue
// grows and each brick's latency, counted from its intended send time, includes the wait.
TEST(SoltexLoad, OpenLoopLatencyIncludesQueueingAboveSaturation) {
  SoltexdProcess server({"--threads", "1"});
  LoadOptions options = options_for(server);
  options.mix = MixKind::uniform;
  options.finest_level = 10;  // about 300,000 bricks: nearly every request is a cold one

  LoadOptions light = options;  // well below what one worker evaluates
  light.rate = 100.0;
  light.count = 100;
  light.seed = 11;
  const LoadResult unloaded = run_load(light);

  LoadOptions heavy = options;  // far above it: 2,000 requests in 20 ms
  heavy.rate = 100000.0;
  heavy.count = 2000;
  heavy.seed = 12;
  const LoadResult saturated = run_load(heavy);

  ASSERT_EQ(unloaded.bricks, 100u);
  ASSERT_EQ(saturated.bricks, 2000u);
  EXPECT_EQ(saturated.stream_failures(), 0u);
  // The last requests wait for about all the others: the median for about half of them.
  EXPECT_GT(saturated.latency.p50, 10 * unloaded.latency.p50)
      << "unloaded p50 " << unloaded.latency.p50 << " ns, saturated p50 " << saturated.latency.p50
      << " ns";
  EXPECT_GT(saturated.latency.max, saturated.latency.p50);
}

std::vector<RecordedRequest> sample_log() {
  std::vector<RecordedRequest> log;
  // Valid for L = 8, B = 16: levels 0..4, 16 >> level bricks per axis.
  for (int i = 0; i < 40; ++i) {
    const int level = i % 5;
    const int n = 16 >> level;
    log.push_back({i / 100.0,  // whole microseconds: written exactly
                   level, (i * 7) % n, (i * 3) % n, (i * 5) % n, 100 - 3 * i});
  }
  return log;
}

TEST(SoltexLoad, RequestLogRoundTrip) {
  const std::vector<RecordedRequest> log = sample_log();
  const std::string path = temporary_path("soltex-request-log");
  write_request_log_file(path, log);
  EXPECT_EQ(read_request_log_file(path), log);
  std::filesystem::remove(path);

  std::istringstream bad(std::string(kRequestLogHeader) +
                         "\n0.5 1 2 3 4 5\n# note\n0.25 1 2 3 4 5\n");
  try {
    read_request_log(bad, "bad.log");
    FAIL() << "a decreasing time was accepted";
  } catch (const RequestLogError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.log:4:"), std::string::npos) << e.what();
  }
  std::istringstream short_line(std::string(kRequestLogHeader) + "\n0.5 1 2 3\n");
  EXPECT_THROW(read_request_log(short_line, "short.log"), RequestLogError);
  std::istringstream no_header("0.5 1 2 3 4 5\n");
  EXPECT_THROW(read_request_log(no_header, "headerless.log"), RequestLogError);
  // Times are bounded, so every accepted line can be written back whole.
  std::istringstream huge_time(std::string(kRequestLogHeader) + "\n1e300 0 0 0 0 0\n");
  EXPECT_THROW(read_request_log(huge_time, "huge.log"), RequestLogError);
  std::ostringstream out;
  RequestLogWriter writer(out);
  EXPECT_THROW(writer.append({1e300, 0, 0, 0, 0, 0}), RequestLogError);
}

TEST(SoltexLoad, ReplaysARecordedLog) {
  SoltexdProcess server;
  const std::vector<RecordedRequest> log = sample_log();
  const std::string path = temporary_path("soltex-replay-log");
  write_request_log_file(path, log);

  LoadOptions options = options_for(server);
  options.mix = MixKind::replay;
  options.replay_file = path;
  options.streams = 2;
  options.count = log.size();
  const LoadResult closed = run_load(options);
  EXPECT_EQ(closed.bricks, log.size());
  EXPECT_EQ(closed.measured_errors(), 0u);
  EXPECT_EQ(metric(server, "soltex_bricks_requested_total"), static_cast<double>(log.size()));

  // At the recorded times: the last request cannot go before its offset.
  options.replay_speed = 1.0;
  const LoadResult timed = run_load(options);
  EXPECT_EQ(timed.bricks, log.size());
  EXPECT_GE(timed.elapsed_seconds, log.back().seconds);
  std::filesystem::remove(path);
}

TEST(SoltexLoad, OptionsAreBoundedAndNamed) {
  LoadOptions options;
  options.target = "127.0.0.1:1";
  resolve(options);
  ASSERT_TRUE(options.duration_seconds.has_value());  // always bounded
  EXPECT_EQ(*options.duration_seconds, LoadBounds::kDefaultDurationSeconds);

  const auto message = [](LoadOptions o) {
    o.target = "127.0.0.1:1";
    try {
      resolve(o);
    } catch (const LoadOptionsError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  LoadOptions o;
  o.duration_seconds = 1e6;
  EXPECT_NE(message(o).find("--duration"), std::string::npos);
  o = {};
  o.invalid_fraction = 1.5;
  EXPECT_NE(message(o).find("--invalid-fraction"), std::string::npos);
  o = {};
  o.mix = MixKind::replay;
  EXPECT_NE(message(o).find("--replay-file"), std::string::npos);
  o = {};
  o.rate = 10.0;
  o.replay_speed = 1.0;
  EXPECT_NE(message(o).find("--rate"), std::string::npos);
}

// The row of a CSV report that must be a header and one row with as many fields.
std::string csv_row(const std::string& csv) {
  std::istringstream lines(csv);
  std::string header, row, extra;
  EXPECT_TRUE(std::getline(lines, header));
  EXPECT_TRUE(std::getline(lines, row));
  EXPECT_FALSE(std::getline(lines, extra)) << csv;
  EXPECT_EQ(std::count(header.begin(), header.end(), ','), std::count(row.begin(), row.end(), ','))
      << csv;
  return row;
}

TEST(SoltexLoad, CsvIsAHeaderAndOneRow) {
  LoadResult result;
  result.options.target = "127.0.0.1:1";
  result.bricks = 10;
  result.measured_seconds = 2.0;
  const std::string row = csv_row(format_csv(result));
  EXPECT_NE(row.find(",5.000,"), std::string::npos) << row;  // 10 bricks in 2 s
}

TEST(SoltexLoad, HttpCsvIsAHeaderAndOneRowToo) {
  HttpLoadResult result;
  result.connections = 4;
  result.bricks = 10;
  result.statuses = {{200, 10}, {404, 2}};
  result.p50_us = 1500.0;
  const std::string row = csv_row(format_http_result(result, OutputFormat::csv));
  EXPECT_EQ(row.substr(0, 5), "http,") << row;
  EXPECT_NE(row.find(",1.5,"), std::string::npos) << row;   // p50 in ms
  EXPECT_NE(row.find(",2,0,0"), std::string::npos) << row;  // two answers other than 200
}

}  // namespace
}  // namespace soltex::load
