#include "soltex/net/channel_security.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace soltex::net {
namespace {

std::filesystem::path temporary(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("soltex-unit-" + name);
  std::ofstream(path) << text;
  return path;
}

TEST(ChannelSecurity, TokenFilesLoseSurroundingWhitespace) {
  const auto path = temporary("token", "  abc.def-123 \n\n");
  EXPECT_EQ(read_token_file(path.string()), "abc.def-123");
  std::filesystem::remove(path);
}

TEST(ChannelSecurity, EmptyOrMissingTokenFilesAreErrorsThatNameThePath) {
  const auto path = temporary("empty-token", "\n");
  try {
    read_token_file(path.string());
    ADD_FAILURE() << "an empty token file was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos);
  }
  std::filesystem::remove(path);
  EXPECT_THROW(read_token_file("/nonexistent/soltex-token"), std::runtime_error);
}

TEST(ChannelSecurity, HalfGivenCertificatesAreRefused) {
  ChannelSecurity plain_with_certificate;
  plain_with_certificate.tls_cert_file = "client.pem";
  EXPECT_THROW(channel_credentials(plain_with_certificate), std::runtime_error);

  const auto ca = temporary("ca.pem", "not really a certificate");
  ChannelSecurity key_missing;
  key_missing.tls_ca_file = ca.string();
  key_missing.tls_cert_file = ca.string();
  EXPECT_THROW(channel_credentials(key_missing), std::runtime_error);

  ChannelSecurity ca_missing;
  ca_missing.tls_ca_file = "/nonexistent/ca.pem";
  EXPECT_THROW(channel_credentials(ca_missing), std::runtime_error);
  std::filesystem::remove(ca);
}

TEST(ChannelSecurity, ACaFileWithNoPemBlockIsNamedAtOnce) {
  const auto ca = temporary("not-pem", "soltex-host\n");
  ChannelSecurity security;
  security.tls_ca_file = ca.string();
  try {
    (void)channel_credentials(security);
    ADD_FAILURE() << "a CA file with no PEM block was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("server CA '" + ca.string() + "' holds no PEM block"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(ca);
}

// gRPC aborts the process on a header value outside visible ASCII: such a token is refused
// first, naming where it came from and the character.
TEST(ChannelSecurity, ATokenThatCannotTravelInAHeaderIsRefused) {
  EXPECT_NO_THROW(check_token("abc.DEF-123_~+/=", "--token"));
  EXPECT_NO_THROW(check_token("", "--token"));
  for (const std::string bad : {"ab\ncd", "ab\tcd", "ab cd", "ab\x7f", "\xc3\xa9t\xc3\xa9"}) {
    try {
      check_token(bad, "--token-file t");
      ADD_FAILURE() << "accepted a token with a byte outside visible ASCII";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("--token-file t: the token's character "),
                std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace soltex::net
