#pragma once

#include <grpc/grpc_security.h>
#include <grpcpp/security/server_credentials.h>

#include <memory>
#include <mutex>
#include <string>

namespace soltex::server {

struct TlsFiles {
  std::string cert;       // certificate chain (PEM)
  std::string key;        // its private key (PEM)
  std::string client_ca;  // empty: no client certificates asked for
};

// Server TLS that reads its files again on reload() (SIGHUP): connections accepted after it
// use the new certificate, key and client CA; connections already open, and the streams on
// them, keep what they were made with. Uses gRPC's certificate-config fetcher, which asks
// for a new configuration at each handshake.
class ReloadableTls {
 public:
  // Reads the files now; throws std::runtime_error naming the file that is missing or wrong.
  explicit ReloadableTls(TlsFiles files);
  ReloadableTls(const ReloadableTls&) = delete;
  ReloadableTls& operator=(const ReloadableTls&) = delete;

  // Reads the files again; throws (and keeps what it had) when one cannot be read or holds
  // no PEM block of the kind expected.
  void reload();

  // Credentials for ServerBuilder::AddListeningPort; this object must outlive the server.
  std::shared_ptr<grpc::ServerCredentials> credentials();

  // gRPC's fetcher callback: the new configuration once after each reload, else unchanged.
  grpc_ssl_certificate_config_reload_status fetch(grpc_ssl_server_certificate_config** config);

 private:
  struct Pem {
    std::string cert, key, client_ca;
  };
  Pem read() const;

  const TlsFiles files_;
  std::mutex mutex_;
  Pem current_;
  bool changed_ = true;  // the first fetch, at start-up, takes the first configuration
};

}  // namespace soltex::server
