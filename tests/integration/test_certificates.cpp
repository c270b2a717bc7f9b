#include "test_certificates.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace soltex::testing {
namespace {

void run(const std::string& command) {
  if (std::system((command + " >/dev/null 2>&1").c_str()) != 0) {
    throw std::runtime_error("certificate set-up failed: " + command);
  }
}

}  // namespace

TestCertificates::TestCertificates() {
  std::string pattern = (std::filesystem::temp_directory_path() / "soltex-certs-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  directory_ = pattern;
  const std::string d = directory_;
  // P-256 keys: quick to make, and every TLS stack takes them.
  const std::string key = " -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes";
  const auto authority = [&](const std::string& name) {
    run("openssl req -x509" + key + " -keyout " + d + "/" + name + ".key -out " + d + "/" + name +
        ".pem -days 2 -subj '/CN=soltex test " + name + "'");
  };
  const auto leaf = [&](const std::string& name, const std::string& ca, const std::string& ext) {
    std::ofstream(d + "/" + name + ".ext") << ext << "\n";
    run("openssl req" + key + " -keyout " + d + "/" + name + ".key -out " + d + "/" + name +
        ".csr -subj '/CN=soltex test " + name + "'");
    run("openssl x509 -req -in " + d + "/" + name + ".csr -CA " + d + "/" + ca + ".pem -CAkey " +
        d + "/" + ca + ".key -CAcreateserial -out " + d + "/" + name + ".pem -days 2 -extfile " +
        d + "/" + name + ".ext");
  };
  authority("ca");
  authority("other-ca");
  leaf("server", "ca", "subjectAltName=DNS:localhost,IP:127.0.0.1");
  leaf("client", "ca", "extendedKeyUsage=clientAuth");
  leaf("other-client", "other-ca", "extendedKeyUsage=clientAuth");
}

TestCertificates::~TestCertificates() {
  std::error_code ignored;
  std::filesystem::remove_all(directory_, ignored);
}

std::string write_temporary_file(const std::string& name, const std::string& text) {
  std::string pattern =
      (std::filesystem::temp_directory_path() / ("soltex-" + name + "-XXXXXX")).string();
  const int fd = mkstemp(pattern.data());
  if (fd < 0) throw std::runtime_error("mkstemp failed");
  close(fd);
  std::ofstream(pattern) << text;
  return pattern;
}

}  // namespace soltex::testing
