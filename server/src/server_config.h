#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fault_injection.h"

namespace soltex::server {

// Everything an operator can set (command line, config file or environment).
struct ServerConfig {
  std::string listen = "127.0.0.1:7447";          // gRPC, HOST:PORT; port 0 picks a free one
  std::string metrics_listen = "127.0.0.1:9447";  // Prometheus GET /metrics, HOST:PORT
  std::size_t cache_mb = 256;                     // encoded-brick cache budget
  int threads = 0;                                // brick workers; 0 = one per core
  std::string log_level = "info";
  // After the 3D predictor a brick is mostly literals: a fast negative level (literals still
  // entropy coded) encodes 1.9x faster than level 1 for 4 % more bytes over the codec
  // benchmark's patterns, and fewer on noisy ones (docs/PERFORMANCE.md, "Brick codec").
  int zstd_level = -200;
  // The texture registry: least recently used textures no stream uses are evicted beyond these.
  uint32_t max_textures = 16384;
  uint32_t registry_mb = 8;
  uint32_t max_textures_per_client = 1024;
  uint32_t max_keys_per_request = 1024;
  uint32_t max_queued_per_stream = 4096;
  uint32_t max_message_bytes = 4u << 20;
  // Bricks a message waits for while more are being made, and for at most how long (µs):
  // fewer, larger messages cost both ends fewer wake-ups (docs/PERFORMANCE.md, "soltexd under
  // load").
  uint32_t coalesce_bricks = 32;
  uint32_t coalesce_wait_us = 2000;
  // Threads' worth of time gRPC's threads may spend handling stream requests themselves; past
  // it a request waits for a brick worker's turn, shared fairly between clients.
  double direct_request_share = 1.0;
  double shutdown_grace_seconds = 5.0;
  // Every this many seconds soltexd calls its own health service over a new connection, and
  // exits 1 after three calls in a row get no answer: gRPC accepts no connection any more
  // (ListenerWatchdog). 0: off.
  double listen_watchdog_seconds = 5.0;
  std::string ready_file;  // written once listening: "grpc=PORT\nmetrics=PORT\n[http=PORT\n]"

  // HTTP bricks (docs/PROTOCOL.md, HTTP): off while empty.
  std::string http_listen;
  uint32_t http_max_connections = 1024;
  uint32_t http_max_connections_per_client =
      64;  // of those, from one address (not a trusted proxy)
  double http_timeout_seconds = 15.0;
  int http_threads = 2;

  // Shared second-level cache (memcached); off while the list is empty.
  std::vector<std::string> memcached;  // HOST:PORT each
  int memcached_timeout_ms = 50;
  int memcached_ttl_seconds = 0;

  // Security: TLS when cert and key are set; client certificates required when client_ca is.
  std::string tls_cert_file;
  std::string tls_key_file;
  std::string tls_client_ca_file;
  std::string token_file;  // tokens file (access_tokens.h); a token is required when set
  std::string token;       // or the token itself (SOLTEXD_TOKEN)
  uint32_t max_streams_per_client = 64;
  uint32_t max_queued_per_client = 65536;
  bool trust_forwarded_for = false;          // replaced by trusted_proxies: refused at start
  std::vector<std::string> trusted_proxies;  // peers whose x-forwarded-for names the client

  FaultConfig faults;
};

// "HOST:PORT" or "[V6]:PORT" -> host and port; throws std::invalid_argument naming the text.
struct HostPort {
  std::string host;
  uint16_t port;
};
HostPort parse_host_port(const std::string& text);
// HOST:PORT again, an IPv6 host in brackets.
std::string host_port_text(const std::string& host, int port);

// Whether `address` names a unix-domain socket as gRPC writes one (unix:PATH,
// unix-abstract:NAME): soltexd's gRPC listener accepts these besides HOST:PORT.
bool is_unix_socket_address(const std::string& address);

}  // namespace soltex::server
