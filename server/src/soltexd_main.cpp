// soltexd: evaluates procedural texture bricks on request and streams them over gRPC.
#include <absl/synchronization/mutex.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "daemon.h"
#include "limit_options.h"
#include "soltex/cli/tool_cli.h"

namespace {

using soltex::server::ServerConfig;

void write_ready_file(const std::string& path, int grpc_port, int metrics_port, int http_port) {
  // Written to a temporary name and renamed, so a reader never sees half a file.
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary);
    out << "grpc=" << grpc_port << "\nmetrics=" << metrics_port << "\n";
    if (http_port != 0) out << "http=" << http_port << "\n";
  }
  std::filesystem::rename(temporary, path);
}

}  // namespace

int main(int argc, char** argv) {
  ServerConfig config;
  CLI::App app{"soltexd: procedural solid-texture brick server (gRPC)"};
  app.set_config("--config", "", "read options from a TOML or INI file");
  soltex::cli::add_common_options(app, "soltexd", config.log_level);
  app.add_option("--listen", config.listen, "gRPC address HOST:PORT (port 0: any free port)")
      ->capture_default_str();
  app.add_option("--metrics-listen", config.metrics_listen,
                 "Prometheus metrics address HOST:PORT, served at GET /metrics")
      ->capture_default_str();
  app.add_option("--cache-mb", config.cache_mb, "encoded-brick cache budget in MiB")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  app.add_option("--threads", config.threads, "brick worker threads (0: one per core)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  app.add_option("--zstd-level", config.zstd_level,
                 "zstd compression level for bricks; negative levels search fewer matches "
                 "(literals are entropy coded at every level)")
      ->check(CLI::Range(-1000, 19))
      ->capture_default_str();
  app.add_option("--max-textures", config.max_textures,
                 "textures the registry holds before evicting the least recently used unused one")
      ->check(CLI::Range(1u, 1u << 20))
      ->capture_default_str();
  app.add_option("--max-keys-per-request", config.max_keys_per_request,
                 "brick keys one BrickRequest may want")
      ->check(CLI::Range(1u, 1u << 20))
      ->capture_default_str();
  app.add_option("--max-queued-per-stream", config.max_queued_per_stream,
                 "bricks queued on one stream before RESOURCE_EXHAUSTED")
      ->check(CLI::Range(1u, 1u << 24))
      ->capture_default_str();
  app.add_option("--max-message-bytes", config.max_message_bytes,
                 "largest request message accepted")
      ->check(CLI::Range(1024u, 1u << 30))
      ->capture_default_str();
  app.add_option("--coalesce-bricks", config.coalesce_bricks,
                 "bricks a message waits for while more of its stream's bricks are being made "
                 "(1: send each as soon as the previous message is written)")
      ->check(CLI::Range(1u, 32u))
      ->capture_default_str();
  app.add_option("--coalesce-wait-us", config.coalesce_wait_us,
                 "longest a made brick waits for others to share its message, microseconds")
      ->check(CLI::Range(0u, 1000000u))
      ->capture_default_str();
  app.add_option("--shutdown-grace-s,--shutdown-grace", config.shutdown_grace_seconds,
                 "seconds open calls get to finish on SIGINT/SIGTERM (--shutdown-grace: old name)")
      ->check(CLI::Range(0.0, 600.0))
      ->capture_default_str();
  app.add_option("--ready-file", config.ready_file,
                 "once listening, write 'grpc=PORT', 'metrics=PORT' (and 'http=PORT') lines here");

  auto* web = app.add_option_group("http", "bricks over HTTP/1.1 (docs/PROTOCOL.md, HTTP)");
  web->add_option("--http-listen", config.http_listen,
                  "HTTP brick address HOST:PORT (port 0: any free port); empty: off");
  web->add_option("--http-max-connections", config.http_max_connections,
                  "open HTTP connections; one more is answered 503 and closed")
      ->check(CLI::Range(1u, 1u << 20))
      ->capture_default_str();
  web->add_option("--http-timeout-s", config.http_timeout_seconds,
                  "seconds a request may take to arrive, a response to be written, or a "
                  "keep-alive connection to idle")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  web->add_option("--http-threads", config.http_threads,
                  "HTTP I/O threads (bricks are made on the brick workers)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();

  auto* shared = app.add_option_group("shared cache", "second-level brick cache on memcached");
  shared
      ->add_option("--memcached", config.memcached,
                   "memcached nodes HOST:PORT[,HOST:PORT...] (consistent hashing); empty: off")
      ->delimiter(',');
  shared
      ->add_option("--memcached-timeout-ms", config.memcached_timeout_ms,
                   "connect and I/O timeout; a slower node counts as a miss")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  shared
      ->add_option("--memcached-ttl-s", config.memcached_ttl_seconds,
                   "expiry of shared bricks in seconds (0: until evicted)")
      ->check(CLI::Range(0, 30 * 24 * 3600))
      ->capture_default_str();

  auto* security = app.add_option_group("security", "TLS, tokens and per-client limits");
  security->add_option("--tls-cert", config.tls_cert_file, "server certificate chain (PEM)")
      ->check(CLI::ExistingFile);
  security->add_option("--tls-key", config.tls_key_file, "server private key (PEM)")
      ->check(CLI::ExistingFile);
  security
      ->add_option(
          "--tls-client-ca", config.tls_client_ca_file,
          "CA (PEM) that client certificates must be signed by; set: certificates required")
      ->check(CLI::ExistingFile);
  security
      ->add_option("--token-file", config.token_file,
                   "tokens file ('NAME TOKEN' or 'TOKEN' per line) for BrickService calls")
      ->check(CLI::ExistingFile);
  security->add_option("--token", config.token, "the bearer token itself (prefer --token-file)");
  security
      ->add_option("--max-streams-per-client", config.max_streams_per_client,
                   "open brick streams one client (token name, else address) may hold")
      ->check(CLI::Range(1u, 1u << 20))
      ->capture_default_str();
  security
      ->add_option("--max-queued-per-client", config.max_queued_per_client,
                   "bricks one client may have queued over all its streams")
      ->check(CLI::Range(1u, 1u << 30))
      ->capture_default_str();
  security->add_flag("--trust-forwarded-for", config.trust_forwarded_for)->group("");  // refused
  soltex::server::add_limit_options(*security, config);

  auto* faults = app.add_option_group("faults", "for testing clients against a misbehaving server");
  faults
      ->add_option("--fault-delay-ms", config.faults.delay_ms,
                   "deliver every brick this many milliseconds late")
      ->check(CLI::Range(0, 60000));
  faults
      ->add_option("--fault-corrupt-every", config.faults.corrupt_every,
                   "flip a payload byte in every Nth brick sent (0: never)")
      ->check(CLI::Range(0u, 1u << 30));

  // SOLTEXD_LISTEN and SOLTEXD_TOKEN were the only variables before every option had one.
  if (const auto exit_code = soltex::cli::parse(
          app, "soltexd", argc, argv,
          {{"SOLTEXD_LISTEN", "SOLTEX_LISTEN"}, {"SOLTEXD_TOKEN", "SOLTEX_TOKEN"}})) {
    return *exit_code;
  }
  if (config.max_keys_per_request > config.max_queued_per_stream) {
    std::fprintf(stderr,
                 "--max-keys-per-request (%u) must not exceed --max-queued-per-stream (%u)\n",
                 config.max_keys_per_request, config.max_queued_per_stream);
    return soltex::cli::kExitUsage;
  }
  soltex::cli::start_logging("soltexd", config.log_level, soltex::cli::LogStyle::timestamped);
  soltex::cli::keep_freed_memory();
  // gRPC locks abseil mutexes several times per message; Debian's abseil tracks their lock
  // order for deadlock detection on every acquisition unless told not to.
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);

  std::unique_ptr<soltex::server::Daemon> daemon;
  try {
    daemon = std::make_unique<soltex::server::Daemon>(config);
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return soltex::cli::kExitFailure;
  }
  spdlog::info("soltexd {} listening on {} (gRPC port {}), metrics on http://{}/metrics (port {})",
               SOLTEX_VERSION, config.listen, daemon->grpc_port(), config.metrics_listen,
               daemon->metrics_port());
  if (daemon->http_port() != 0) {
    spdlog::info("HTTP bricks on {} (port {})", config.http_listen, daemon->http_port());
  }
  if (!config.ready_file.empty()) {
    write_ready_file(config.ready_file, daemon->grpc_port(), daemon->metrics_port(),
                     daemon->http_port());
  }

  soltex::server::wait_for_signals(*daemon);  // SIGHUP reloads; SIGINT or SIGTERM returns
  daemon->shut_down();
  return 0;
}
