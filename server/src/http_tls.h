#pragma once

#include <boost/asio/ssl/context.hpp>
#include <memory>
#include <mutex>

#include "reloadable_tls.h"

namespace soltex::server {

// The HTTP endpoint's TLS: the same certificate, key and client CA files as gRPC's, read into
// an OpenSSL context. reload() reads them again into a new context for later connections;
// open ones keep theirs.
class HttpTls {
 public:
  // Throws std::runtime_error naming the file that cannot be used.
  explicit HttpTls(TlsFiles files);
  void reload();
  std::shared_ptr<boost::asio::ssl::context> context() const;

 private:
  std::shared_ptr<boost::asio::ssl::context> make() const;

  const TlsFiles files_;
  mutable std::mutex mutex_;
  std::shared_ptr<boost::asio::ssl::context> context_;
};

}  // namespace soltex::server
