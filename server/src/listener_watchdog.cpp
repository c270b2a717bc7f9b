#include "listener_watchdog.h"

#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/security/tls_certificate_provider.h>
#include <grpcpp/security/tls_certificate_verifier.h>
#include <grpcpp/security/tls_credentials_options.h>
#include <openssl/pem.h>
#include <openssl/x509v3.h>
#include <spdlog/spdlog.h>

#include "server_config.h"
#include "soltex/common/text_file.h"

namespace soltex::server {

ListenerWatchdog::ListenerWatchdog(Config config, std::function<void(const std::string&)> on_dead)
    : config_(std::move(config)), on_dead_(std::move(on_dead)) {
  thread_ = std::thread([this] { run(); });
}

ListenerWatchdog::~ListenerWatchdog() {
  stop();
}

void ListenerWatchdog::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    if (probing_ != nullptr) probing_->TryCancel();
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void ListenerWatchdog::run() {
  int misses = 0;
  while (true) {
    {
      std::unique_lock lock(mutex_);
      if (wake_.wait_for(lock, config_.interval, [this] { return stopping_; })) return;
    }
    const bool answered = this->answered();
    if (std::lock_guard lock(mutex_); stopping_) return;  // a cancelled probe is no miss
    misses = answered ? 0 : misses + 1;
    if (misses > 0) {
      spdlog::warn("gRPC listener check: no answer from {} within {} ms ({} of {} in a row)",
                   config_.target, config_.deadline.count(), misses, config_.misses);
    }
    if (misses >= config_.misses) {
      on_dead_("gRPC accepts no connection on " + config_.target + ": " + std::to_string(misses) +
               " health checks over new connections in a row had no answer within " +
               std::to_string(config_.deadline.count()) +
               " ms (gRPC gives up on its listening socket after a failed accept, as when the " +
               "process ran out of file descriptors)");
      return;
    }
  }
}

bool ListenerWatchdog::answered() {
  grpc::ChannelArguments args;
  // A subchannel of its own: a connection another channel holds would answer even though
  // the listener accepts no new one.
  args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);
  // Else the server logs a name its certificate lacks at every probe.
  if (!config_.tls_server_name.empty()) args.SetSslTargetNameOverride(config_.tls_server_name);
  grpc::GenericStub stub(grpc::CreateCustomChannel(config_.target, config_.credentials, args));
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + config_.deadline);
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return true;
    probing_ = &context;
  }
  grpc::CompletionQueue queue;
  grpc::Slice empty;  // HealthCheckRequest{service: ""}: the server as a whole
  const grpc::ByteBuffer request(&empty, 1);
  grpc::ByteBuffer response;
  grpc::Status status;
  auto call = stub.PrepareUnaryCall(&context, "/grpc.health.v1.Health/Check", request, &queue);
  call->StartCall();
  call->Finish(&response, &status, nullptr);
  void* tag = nullptr;
  bool ok = false;
  queue.Next(&tag, &ok);
  {
    std::lock_guard lock(mutex_);
    probing_ = nullptr;
  }
  queue.Shutdown();
  while (queue.Next(&tag, &ok)) {
  }
  return status.error_code() != grpc::StatusCode::DEADLINE_EXCEEDED;
}

std::string self_target(const std::string& listen, int bound_port) {
  if (is_unix_socket_address(listen)) return listen;
  std::string host = parse_host_port(listen).host;
  if (host.empty() || host == "0.0.0.0") host = "127.0.0.1";
  if (host == "::") host = "::1";
  return host_port_text(host, bound_port);
}

std::shared_ptr<grpc::ChannelCredentials> self_credentials(const std::string& cert_file,
                                                           const std::string& key_file) {
  if (cert_file.empty()) return grpc::InsecureChannelCredentials();
  grpc::experimental::TlsChannelCredentialsOptions options;
  const grpc::experimental::IdentityKeyCertPair identity{
      read_text_file(key_file, "TLS key"), read_text_file(cert_file, "TLS certificate")};
  options.set_certificate_provider(
      std::make_shared<grpc::experimental::StaticDataCertificateProvider>(std::vector{identity}));
  options.watch_identity_key_cert_pairs();
  options.set_verify_server_certs(false);
  options.set_certificate_verifier(std::make_shared<grpc::experimental::NoOpCertificateVerifier>());
  options.set_check_call_host(false);
  return grpc::experimental::TlsCredentials(options);
}

std::string certificate_name(const std::string& pem) {
  std::unique_ptr<BIO, decltype(&BIO_free)> bio(
      BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())), &BIO_free);
  std::unique_ptr<X509, decltype(&X509_free)> cert(
      bio ? PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr) : nullptr, &X509_free);
  if (!cert) return {};
  std::string name;
  auto* names = static_cast<GENERAL_NAMES*>(
      X509_get_ext_d2i(cert.get(), NID_subject_alt_name, nullptr, nullptr));
  for (int i = 0; names != nullptr && i < sk_GENERAL_NAME_num(names) && name.empty(); ++i) {
    const GENERAL_NAME* entry = sk_GENERAL_NAME_value(names, i);
    if (entry->type != GEN_DNS) continue;
    const ASN1_STRING* dns = entry->d.dNSName;
    name.assign(reinterpret_cast<const char*>(ASN1_STRING_get0_data(dns)),
                static_cast<std::size_t>(ASN1_STRING_length(dns)));
  }
  GENERAL_NAMES_free(names);
  if (!name.empty()) return name;
  char common_name[256] = {};
  const int length = X509_NAME_get_text_by_NID(X509_get_subject_name(cert.get()), NID_commonName,
                                               common_name, sizeof common_name);
  return length > 0 ? std::string(common_name, static_cast<std::size_t>(length)) : "";
}

}  // namespace soltex::server
