#include "soltexd_options.h"

#include <fstream>
#include <sstream>

#include "access_tokens.h"
#include "address_range.h"
#include "soltex/cli/tool_cli.h"

namespace soltex::server {

namespace {

// What an address option accepts besides HOST:PORT with a port in [0, 65535].
struct AddressForm {
  bool allow_empty = false;  // an empty address turns the endpoint off
  bool allow_unix = false;   // gRPC's unix-socket addresses (unix:PATH, unix-abstract:NAME)
  bool dialed = false;       // an address soltexd connects to: port 0 names no server
};

// HOST:PORT as the daemon reads it (parse_host_port()), refused at parse time with its
// message.
CLI::Validator host_port(AddressForm form) {
  return CLI::Validator(
      [form](std::string& text) -> std::string {
        if (form.allow_empty && text.empty()) return {};
        if (is_unix_socket_address(text)) {
          if (!form.allow_unix) return "address '" + text + "': a unix socket is not served here";
          const std::size_t colon = text.find(':');
          if (colon + 1 == text.size()) return "address '" + text + "' names no socket path";
          return {};
        }
        try {
          if (parse_host_port(text).port == 0 && form.dialed) {
            return "address '" + text + "': port must be in [1, 65535]";
          }
          return {};
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
      },
      "HOST:PORT");
}

// Where soltexd listens and how it makes, caches and sends bricks.
void add_serving_options(CLI::App& app, ServerConfig& config) {
  app.add_option("--listen", config.listen,
                 "gRPC address HOST:PORT (port 0: any free port), or unix:PATH")
      ->check(host_port({.allow_unix = true}))
      ->capture_default_str();
  app.add_option("--metrics-listen", config.metrics_listen,
                 "Prometheus metrics address HOST:PORT, served at GET /metrics")
      ->check(host_port({}))
      ->capture_default_str();
  app.add_option("--cache-mb", config.cache_mb, "encoded-brick cache budget in MiB")
      ->check(cli::IntegerIn(1, 1 << 20))
      ->capture_default_str();
  app.add_option("--threads", config.threads, "brick worker threads (0: one per core)")
      ->check(cli::IntegerIn(0, 1024))
      ->capture_default_str();
  app.add_option("--zstd-level", config.zstd_level,
                 "zstd compression level for bricks; negative levels search fewer matches "
                 "(literals are entropy coded at every level)")
      ->check(cli::IntegerIn(-1000, 19))
      ->capture_default_str();
  app.add_option("--max-textures", config.max_textures,
                 "textures the registry holds before evicting the least recently used unused one")
      ->check(cli::IntegerIn(1u, 1u << 20))
      ->capture_default_str();
  app.add_option("--max-keys-per-request", config.max_keys_per_request,
                 "brick keys one BrickRequest may want")
      ->check(cli::IntegerIn(1u, 1u << 20))
      ->capture_default_str();
  app.add_option("--max-queued-per-stream", config.max_queued_per_stream,
                 "bricks queued on one stream before RESOURCE_EXHAUSTED")
      ->check(cli::IntegerIn(1u, 1u << 24))
      ->capture_default_str();
  app.add_option("--max-message-bytes", config.max_message_bytes,
                 "largest request message accepted")
      ->check(cli::IntegerIn(1024u, 1u << 30))
      ->capture_default_str();
  app.add_option("--coalesce-bricks", config.coalesce_bricks,
                 "bricks a message waits for while more of its stream's bricks are being made "
                 "(1: send each as soon as the previous message is written)")
      ->check(cli::IntegerIn(1u, 32u))
      ->capture_default_str();
  app.add_option("--coalesce-wait-us", config.coalesce_wait_us,
                 "longest a made brick waits for others to share its message, microseconds")
      ->check(cli::IntegerIn(0u, 1000000u))
      ->capture_default_str();
  app.add_option("--direct-request-share", config.direct_request_share,
                 "threads' worth of time gRPC's threads may spend handling stream requests "
                 "themselves; past it a request waits for a brick worker's turn, shared fairly "
                 "between clients (0: every request does)")
      ->check(soltex::cli::NumberIn(0.0, 64.0))
      ->capture_default_str();
  app.add_option("--shutdown-grace-s,--shutdown-grace", config.shutdown_grace_seconds,
                 "seconds open calls get to finish on SIGINT/SIGTERM (--shutdown-grace: old name)")
      ->check(soltex::cli::NumberIn(0.0, 600.0))
      ->capture_default_str();
  app.add_option("--listen-watchdog-s", config.listen_watchdog_seconds,
                 "every this many seconds call soltexd's own health service over a new connection; "
                 "three calls in a row without an answer (gRPC accepts no connection any more, "
                 "as after running out of file descriptors) exit 1 for a supervisor to restart "
                 "soltexd (0: off; at least 0.1)")
      ->check(soltex::cli::NumberIn(0.0, 3600.0))
      ->capture_default_str();
  app.add_option("--ready-file", config.ready_file,
                 "once listening, write 'grpc=PORT' (or 'grpc=unix:PATH'), 'metrics=PORT' (and "
                 "'http=PORT') lines here; removed when shutdown begins");
}

void add_http_options(CLI::App& app, ServerConfig& config) {
  auto* web = app.add_option_group("http", "bricks over HTTP/1.1 (docs/PROTOCOL.md, HTTP)");
  web->add_option("--http-listen", config.http_listen,
                  "HTTP brick address HOST:PORT (port 0: any free port); empty: off")
      ->check(host_port({.allow_empty = true}));
  web->add_option("--http-max-connections", config.http_max_connections,
                  "open HTTP connections; one more is answered 503 and closed")
      ->check(cli::IntegerIn(1u, 1u << 20))
      ->capture_default_str();
  web->add_option("--http-max-connections-per-client", config.http_max_connections_per_client,
                  "of those, open from one address (--trusted-proxies are not bounded); one "
                  "more is answered 503 and closed")
      ->check(cli::IntegerIn(1u, 1u << 20))
      ->capture_default_str();
  web->add_option("--http-timeout-s", config.http_timeout_seconds,
                  "seconds a request may take to arrive, a response to be written, or a "
                  "keep-alive connection to idle")
      ->check(soltex::cli::NumberIn(0.1, 3600.0))
      ->capture_default_str();
  web->add_option("--http-threads", config.http_threads,
                  "HTTP I/O threads (bricks are made on the brick workers)")
      ->check(cli::IntegerIn(1, 64))
      ->capture_default_str();
}

void add_shared_cache_options(CLI::App& app, ServerConfig& config) {
  auto* shared = app.add_option_group("shared cache", "second-level brick cache on memcached");
  shared
      ->add_option("--memcached", config.memcached,
                   "memcached nodes HOST:PORT[,HOST:PORT...] (consistent hashing); empty: off")
      ->delimiter(',')
      ->check(host_port({.allow_empty = true, .dialed = true}));
  shared
      ->add_option("--memcached-timeout-ms", config.memcached_timeout_ms,
                   "connect and I/O timeout; a slower node counts as a miss")
      ->check(cli::IntegerIn(1, 10000))
      ->capture_default_str();
  shared
      ->add_option("--memcached-ttl-s", config.memcached_ttl_seconds,
                   "expiry of shared bricks in seconds (0: until evicted)")
      ->check(cli::IntegerIn(0, 30 * 24 * 3600))
      ->capture_default_str();
}

// The texture registry's bounds and who a client is, in the `security` group.
void add_limit_options(CLI::Option_group& security, ServerConfig& config) {
  security
      .add_option("--registry-mb", config.registry_mb,
                  "memory bound of the texture registry in MiB; beyond it the least recently "
                  "used textures no open stream uses are evicted")
      ->check(cli::IntegerIn(1u, 1u << 16))
      ->capture_default_str();
  security
      .add_option("--max-textures-per-client", config.max_textures_per_client,
                  "textures one client may have registered at once; beyond it its own least "
                  "recently used unused one is evicted")
      ->check(cli::IntegerIn(1u, 1u << 20))
      ->capture_default_str();
  security
      .add_option("--trusted-proxies", config.trusted_proxies,
                  "balancers ADDRESS[/BITS],... whose x-forwarded-for header names the client "
                  "for the per-client limits (only they are believed)")
      ->delimiter(',');
}

void add_security_options(CLI::App& app, ServerConfig& config) {
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
  security->add_option("--token", config.token, "the bearer token itself (prefer --token-file)")
      ->check(CLI::Validator(
          [](std::string& token) -> std::string {
            // An unset variable in a deploy script must not turn authentication off silently.
            return token.empty() ? "is empty: give the token, or leave --token out to serve "
                                   "without one"
                                 : "";
          },
          "TOKEN"));
  security
      ->add_option("--max-streams-per-client", config.max_streams_per_client,
                   "open brick streams one client (token name, else address) may hold")
      ->check(cli::IntegerIn(1u, 1u << 20))
      ->capture_default_str();
  security
      ->add_option("--max-queued-per-client", config.max_queued_per_client,
                   "bricks one client may have queued over all its streams")
      ->check(cli::IntegerIn(1u, 1u << 30))
      ->capture_default_str();
  security->add_flag("--trust-forwarded-for", config.trust_forwarded_for)->group("");  // refused
  add_limit_options(*security, config);
}

void add_fault_options(CLI::App& app, ServerConfig& config) {
  auto* faults = app.add_option_group("faults", "for testing clients against a misbehaving server");
  faults
      ->add_option("--fault-delay-ms", config.faults.delay_ms,
                   "make every brick this many milliseconds slower to produce, on the worker "
                   "making it, as a slow server would (delays end with the shutdown grace)")
      ->check(cli::IntegerIn(0, 60000));
  faults
      ->add_option("--fault-corrupt-every", config.faults.corrupt_every,
                   "flip a payload byte in every Nth brick sent (0: never)")
      ->check(cli::IntegerIn(0u, 1u << 30));
}

}  // namespace

void add_soltexd_options(CLI::App& app, ServerConfig& config) {
  add_serving_options(app, config);
  add_http_options(app, config);
  add_shared_cache_options(app, config);
  add_security_options(app, config);
  add_fault_options(app, config);
}

std::string usage_problem(const ServerConfig& config) {
  if (config.max_keys_per_request > config.max_queued_per_stream) {
    return "--max-keys-per-request (" + std::to_string(config.max_keys_per_request) +
           ") must not exceed --max-queued-per-stream (" +
           std::to_string(config.max_queued_per_stream) + ")";
  }
  if (config.listen_watchdog_seconds > 0.0 && config.listen_watchdog_seconds < 0.1) {
    std::ostringstream given;
    given << config.listen_watchdog_seconds;
    return "--listen-watchdog-s " + given.str() + ": must be 0 (off) or at least 0.1";
  }
  if (config.tls_cert_file.empty() != config.tls_key_file.empty()) {
    return "TLS needs both --tls-cert and --tls-key";
  }
  if (config.tls_cert_file.empty() && !config.tls_client_ca_file.empty()) {
    return "--tls-client-ca needs --tls-cert and --tls-key";
  }
  if (!config.token.empty() && !config.token_file.empty()) {
    return "--token and --token-file both name tokens: give one";
  }
  if (config.trust_forwarded_for) {
    return "--trust-forwarded-for trusted x-forwarded-for from any peer and is gone: name the "
           "balancers whose header to trust with --trusted-proxies ADDRESS[/BITS],...";
  }
  try {
    (void)parse_address_ranges(config.trusted_proxies);
    // What the file says, where it can be read: a file that cannot be is a runtime failure
    // (exit 1), which the daemon reports when it reads it.
    if (!config.token_file.empty() && std::ifstream(config.token_file)) {
      (void)read_access_tokens(config.token_file);
    }
  } catch (const std::exception& e) {
    return e.what();
  }
  return {};
}

}  // namespace soltex::server
