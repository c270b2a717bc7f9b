#include "soltex/net/channel_security.h"

#include <cstdio>
#include <stdexcept>

#include "soltex/common/text_file.h"

namespace soltex::net {

namespace {

// gRPC takes any text and, given no PEM block, fails each connection later with a message
// about addresses: a file that holds none is named now.
std::string read_pem_file(const std::string& path, const std::string& what) {
  std::string text = read_text_file(path, what);
  if (text.find("-----BEGIN ") == std::string::npos) {
    throw std::runtime_error(what + " '" + path + "' holds no PEM block (-----BEGIN ...)");
  }
  return text;
}

}  // namespace

std::string read_token_file(const std::string& path) {
  return read_trimmed_text_file(path, "token");
}

void check_token(const std::string& token, const std::string& source) {
  for (std::size_t i = 0; i < token.size(); ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x21 && c <= 0x7E) continue;
    char code[8];
    std::snprintf(code, sizeof code, "0x%02X", c);
    throw std::invalid_argument(source + ": the token's character " + std::to_string(i + 1) +
                                " is " + code +
                                "; a bearer token is visible ASCII (0x21 to 0x7E), one line");
  }
}

std::shared_ptr<grpc::ChannelCredentials> channel_credentials(const ChannelSecurity& security) {
  if (!security.tls()) {
    if (!security.tls_cert_file.empty() || !security.tls_key_file.empty()) {
      throw std::runtime_error("a client certificate needs TLS: give the server's CA too");
    }
    return grpc::InsecureChannelCredentials();
  }
  if (security.tls_cert_file.empty() != security.tls_key_file.empty()) {
    throw std::runtime_error("a client certificate needs both its chain and its key");
  }
  grpc::SslCredentialsOptions options;
  options.pem_root_certs = read_pem_file(security.tls_ca_file, "server CA");
  if (!security.tls_cert_file.empty()) {
    options.pem_cert_chain = read_pem_file(security.tls_cert_file, "client certificate");
    options.pem_private_key = read_pem_file(security.tls_key_file, "client key");
  }
  return grpc::SslCredentials(options);
}

std::shared_ptr<grpc::Channel> open_channel(const std::string& target,
                                            const ChannelSecurity& security,
                                            grpc::ChannelArguments args) {
  if (security.tls() && !security.tls_server_name.empty()) {
    args.SetSslTargetNameOverride(security.tls_server_name);
  }
  return grpc::CreateCustomChannel(target, channel_credentials(security), args);
}

void authorize(const ChannelSecurity& security, grpc::ClientContext& context) {
  if (!security.token.empty()) context.AddMetadata("authorization", "Bearer " + security.token);
}

}  // namespace soltex::net
