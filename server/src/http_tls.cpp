#include "http_tls.h"

#include <stdexcept>

namespace soltex::server {

namespace ssl = boost::asio::ssl;

HttpTls::HttpTls(TlsFiles files) : files_(std::move(files)), context_(make()) {}

std::shared_ptr<ssl::context> HttpTls::make() const {
  auto context = std::make_shared<ssl::context>(ssl::context::tls_server);
  context->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 |
                       ssl::context::no_sslv3 | ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1);
  const auto use = [](const std::string& what, const std::string& file, auto&& load) {
    boost::system::error_code ec;
    load(ec);
    if (ec) throw std::runtime_error("HTTP TLS: " + what + " " + file + ": " + ec.message());
  };
  use("certificate chain", files_.cert,
      [&](auto& ec) { context->use_certificate_chain_file(files_.cert, ec); });
  use("private key", files_.key,
      [&](auto& ec) { context->use_private_key_file(files_.key, ssl::context::pem, ec); });
  if (!files_.client_ca.empty()) {
    use("client CA", files_.client_ca,
        [&](auto& ec) { context->load_verify_file(files_.client_ca, ec); });
    context->set_verify_mode(ssl::verify_peer | ssl::verify_fail_if_no_peer_cert);
  }
  return context;
}

void HttpTls::reload() {
  auto next = make();  // throws, keeping the old one, when a file cannot be used
  std::lock_guard lock(mutex_);
  context_ = std::move(next);
}

std::shared_ptr<ssl::context> HttpTls::context() const {
  std::lock_guard lock(mutex_);
  return context_;
}

}  // namespace soltex::server
