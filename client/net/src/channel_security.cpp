#include "soltex/net/channel_security.h"

#include <cctype>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace soltex::net {
namespace {

std::string read_file(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error(std::string("cannot read the ") + what + " file '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

std::string read_token_file(const std::string& path) {
  std::string token = read_file(path, "token");
  const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!token.empty() && space(token.back())) token.pop_back();
  std::size_t first = 0;
  while (first < token.size() && space(token[first])) ++first;
  token.erase(0, first);
  if (token.empty()) throw std::runtime_error("the token file '" + path + "' is empty");
  return token;
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
  options.pem_root_certs = read_file(security.tls_ca_file, "server CA");
  if (!security.tls_cert_file.empty()) {
    options.pem_cert_chain = read_file(security.tls_cert_file, "client certificate");
    options.pem_private_key = read_file(security.tls_key_file, "client key");
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
