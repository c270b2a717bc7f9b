#include "daemon.h"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "soltex/common/brick_layout.h"

namespace soltex::server {
namespace {

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
  limits->set_max_textures(config.max_textures);
  limits->set_max_message_bytes(config.max_message_bytes);
  limits->set_max_octaves(SpecLimits::kMaxOctaveCount);
  info.add_brick_sizes(kMinBrickSize);
  info.add_brick_sizes(kMaxBrickSize);
  info.add_codecs(v1::CODEC_ZSTD);
  info.add_codecs(v1::CODEC_LZ4);
  info.add_codecs(v1::CODEC_RAW);
  info.set_worker_threads(static_cast<uint32_t>(threads));
  return info;
}

}  // namespace

Daemon::Daemon(const ServerConfig& config)
    : config_(config),
      registry_(config.max_textures),
      store_(config.cache_mb << 20),
      scheduler_(worker_count(config.threads)),
      producer_(store_, metrics_state_, config.zstd_level) {
  const BrickStream::Context context{
      registry_, scheduler_, producer_, metrics_state_,
      StreamLimits{config.max_keys_per_request, config.max_queued_per_stream, 32, 1u << 20}};
  service_ = std::make_unique<BrickServiceImpl>(context, make_info(config, scheduler_.threads()));

  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(config.listen, grpc::InsecureServerCredentials(), &grpc_port_);
  builder.RegisterService(service_.get());
  builder.SetMaxReceiveMessageSize(static_cast<int>(config.max_message_bytes));
  server_ = builder.BuildAndStart();
  if (!server_ || grpc_port_ == 0) {
    throw std::runtime_error("cannot listen for gRPC on " + config.listen +
                             " (address in use or not a local address?)");
  }
  const HostPort metrics_address = parse_host_port(config.metrics_listen);
  metrics_ = std::make_unique<MetricsHttpServer>(metrics_address.host, metrics_address.port,
                                                 [this] { return render_metrics(); });
  server_->GetHealthCheckService()->SetServingStatus(true);
}

Daemon::~Daemon() {
  shut_down();
}

std::string Daemon::render_metrics() const {
  return metrics_state_.render(store_.stats(), store_.byte_budget(), registry_.size());
}

void Daemon::shut_down() {
  if (shut_down_) return;
  shut_down_ = true;
  spdlog::info("shutting down: health NOT_SERVING, finishing open streams");
  server_->GetHealthCheckService()->SetServingStatus(false);
  service_->shut_down_streams();
  const auto grace = std::chrono::duration_cast<std::chrono::milliseconds>(
      std::chrono::duration<double>(config_.shutdown_grace_seconds));
  server_->Shutdown(std::chrono::system_clock::now() + grace);
  scheduler_.stop();
  metrics_->stop();
  spdlog::info("shut down");
}

}  // namespace soltex::server
