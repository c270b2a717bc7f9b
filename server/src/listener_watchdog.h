#pragma once

#include <grpcpp/grpcpp.h>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace soltex::server {

// gRPC (Debian's 1.51) stops a listening socket for good after one failed accept4, as when the
// process has run out of file descriptors: soltexd lives on, serving the connections it has,
// but accepts no new one, and nothing in gRPC's API arms the listener again. The watchdog
// finds out from outside: every interval it calls the health service over a new connection
// to the listening address. A call with no answer within the deadline is a miss (a dead
// listener leaves the connection in the backlog, unanswered); `misses` in a row call
// `on_dead`, once. A call that fails otherwise (no descriptor for the probe's own socket, a
// TLS handshake the server refused) shows that the listener accepted, and resets the count.
class ListenerWatchdog {
 public:
  struct Config {
    std::string target;  // what a client dials: HOST:PORT, unix:PATH or unix-abstract:NAME
    std::shared_ptr<grpc::ChannelCredentials> credentials;
    std::string tls_server_name;  // TLS: a name the certificate has, so no handshake is refused
    std::chrono::milliseconds interval{5000};
    std::chrono::milliseconds deadline{5000};  // under gRPC's 20 s connect timeout
    int misses = 3;
  };
  // `on_dead(why)` runs on the watchdog's thread.
  ListenerWatchdog(Config config, std::function<void(const std::string&)> on_dead);
  ~ListenerWatchdog();
  ListenerWatchdog(const ListenerWatchdog&) = delete;
  ListenerWatchdog& operator=(const ListenerWatchdog&) = delete;

  // Cancels a probe under way and joins the thread. Idempotent.
  void stop();

 private:
  void run();
  bool answered();  // one probe: false only when it had no answer within the deadline

  const Config config_;
  const std::function<void(const std::string&)> on_dead_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  grpc::ClientContext* probing_ = nullptr;  // the call under way, for stop() to cancel
  std::thread thread_;
};

// The address soltexd's own gRPC listener is reached at: a wildcard host becomes loopback,
// port 0 the port bound. `listen` as --listen gives it.
std::string self_target(const std::string& listen, int bound_port);

// Credentials the watchdog dials with: plaintext (`cert_file` empty), or TLS that does not
// check the server's certificate (the probe asks whether the listener accepts, not who
// answers) and shows the server's own certificate, for a server that asks for one.
std::shared_ptr<grpc::ChannelCredentials> self_credentials(const std::string& cert_file,
                                                           const std::string& key_file);

// A DNS name the PEM certificate is for (its first subjectAltName, else its common name), or
// "" when it names none.
std::string certificate_name(const std::string& pem);

}  // namespace soltex::server
