#include "http_load.h"

#include <atomic>
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <chrono>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>
#include <vector>

#include "load_generator.h"
#include "load_texture.h"
#include "request_mix.h"
#include "soltex/common/brick_codec.h"
#include "soltex/common/latency_histogram.h"
#include "soltex/scene/texture_spec_json.h"
#include "soltex/spec_proto/spec_from_proto.h"

namespace soltex::load {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
using tcp = boost::asio::ip::tcp;
using Clock = std::chrono::steady_clock;

struct Target {
  std::string host;
  std::string port;
};

Target split_target(const std::string& target) {
  const std::size_t colon = target.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == target.size()) {
    throw LoadOptionsError("--server '" + target + "' must be HOST:PORT");
  }
  return {target.substr(0, colon), target.substr(colon + 1)};
}

// The run's texture as the HTTP endpoint reads it (the gRPC registration, in JSON).
std::string registration_json(const LoadOptions& options) {
  const v1::RegisterTextureRequest request = texture_registration(options);
  const Volume volume = from_proto(request.volume());
  nlohmann::json body;
  body["texture"] = texture_spec_to_json(from_proto(request.spec()));
  body["volume"] = {{"min", {volume.min.x, volume.min.y, volume.min.z}},
                    {"max", {volume.max.x, volume.max.y, volume.max.z}},
                    {"finest_level_log2", volume.finest_level_log2}};
  body["brick_size"] = request.brick_size();
  body["mip_mode"] = "band_limited";
  return body.dump();
}

// One keep-alive connection, reopened after a failed exchange. Every request carries the
// bearer token, when there is one, as gRPC calls carry it (docs/PROTOCOL.md, HTTP).
class Connection {
 public:
  Connection(Target target, std::string token)
      : target_(std::move(target)), token_(std::move(token)), socket_(io_) {}

  http::response<http::string_body> exchange(http::request<http::string_body>& request) {
    if (!socket_.is_open()) {
      tcp::resolver resolver(io_);
      boost::asio::connect(socket_, resolver.resolve(target_.host, target_.port));
    }
    request.set(http::field::host, target_.host);
    if (!token_.empty()) request.set(http::field::authorization, "Bearer " + token_);
    request.keep_alive(true);
    request.prepare_payload();
    http::write(socket_, request);
    http::response_parser<http::string_body> parser;
    parser.body_limit(64u << 20);
    http::read(socket_, buffer_, parser);
    http::response<http::string_body> response = parser.release();
    if (!response.keep_alive()) close();
    return response;
  }

  void close() {
    beast::error_code ignored;
    socket_.close(ignored);
    buffer_.clear();
  }

 private:
  Target target_;
  std::string token_;
  boost::asio::io_context io_;
  tcp::socket socket_;
  beast::flat_buffer buffer_;
};

struct Handle {
  std::string id;
  std::string bricks;  // the URL template
  TextureShape shape;
};

Handle register_over_http(const LoadOptions& options, const Target& target) {
  Connection connection(target, options.security.token);
  http::request<http::string_body> request{http::verb::post, "/v1/textures", 11};
  request.set(http::field::content_type, "application/json");
  request.body() = registration_json(options);
  http::response<http::string_body> response;
  try {
    response = connection.exchange(request);
  } catch (const std::exception& e) {
    throw LoadSetupError("POST /v1/textures to " + options.target + " failed: " + e.what());
  }
  if (response.result_int() != 200) {
    throw LoadSetupError("POST /v1/textures to " + options.target + " was answered " +
                         std::to_string(response.result_int()) + ": " + response.body());
  }
  const nlohmann::json handle = nlohmann::json::parse(response.body());
  Handle out;
  out.id = handle.at("id").get<std::string>();
  out.bricks = handle.at("bricks").get<std::string>();
  out.shape.texture_id = std::stoull(out.id, nullptr, 16);
  out.shape.level_count = handle.at("levels").get<int>();
  out.shape.brick_size = handle.at("brick_size").get<int>();
  return out;
}

std::string brick_target(const Handle& handle, const BrickKey& key, CodecChoice codec) {
  std::string target = handle.bricks;
  const std::string placeholder = "{level}/{x}/{y}/{z}";
  const std::string path = std::to_string(key.level) + "/" + std::to_string(key.brick.x) + "/" +
                           std::to_string(key.brick.y) + "/" + std::to_string(key.brick.z);
  target.replace(target.find(placeholder), placeholder.size(), path);
  if (key.texture == handle.shape.texture_id) return target + "&codec=" + codec_choice_name(codec);
  // An unknown texture (the invalid mix): its id without the real one's spec, which the server
  // would refuse as another texture's (400) before finding the id unknown (404, as NOT_FOUND
  // over gRPC).
  char id[17];
  std::snprintf(id, sizeof id, "%016llx", static_cast<unsigned long long>(key.texture));
  target.erase(target.find('?'));
  target.replace(target.find(handle.id), handle.id.size(), id);
  return target + "?codec=" + codec_choice_name(codec);
}

