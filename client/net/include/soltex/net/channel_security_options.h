#pragma once

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <stdexcept>
#include <string>

#include "soltex/net/channel_security.h"

namespace soltex::net {

// The command-line options every client shares for reaching a secured soltexd. Call
// finish_channel_security() after parsing to read the token file.
struct ChannelSecurityOptions {
  ChannelSecurity security;
  std::string token_file;
};

inline void add_channel_security_options(CLI::App& app, ChannelSecurityOptions& options) {
  auto* group = app.add_option_group("security", "TLS and the bearer token");
  group
      ->add_option("--tls-ca", options.security.tls_ca_file,
                   "CA (PEM) to check the server's certificate; set: TLS")
      ->check(CLI::ExistingFile);
  group->add_option("--tls-cert", options.security.tls_cert_file, "client certificate (PEM)")
      ->check(CLI::ExistingFile);
  group->add_option("--tls-key", options.security.tls_key_file, "client private key (PEM)")
      ->check(CLI::ExistingFile);
  group->add_option("--tls-server-name", options.security.tls_server_name,
                    "name the server's certificate must carry, if not the host's");
  group->add_option("--token-file", options.token_file, "file holding the bearer token")
      ->check(CLI::ExistingFile);
  group->add_option("--token", options.security.token, "the bearer token itself")
      ->envname("SOLTEX_TOKEN");
}

// Where --token's value came from. The command line or a config file names a token for this
// run; SOLTEX_TOKEN may be kept in the environment for other runs, so a --token-file given with
// it takes its place (the more specific source wins) where two typed tokens are refused.
enum class TokenOrigin { typed, environment };

// Throws std::runtime_error when the token file cannot be read, std::invalid_argument for a
// token that cannot travel in a header (check_token) or for two tokens typed for one run.
inline ChannelSecurity finish_channel_security(const ChannelSecurityOptions& options,
                                               TokenOrigin token_origin = TokenOrigin::typed) {
  ChannelSecurity security = options.security;
  // Options that cannot work together are the command line's fault (exit 2), not the
  // connection's, where channel_credentials() would find them.
  if (security.tls_cert_file.empty() != security.tls_key_file.empty()) {
    throw std::invalid_argument(
        "--tls-cert and --tls-key go together: a client certificate "
        "needs both its chain and its key");
  }
  if (!security.tls() && !security.tls_cert_file.empty()) {
    throw std::invalid_argument(
        "--tls-cert and --tls-key need --tls-ca: a client certificate "
        "needs TLS, which the server's CA turns on");
  }
  if (!options.token_file.empty() && !security.token.empty()) {
    if (token_origin == TokenOrigin::typed) {
      throw std::invalid_argument("--token and --token-file both name tokens: give one");
    }
    spdlog::info("the token of --token-file {} is sent, not SOLTEX_TOKEN's", options.token_file);
  }
  if (!options.token_file.empty()) {
    security.token = read_token_file(options.token_file);
    check_token(security.token, "--token-file " + options.token_file);
  } else {
    check_token(security.token, "--token");
  }
  return security;
}

}  // namespace soltex::net
