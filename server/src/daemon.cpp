#include "daemon.h"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <spdlog/fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "soltex/common/brick_layout.h"
#include "soltex/common/text_file.h"
#include "soltex/graph/graph_limits.h"

namespace soltex::server {

using namespace std::chrono_literals;
namespace {

// Why gRPC could not listen on `address`, in the system's words: gRPC reports only that it
// failed, so the same bind is tried once more here (for host:port; a unix socket's path is
// named as it is).
std::string why_not_listening(const std::string& address) {
  if (is_unix_socket_address(address)) return "the socket path cannot be bound";
  try {
    const HostPort at = parse_host_port(address);
    boost::asio::io_context io;
    boost::system::error_code ec;
    boost::asio::ip::tcp::resolver resolver(io);
    const auto found = resolver.resolve(at.host, std::to_string(at.port), ec);
    if (ec || found.empty()) return "cannot resolve " + at.host + " (" + ec.message() + ")";
    boost::asio::ip::tcp::acceptor acceptor(io);
    const boost::asio::ip::tcp::endpoint endpoint = found.begin()->endpoint();
    acceptor.open(endpoint.protocol(), ec);
    if (!ec) acceptor.bind(endpoint, ec);
    if (ec) return ec.message();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "address in use or not a local address";
}

int worker_count(int configured) {
  if (configured > 0) return configured;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

v1::ServerInfo make_info(const ServerConfig& config, int threads) {
  v1::ServerInfo info;
  info.set_version(SOLTEX_VERSION);
  auto* limits = info.mutable_limits();
  limits->set_max_finest_level_log2(SpecLimits::kMaxFinestLevelLog2);
  limits->set_max_keys_per_request(config.max_keys_per_request);
  limits->set_max_queued_per_stream(config.max_queued_per_stream);
  limits->set_max_queued_per_client(config.max_queued_per_client);
  limits->set_max_textures(config.max_textures);
  limits->set_max_message_bytes(config.max_message_bytes);
  limits->set_max_octaves(SpecLimits::kMaxOctaveCount);
  limits->set_max_graph_nodes(graph::GraphLimits::kMaxNodes);
  limits->set_max_graph_depth(graph::GraphLimits::kMaxDepth);
  limits->set_max_graph_cost(graph::GraphLimits::kMaxCostPerSample);
  info.add_brick_sizes(kMinBrickSize);
  info.add_brick_sizes(kMaxBrickSize);
  info.add_codecs(v1::CODEC_ZSTD);
  info.add_codecs(v1::CODEC_LZ4);
  info.add_codecs(v1::CODEC_RAW);
  info.set_worker_threads(static_cast<uint32_t>(threads));
  return info;
}

std::vector<AccessToken> access_tokens(const ServerConfig& config) {
  if (!config.token_file.empty()) return read_access_tokens(config.token_file);
  if (!config.token.empty()) return {AccessToken{"", config.token}};
  return {};
}

AccessConfig access_config(const ServerConfig& config) {
  if (config.trust_forwarded_for) {
    throw std::runtime_error(
        "--trust-forwarded-for trusted x-forwarded-for from any peer and is gone: name the "
        "balancers whose header to trust with --trusted-proxies ADDRESS[/BITS],...");
  }
  AccessConfig access;
  access.tokens = access_tokens(config);
  access.max_streams_per_client = config.max_streams_per_client;
  access.max_queued_per_client = config.max_queued_per_client;
  access.trusted_proxies = parse_address_ranges(config.trusted_proxies);
  return access;
}

RegistryLimits registry_limits(const ServerConfig& config) {
  return {std::size_t{config.registry_mb} << 20, config.max_textures,
          config.max_textures_per_client};
}

std::unique_ptr<SharedBrickCache> shared_cache(const ServerConfig& config, int threads) {
  SharedCacheConfig shared;
  // `memcached = ""` (the example config's "off") reads as one empty address.
  std::copy_if(config.memcached.begin(), config.memcached.end(), std::back_inserter(shared.servers),
               [](const std::string& s) { return !s.empty(); });
  if (shared.servers.empty()) return nullptr;
  shared.timeout_ms = config.memcached_timeout_ms;
  shared.ttl_seconds = config.memcached_ttl_seconds;
  shared.connections = threads;
  spdlog::info("shared brick cache: memcached {} (consistent hashing, {} ms timeout)",
               fmt::join(shared.servers, ","), config.memcached_timeout_ms);
  return std::make_unique<SharedBrickCache>(shared);
}

std::unique_ptr<ReloadableTls> server_tls(const ServerConfig& config) {
  if (config.tls_cert_file.empty() != config.tls_key_file.empty()) {
    throw std::runtime_error("TLS needs both --tls-cert and --tls-key");
  }
  if (config.tls_cert_file.empty()) {
    if (!config.tls_client_ca_file.empty()) {
      throw std::runtime_error("--tls-client-ca needs --tls-cert and --tls-key");
    }
    return nullptr;
  }
  return std::make_unique<ReloadableTls>(
      TlsFiles{config.tls_cert_file, config.tls_key_file, config.tls_client_ca_file});
}

HttpLimits http_limits(const ServerConfig& config) {
  HttpLimits limits;
  limits.max_body_bytes = config.max_message_bytes;
  limits.max_connections = config.http_max_connections;
  limits.max_connections_per_client = config.http_max_connections_per_client;
  limits.unbounded_peers = parse_address_ranges(config.trusted_proxies);
  limits.timeout =
      std::chrono::milliseconds(static_cast<int64_t>(config.http_timeout_seconds * 1000.0));
  limits.threads = config.http_threads;
  return limits;
}

}  // namespace

Daemon::Daemon(const ServerConfig& config)
    : config_(config),
      access_(access_config(config)),
      refusals_([](const std::string& line) { spdlog::warn("{}", line); }),
      tls_(server_tls(config)),
      faults_(config.faults),
      shared_cache_(shared_cache(config, worker_count(config.threads))),
      registry_(registry_limits(config)),
      store_(config.cache_mb << 20),
      scheduler_(worker_count(config.threads), config.direct_request_share),
      producer_(store_, metrics_state_, config.zstd_level, shared_cache_.get(), &faults_) {
  if (config.faults.any()) {
    spdlog::warn("fault injection on: bricks delayed {} ms, every {} brick corrupted (0: none)",
                 config.faults.delay_ms, config.faults.corrupt_every);
  }
  const BrickStream::Context context{
      registry_,
      scheduler_,
      producer_,
      metrics_state_,
      faults_,
      refusals_,
      StreamLimits{config.max_keys_per_request, config.max_queued_per_stream, 32, 1u << 20,
                   config.max_queued_per_client, config.coalesce_bricks,
                   std::chrono::microseconds(config.coalesce_wait_us)}};
  service_ =
      std::make_unique<BrickServiceImpl>(context, access_, make_info(config, scheduler_.threads()));

  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  // A clear error for a bad address (a port over 65535); gRPC checks unix-socket paths itself.
  if (!is_unix_socket_address(config.listen)) (void)parse_host_port(config.listen);
  // Otherwise gRPC sets SO_REUSEPORT, and a second soltexd given a port in use would share it
  // with the first, each taking some of the new connections, instead of failing to start.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.AddListeningPort(
      config.listen, tls_ ? tls_->credentials() : grpc::InsecureServerCredentials(), &grpc_port_);
  builder.RegisterService(service_.get());
  builder.SetMaxReceiveMessageSize(static_cast<int>(config.max_message_bytes));
  // Sees every call, also those gRPC refuses before a handler runs (a message too large).
  std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> interceptors;
  // Our service and gRPC's default health service use the callback API; reflection is sync.
  interceptors.push_back(metrics_state_.grpc_calls.interceptor_factory(
      {v1::BrickService::service_full_name(), "grpc.health.v1.Health"}));
  builder.experimental().SetInterceptorCreators(std::move(interceptors));
  server_ = builder.BuildAndStart();
  if (!server_ || grpc_port_ == 0) {
    throw std::runtime_error("cannot listen for gRPC on " + config.listen + ": " +
                             why_not_listening(config.listen));
  }
  const HostPort metrics_address = parse_host_port(config.metrics_listen);
  metrics_ = std::make_unique<MetricsHttpServer>(metrics_address.host, metrics_address.port,
                                                 [this] { return render_metrics(); });
  if (!config.http_listen.empty()) {
    // With --tls-cert the HTTP endpoint is HTTPS, with the same files (and client CA) as gRPC.
    std::optional<TlsFiles> http_tls;
    if (tls_)
      http_tls = TlsFiles{config.tls_cert_file, config.tls_key_file, config.tls_client_ca_file};
    const HostPort http_address = parse_host_port(config.http_listen);
    http_ = std::make_unique<HttpBrickServer>(
        http_address.host, http_address.port, http_limits(config),
        HttpRequestHandler::Context{registry_, scheduler_, producer_, metrics_state_, access_,
                                    refusals_, &faults_},
        http_tls);
  }
  // Health answers for the service by name as well as for the server ("").
  server_->GetHealthCheckService()->SetServingStatus(v1::BrickService::service_full_name(), true);
  server_->GetHealthCheckService()->SetServingStatus(true);
  start_watchdog();
}

void Daemon::start_watchdog() {
  if (config_.listen_watchdog_seconds <= 0.0) return;
  ListenerWatchdog::Config watchdog;
  watchdog.target = self_target(config_.listen, grpc_port_);
  watchdog.credentials = self_credentials(config_.tls_cert_file, config_.tls_key_file);
  if (!watchdog.credentials) {
    spdlog::warn("no credentials to check the gRPC listener with: --listen-watchdog-s is off");
    return;
  }
  if (tls_) {
    watchdog.tls_server_name =
        certificate_name(read_text_file(config_.tls_cert_file, "TLS certificate"));
  }
  // At most ten new connections a second, however small the period asked for.
  watchdog.interval = std::chrono::milliseconds(
      std::max<int64_t>(100, static_cast<int64_t>(config_.listen_watchdog_seconds * 1000.0)));
  // A dead listener never answers, so a long wait costs only detection time; a short one would
  // count a busy server's slow answer as a miss.
  watchdog.deadline = std::clamp(watchdog.interval, std::chrono::milliseconds(2000),
                                 std::chrono::milliseconds(5000));
  spdlog::debug("checking that gRPC accepts connections on {} every {} ms", watchdog.target,
                watchdog.interval.count());
  watchdog_ =
      std::make_unique<ListenerWatchdog>(watchdog, [this](const std::string& why) { fail(why); });
}

void Daemon::fail(const std::string& why) {
  spdlog::critical("{}; shutting down to exit 1, for a supervisor to restart soltexd", why);
  failed_ = true;
  std::lock_guard lock(failure_mutex_);
  if (on_failure_) on_failure_();
}

void Daemon::on_failure(std::function<void()> stop) {
  std::lock_guard lock(failure_mutex_);
  on_failure_ = std::move(stop);
  if (on_failure_ && failed_) on_failure_();
}

Daemon::~Daemon() {
  shut_down();
}

std::string Daemon::render_metrics() const {
  const std::optional<SharedCacheStats> shared =
      shared_cache_ ? std::optional(shared_cache_->stats()) : std::nullopt;
  const AccessCounts access{reloads_ok_.load(), reloads_failed_.load(), refusals_.suppressed()};
  return metrics_state_.render(store_.stats(), store_.byte_budget(), registry_.stats(),
                               shared ? &*shared : nullptr, faults_.corrupted(), access);
}

void Daemon::reload() {
  try {
    // Everything is read before anything is replaced: a failure changes nothing.
    std::optional<std::vector<AccessToken>> tokens;
    if (!config_.token_file.empty()) tokens = read_access_tokens(config_.token_file);
    if (tls_) tls_->reload();
    if (http_) http_->reload_tls();
    if (tokens) access_.replace_tokens(std::move(*tokens));
    reloads_ok_.fetch_add(1);
    std::vector<std::string> reloaded;
    if (!config_.tls_cert_file.empty()) reloaded.emplace_back("the TLS certificate and key");
    if (!config_.token_file.empty()) reloaded.emplace_back("the tokens file");
    spdlog::info("reloaded {}: open streams go on, new calls use what was read",
                 reloaded.empty() ? std::string("nothing (no TLS files, no tokens file)")
                                  : fmt::format("{}", fmt::join(reloaded, " and ")));
  } catch (const std::exception& e) {
    reloads_failed_.fetch_add(1);
    spdlog::error("reload failed, keeping what was loaded before: {}", e.what());
  }
}

// Streams stop reading and send what they were asked for; those still sending near the
// grace's end drop the rest and end UNAVAILABLE, a little before gRPC would cancel them.
void Daemon::finish_calls_within_grace() {
  const auto grace = std::chrono::duration_cast<std::chrono::milliseconds>(
      std::chrono::duration<double>(config_.shutdown_grace_seconds));
  const auto now = std::chrono::system_clock::now();
  const auto cut = now + grace - std::min<std::chrono::milliseconds>(grace / 10, 500ms);
  std::mutex mutex;
  std::condition_variable calls_done;
  bool done = false;
  std::thread cutter;
  try {
    cutter = std::thread([&] {
      std::unique_lock lock(mutex);
      if (!calls_done.wait_until(lock, cut, [&] { return done; })) {
        spdlog::info("shutting down: the grace is nearly over; open streams end UNAVAILABLE");
        service_->shut_down_streams();
      }
    });
  } catch (const std::system_error& e) {
    // No thread to spare (the process may be out of resources): end the streams now.
    spdlog::warn("shutting down: {}; open streams end UNAVAILABLE now", e.what());
    service_->shut_down_streams();
  }
  server_->Shutdown(now + grace);  // no new calls; returns once the open ones have ended
  {
    std::lock_guard lock(mutex);
    done = true;
  }
  calls_done.notify_all();
  if (cutter.joinable()) cutter.join();
}

void Daemon::shut_down() {
  if (shut_down_) return;
  shut_down_ = true;
  if (watchdog_) watchdog_->stop();
  spdlog::info("shutting down: health NOT_SERVING, open streams get {} s to send what they owe",
               config_.shutdown_grace_seconds);
  // Streams stop reading before health says so: a client that sees NOT_SERVING knows that
  // nothing it sends from then on is read.
  service_->drain_streams();
  server_->GetHealthCheckService()->SetServingStatus(false);
  if (http_) http_->stop_accepting();  // as gRPC takes no new calls during the grace
  finish_calls_within_grace();
  faults_.stop();
  scheduler_.stop();
  if (http_) http_->stop();
  metrics_->stop();
  spdlog::info("shut down");
}

}  // namespace soltex::server