// What every connection thread adds up, merged under one lock at its end.
struct Tally {
  uint64_t requests = 0, bricks = 0, bytes = 0, checksum_failures = 0, connection_errors = 0;
  std::map<int, uint64_t> statuses;
  std::map<std::string, uint64_t> cache_statuses;
};

// Takes one of the requests left, or false when none is.
bool take_one(std::atomic<uint64_t>& left) {
  uint64_t now = left.load();
  do {
    if (now == 0) return false;
  } while (!left.compare_exchange_weak(now, now - 1));
  return true;
}

// After a failed exchange (a server gone, refusing connections): a pause before the next
// attempt, 10 ms doubling to 1 s while failures go on, so a run against a dead server does not
// spin on connect().
class ReconnectBackoff {
 public:
  void succeeded() { pause_ = kFirst; }
  void wait(Clock::time_point stop_at) {
    std::this_thread::sleep_until(std::min(Clock::now() + pause_, stop_at));
    pause_ = std::min(pause_ * 2, kMost);
  }

 private:
  static constexpr std::chrono::milliseconds kFirst{10}, kMost{1000};
  std::chrono::milliseconds pause_ = kFirst;
};

void run_connection(const LoadOptions& options, const Target& target, const Handle& handle,
                    RequestMix& mix, Clock::time_point measure_from, Clock::time_point stop_at,
                    std::atomic<uint64_t>& measured_left, LatencyHistogram& latency, Tally& tally) {
  Connection connection(target, options.security.token);
  const RequestMix::Busy never_busy = [](const BrickKey&) { return false; };
  ReconnectBackoff backoff;
  while (Clock::now() < stop_at) {
    const PlannedWant want = mix.next(never_busy);
    http::request<http::string_body> request{http::verb::get,
                                             brick_target(handle, want.key, options.codec), 11};
    const Clock::time_point sent = Clock::now();
    const bool measured = sent >= measure_from;
    // --count: a measured request takes its place before it goes, so that no more than that
    // many are sent over all threads (the server's counters then agree with the report).
    if (measured && !take_one(measured_left)) return;
    http::response<http::string_body> response;
    try {
      response = connection.exchange(request);
      backoff.succeeded();
    } catch (const std::exception&) {
      if (measured) measured_left.fetch_add(1);
      connection.close();
      ++tally.connection_errors;
      backoff.wait(stop_at);
      continue;
    }
    if (!measured) continue;
    latency.record(static_cast<uint64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - sent).count()));
    ++tally.requests;
    ++tally.statuses[response.result_int()];
    const auto cache = response.find("X-Cache-Status");
    ++tally.cache_statuses[cache == response.end() ? std::string("none")
                                                   : std::string(cache->value())];
    if (response.result_int() != 200) continue;
    ++tally.bricks;
    tally.bytes += response.body().size();
    if (options.verify) {
      try {
        (void)decode_brick(std::span(reinterpret_cast<const uint8_t*>(response.body().data()),
                                     response.body().size()));
      } catch (const CodecError&) {
        ++tally.checksum_failures;
      }
    }
  }
}

}  // namespace

