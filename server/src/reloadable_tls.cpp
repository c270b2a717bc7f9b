#include "reloadable_tls.h"

#include <grpc/grpc.h>
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

#include <memory>
#include <stdexcept>

#include "soltex/common/text_file.h"

namespace soltex::server {
namespace {

std::string read_pem(const std::string& path, const std::string& what, const char* block) {
  std::string text = read_text_file(path, what);
  // A truncated or swapped file is refused here, with its name, rather than deep in a later
  // handshake that only gRPC's own log would explain.
  if (text.find("-----BEGIN ") == std::string::npos || text.find(block) == std::string::npos) {
    throw std::runtime_error("the " + what + " file '" + path + "' holds no PEM " + block +
                             " block");
  }
  return text;
}

// OpenSSL's last error, as text, for a message that names the file it was about.
std::string openssl_error() {
  const unsigned long code = ERR_get_error();
  ERR_clear_error();
  if (code == 0) return "no detail";
  char text[256];
  ERR_error_string_n(code, text, sizeof text);
  return text;
}

// The certificate and the key must be a pair: gRPC takes a mismatched pair without a word and
// then fails every handshake ("Invalid private key" in its own log), and at start-up the
// failure to add the port read as an address in use.
void check_key_matches_certificate(const std::string& cert, const std::string& key,
                                   const TlsFiles& files) {
  const auto bio_of = [](const std::string& text) {
    return std::unique_ptr<BIO, decltype(&BIO_free)>(
        BIO_new_mem_buf(text.data(), static_cast<int>(text.size())), &BIO_free);
  };
  const auto cert_bio = bio_of(cert);
  const std::unique_ptr<X509, decltype(&X509_free)> x509(
      PEM_read_bio_X509(cert_bio.get(), nullptr, nullptr, nullptr), &X509_free);
  if (!x509) {
    throw std::runtime_error("the TLS certificate file '" + files.cert +
                             "' does not parse: " + openssl_error());
  }
  const auto key_bio = bio_of(key);
  const std::unique_ptr<EVP_PKEY, decltype(&EVP_PKEY_free)> pkey(
      PEM_read_bio_PrivateKey(key_bio.get(), nullptr, nullptr, nullptr), &EVP_PKEY_free);
  if (!pkey) {
    throw std::runtime_error("the TLS key file '" + files.key +
                             "' does not parse: " + openssl_error());
  }
  if (X509_check_private_key(x509.get(), pkey.get()) != 1) {
    ERR_clear_error();
    throw std::runtime_error("the TLS key file '" + files.key +
                             "' is not the key of the certificate in '" + files.cert + "'");
  }
}

grpc_ssl_certificate_config_reload_status fetch_callback(
    void* user_data, grpc_ssl_server_certificate_config** config) {
  return static_cast<ReloadableTls*>(user_data)->fetch(config);
}

// ServerCredentials whose TLS configuration comes from the fetcher: the C++ API offers only
// fixed certificates (SslServerCredentials) or a file watcher that polls on its own schedule.
class FetcherCredentials final : public grpc::ServerCredentials {
 public:
  FetcherCredentials(ReloadableTls& tls, grpc_ssl_client_certificate_request_type request)
      : tls_(tls), request_(request) {}
  void SetAuthMetadataProcessor(const std::shared_ptr<grpc::AuthMetadataProcessor>&) override {
    throw std::logic_error("soltexd's TLS credentials take no auth metadata processor");
  }

 private:
  int AddPortToServer(const std::string& address, grpc_server* server) override {
    grpc_ssl_server_credentials_options* options =
        grpc_ssl_server_credentials_create_options_using_config_fetcher(request_, fetch_callback,
                                                                        &tls_);
    grpc_server_credentials* credentials = grpc_ssl_server_credentials_create_with_options(options);
    if (credentials == nullptr) return 0;
    const int port = grpc_server_add_http2_port(server, address.c_str(), credentials);
    grpc_server_credentials_release(credentials);
    return port;
  }

  ReloadableTls& tls_;
  const grpc_ssl_client_certificate_request_type request_;
};

}  // namespace

ReloadableTls::ReloadableTls(TlsFiles files) : files_(std::move(files)), current_(read()) {}

ReloadableTls::Pem ReloadableTls::read() const {
  Pem pem;
  pem.cert = read_pem(files_.cert, "TLS certificate", "CERTIFICATE");
  pem.key = read_pem(files_.key, "TLS key", "PRIVATE KEY");
  check_key_matches_certificate(pem.cert, pem.key, files_);
  if (!files_.client_ca.empty())
    pem.client_ca = read_pem(files_.client_ca, "client CA", "CERTIFICATE");
  return pem;
}

void ReloadableTls::reload() {
  Pem pem = read();
  std::lock_guard lock(mutex_);
  current_ = std::move(pem);
  changed_ = true;
}

std::shared_ptr<grpc::ServerCredentials> ReloadableTls::credentials() {
  return std::make_shared<FetcherCredentials>(
      *this, files_.client_ca.empty() ? GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE
                                      : GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
}

grpc_ssl_certificate_config_reload_status ReloadableTls::fetch(
    grpc_ssl_server_certificate_config** config) {
  std::lock_guard lock(mutex_);
  if (!changed_) return GRPC_SSL_CERTIFICATE_CONFIG_RELOAD_UNCHANGED;
  const grpc_ssl_pem_key_cert_pair pair{current_.key.c_str(), current_.cert.c_str()};
  // gRPC's fetcher path asserts that root certificates are given even when no client
  // certificate is asked for (then they are never used): the server's own chain stands in.
  const std::string& roots = current_.client_ca.empty() ? current_.cert : current_.client_ca;
  // gRPC copies the strings and takes ownership of the configuration.
  *config = grpc_ssl_server_certificate_config_create(roots.c_str(), &pair, 1);
  changed_ = false;
  return GRPC_SSL_CERTIFICATE_CONFIG_RELOAD_NEW;
}

}  // namespace soltex::server
