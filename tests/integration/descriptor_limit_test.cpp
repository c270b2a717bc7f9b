// soltexd out of file descriptors, against a real soltexd whose limit is low: idle clients
// that hold every descriptor must not leave a listener dead once they are gone. The metrics
// listener accepts again; gRPC's cannot, so the watchdog makes soltexd exit for a supervisor
// to restart it.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "brick_test_client.h"
#include "test_certificates.h"

namespace soltex {
namespace {

using namespace testing;
using namespace std::chrono_literals;

// Under the metrics listener's 64 connections plus what soltexd opens to start.
constexpr int kDescriptorLimit = 64;

// Connections to 127.0.0.1:port that send nothing; closed with the object.
class IdleConnections {
 public:
  IdleConnections(int port, int count) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    for (int i = 0; i < count; ++i) {
      const int fd = socket(AF_INET, SOCK_STREAM, 0);
      if (fd < 0) break;
      if (connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
        close(fd);
        break;
      }
      fds_.push_back(fd);
    }
  }
  ~IdleConnections() { close_all(); }

  std::size_t size() const { return fds_.size(); }
  void close_all() {
    for (const int fd : fds_) close(fd);
    fds_.clear();
  }
  // How many of them the server has closed, waiting up to `timeout` for `expected` of them.
  std::size_t closed_by_server(std::size_t expected, std::chrono::milliseconds timeout) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    std::size_t closed = 0;
    do {
      closed = 0;
      for (const int fd : fds_) {
        pollfd entry{fd, POLLIN, 0};
        char byte = 0;
        if (poll(&entry, 1, 0) == 1 && recv(fd, &byte, 1, MSG_PEEK) <= 0) ++closed;
      }
      if (closed >= expected) break;
      std::this_thread::sleep_for(50ms);
    } while (std::chrono::steady_clock::now() < deadline);
    return closed;
  }

 private:
  std::vector<int> fds_;
};

// Polls the daemon's log for `text`, up to `timeout`.
bool log_shows(const SoltexdProcess& server, const std::string& text,
               std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (server.log().find(text) == std::string::npos) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(50ms);
  }
  return true;
}

std::size_t occurrences(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

TEST(DescriptorLimit, MetricsAnswerAgainOnceIdleConnectionsThatTookEveryDescriptorClose) {
  SoltexdProcess server({}, 0, kDescriptorLimit);
  IdleConnections idle(server.metrics_port(), 2 * kDescriptorLimit);
  ASSERT_EQ(idle.size(), 2u * kDescriptorLimit);
  ASSERT_TRUE(log_shows(server, "accepting metrics connections failed", 10s)) << server.log();
  idle.close_all();

  int status = 0;
  for (int i = 0; i < 100 && status != 200; ++i) {
    (void)http_get(server.metrics_port(), "/metrics", &status);
    if (status != 200) std::this_thread::sleep_for(100ms);
  }
  EXPECT_EQ(status, 200) << server.log();
  EXPECT_TRUE(log_shows(server, "accepting metrics connections works again", 5s));
  // One line for the whole burst, not one per retry.
  EXPECT_EQ(occurrences(server.log(), "accepting metrics connections failed"), 1u);
  EXPECT_EQ(health_status(server), 1);
  EXPECT_EQ(server.terminate(), 0);
}

TEST(DescriptorLimit, MetricsHoldAtMostTheirCapOfConnections) {
  SoltexdProcess server;
  IdleConnections idle(server.metrics_port(), 100);
  ASSERT_EQ(idle.size(), 100u);
  // 64 are held (until their deadline); the others are closed at once.
  EXPECT_GE(idle.closed_by_server(36, 10s), 36u);
  idle.close_all();
  int status = 0;
  for (int i = 0; i < 100 && status != 200; ++i) {
    (void)http_get(server.metrics_port(), "/metrics", &status);
    if (status != 200) std::this_thread::sleep_for(100ms);
  }
  EXPECT_EQ(status, 200);
}

TEST(DescriptorLimit, AGrpcListenerOutOfDescriptorsKeepsAnsweringOrExitsOne) {
  SoltexdProcess server({"--listen-watchdog-s", "0.5"}, 0, kDescriptorLimit);
  {
    IdleConnections idle(server.grpc_port(), 2 * kDescriptorLimit);
    ASSERT_EQ(idle.size(), 2u * kDescriptorLimit);
    // gRPC has taken what it can when it says so; soltexd's watchdog must not act before.
    if (log_shows(server, "Too many open files", 5s)) {
      // Said in soltexd's log format, not gRPC's own.
      EXPECT_NE(server.log().find("error soltexd: gRPC: Failed accept4: Too many open files ("),
                std::string::npos)
          << server.log();
    }
  }
  // Either gRPC accepts again, or the watchdog ends soltexd after three probes unanswered (each
  // waits 2 s for its answer). The bound only keeps a hang from lasting.
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (std::chrono::steady_clock::now() < deadline) {
    const int exit_status = server.wait_for_exit(500ms);
    if (exit_status != -1000) {
      EXPECT_EQ(exit_status, 1) << server.log();
      EXPECT_NE(server.log().find("gRPC accepts no connection"), std::string::npos) << server.log();
      return;
    }
    if (health_status(server) == 1) return;  // the listener works
  }
  ADD_FAILURE() << "soltexd neither answered nor exited:\n" << server.log();
}

TEST(DescriptorLimit, TheWatchdogLeavesAHealthyServerWithMutualTlsAlone) {
  const TestCertificates certs;
  SoltexdProcess server({"--listen-watchdog-s", "0.1", "--tls-cert", certs.server_cert(),
                         "--tls-key", certs.server_key(), "--tls-client-ca", certs.ca()});
  // Ten periods and more: each probe is answered, or its handshake refused, never ignored.
  EXPECT_EQ(server.wait_for_exit(1500ms), -1000) << server.log();
  EXPECT_EQ(server.log().find("gRPC listener check"), std::string::npos) << server.log();
  EXPECT_EQ(server.terminate(), 0);
}

}  // namespace
}  // namespace soltex