HttpLoadResult run_http_load(const LoadOptions& options) {
  if (options.mix == MixKind::replay) throw LoadOptionsError("--http takes --mix hot or uniform");
  if (options.open_loop()) throw LoadOptionsError("--http runs closed loop: leave out --rate");
  if (options.security.tls() || !options.security.tls_cert_file.empty()) {
    throw LoadOptionsError(
        "--http speaks plain HTTP: --tls-ca, --tls-cert and --tls-key are for gRPC (load an "
        "HTTPS listener through a TLS-terminating proxy, or over gRPC)");
  }
  const Target target = split_target(options.target);
  const Handle handle = register_over_http(options, target);
  MixSettings settings;
  settings.kind = options.mix;
  settings.hot_set = options.hot_set;
  settings.invalid_fraction = options.invalid_fraction;
  settings.seed = options.seed;
  std::vector<std::unique_ptr<RequestMix>> mixes =
      make_request_mixes(settings, handle.shape, options.connections);

  const double seconds = options.duration_seconds.value_or(
      options.count ? LoadBounds::kMaxSeconds : LoadBounds::kDefaultDurationSeconds);
  const Clock::time_point start = Clock::now();
  const auto measure_from = start + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(options.warmup_seconds));
  const auto stop_at = measure_from + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(seconds));
  LatencyHistogram latency;
  std::atomic<uint64_t> measured_left{options.count.value_or(UINT64_MAX)};
  std::vector<Tally> tallies(static_cast<std::size_t>(options.connections));
  std::vector<std::thread> threads;
  for (int c = 0; c < options.connections; ++c) {
    threads.emplace_back([&, c] {
      run_connection(options, target, handle, *mixes[static_cast<std::size_t>(c)], measure_from,
                     stop_at, measured_left, latency, tallies[static_cast<std::size_t>(c)]);
    });
  }
  for (std::thread& thread : threads) thread.join();
  const double measured = std::chrono::duration<double>(Clock::now() - measure_from).count();

  HttpLoadResult result;
  result.seconds = measured;
  result.connections = options.connections;
  result.texture_id = handle.id;
  for (const Tally& t : tallies) {
    result.requests += t.requests;
    result.bricks += t.bricks;
    result.bytes += t.bytes;
    result.checksum_failures += t.checksum_failures;
    result.connection_errors += t.connection_errors;
    for (const auto& [status, n] : t.statuses) result.statuses[status] += n;
    for (const auto& [value, n] : t.cache_statuses) result.cache_statuses[value] += n;
  }
  result.bricks_per_second = measured > 0 ? static_cast<double>(result.bricks) / measured : 0.0;
  result.p50_us = static_cast<double>(latency.value_at_percentile(50.0)) / 1e3;
  result.p90_us = static_cast<double>(latency.value_at_percentile(90.0)) / 1e3;
  result.p99_us = static_cast<double>(latency.value_at_percentile(99.0)) / 1e3;
  result.max_us = static_cast<double>(latency.max()) / 1e3;
  return result;
}

namespace {

// A header and one row, as the gRPC mode's CSV, for a spreadsheet of runs.
std::string format_http_csv(const HttpLoadResult& r) {
  uint64_t not_ok = 0;  // answers other than 200
  for (const auto& [status, n] : r.statuses) not_ok += status == 200 ? 0 : n;
  std::ostringstream out;
  out << "mode,texture_id,connections,measured_s,requests,bricks,bricks_per_s,bytes,p50_ms,"
         "p90_ms,p99_ms,max_ms,not_ok_responses,checksum_failures,connection_errors\n";
  out << "http," << r.texture_id << "," << r.connections << "," << r.seconds << "," << r.requests
      << "," << r.bricks << "," << r.bricks_per_second << "," << r.bytes << "," << r.p50_us / 1e3
      << "," << r.p90_us / 1e3 << "," << r.p99_us / 1e3 << "," << r.max_us / 1e3 << "," << not_ok
      << "," << r.checksum_failures << "," << r.connection_errors << "\n";
  return out.str();
}

}  // namespace

std::string format_http_result(const HttpLoadResult& r, OutputFormat format) {
  if (format == OutputFormat::json) {
    nlohmann::json out;
    out["mode"] = "http";
    out["texture_id"] = r.texture_id;
    out["seconds"] = r.seconds;
    out["connections"] = r.connections;
    out["requests"] = r.requests;
    out["bricks"] = r.bricks;
    out["bytes"] = r.bytes;
    out["bricks_per_second"] = r.bricks_per_second;
    out["latency_us"] = {
        {"p50", r.p50_us}, {"p90", r.p90_us}, {"p99", r.p99_us}, {"max", r.max_us}};
    nlohmann::json statuses = nlohmann::json::object();
    for (const auto& [status, n] : r.statuses) statuses[std::to_string(status)] = n;
    out["statuses"] = statuses;
    out["cache_statuses"] = r.cache_statuses;
    out["checksum_failures"] = r.checksum_failures;
    out["connection_errors"] = r.connection_errors;
    return out.dump(2) + "\n";
  }
  if (format == OutputFormat::csv) return format_http_csv(r);
  std::ostringstream out;
  out << "http load: " << r.connections << " keep-alive connections, " << r.seconds
      << " s measured, texture " << r.texture_id << "\n";
  out << "requests: " << r.requests << ", bricks: " << r.bricks << " (" << r.bricks_per_second
      << " bricks/s), bytes: " << r.bytes << "\n";
  out << "latency us: p50 " << r.p50_us << ", p90 " << r.p90_us << ", p99 " << r.p99_us << ", max "
      << r.max_us << "\n";
  out << "statuses:";
  for (const auto& [status, n] : r.statuses) out << " " << status << "=" << n;
  out << "\ncache (X-Cache-Status):";
  for (const auto& [value, n] : r.cache_statuses) out << " " << value << "=" << n;
  out << "\nchecksum failures: " << r.checksum_failures
      << ", connection errors: " << r.connection_errors << "\n";
  return out.str();
}

}  // namespace soltex::load
