#pragma once

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

namespace soltex::net {

// How a client reaches soltexd: plain or TLS (optionally with a client certificate), and the
// bearer token sent on every call. Files are read when the channel is made.
struct ChannelSecurity {
  std::string tls_ca_file;      // set: TLS, the server's certificate checked against this CA
  std::string tls_cert_file;    // client certificate chain, for servers that require one
  std::string tls_key_file;     // its private key
  std::string tls_server_name;  // the name the certificate must carry, if not the host's
  std::string token;            // sent as "authorization: Bearer <token>"; empty: none

  bool tls() const { return !tls_ca_file.empty(); }
};

// Reads a token file (one line; surrounding whitespace dropped). Throws std::runtime_error.
std::string read_token_file(const std::string& path);

// A bearer token must be visible ASCII (0x21 to 0x7E) to travel in an HTTP/2 header: gRPC
// aborts the process on anything else. Throws std::invalid_argument naming `source` (the
// option or file it came from) and the first character out of that range.
void check_token(const std::string& token, const std::string& source);

// Credentials for the channel; throws std::runtime_error naming a file it cannot read or a
// certificate given without its key.
std::shared_ptr<grpc::ChannelCredentials> channel_credentials(const ChannelSecurity& security);

// A channel to `target` with these credentials and arguments (the server-name override added).
std::shared_ptr<grpc::Channel> open_channel(const std::string& target,
                                            const ChannelSecurity& security,
                                            grpc::ChannelArguments args);

// Adds the bearer token, if any, to one call.
void authorize(const ChannelSecurity& security, grpc::ClientContext& context);

}  // namespace soltex::net
