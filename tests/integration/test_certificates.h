#pragma once

#include <string>

namespace soltex::testing {

// A throw-away certificate authority with a server certificate for 127.0.0.1 / localhost and a
// client certificate, made with the openssl command in a temporary directory (removed by the
// destructor). Throws std::runtime_error when openssl is missing or fails.
class TestCertificates {
 public:
  TestCertificates();
  ~TestCertificates();
  TestCertificates(const TestCertificates&) = delete;
  TestCertificates& operator=(const TestCertificates&) = delete;

  std::string ca() const { return directory_ + "/ca.pem"; }
  std::string server_cert() const { return directory_ + "/server.pem"; }
  std::string server_key() const { return directory_ + "/server.key"; }
  std::string client_cert() const { return directory_ + "/client.pem"; }
  std::string client_key() const { return directory_ + "/client.key"; }
  // A second CA that signed nothing the server trusts.
  std::string other_client_cert() const { return directory_ + "/other-client.pem"; }
  std::string other_client_key() const { return directory_ + "/other-client.key"; }

 private:
  std::string directory_;
};

// Writes `text` to a new file in the system's temporary directory and returns its path.
std::string write_temporary_file(const std::string& name, const std::string& text);

}  // namespace soltex::testing
