#include "memcached_process.h"

#include <sys/wait.h>

#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <stdexcept>
#include <thread>
#include <vector>

#include "soltexd_process.h"

namespace soltex::testing {
namespace {

bool accepts_connections(int port) {
  try {
    boost::asio::io_context io;
    boost::asio::ip::tcp::socket socket(io);
    socket.connect({boost::asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)});
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

std::string MemcachedProcess::binary() {
  for (const char* candidate : {"/usr/bin/memcached", "/usr/local/bin/memcached"}) {
    if (std::filesystem::exists(candidate)) return candidate;
  }
  return "";
}

MemcachedProcess::MemcachedProcess() : port_(free_port()) {
  const std::string path = binary();
  if (path.empty()) throw std::runtime_error("memcached is not installed");
  pid_ = spawn_process({path, "-l", "127.0.0.1", "-p", std::to_string(port_), "-U", "0", "-m", "64",
                        "-t", "1", "-u", "nobody"});
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < deadline) {
    if (accepts_connections(port_)) return;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      throw std::runtime_error("memcached exited during start-up");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  throw std::runtime_error("memcached did not accept connections within 10 s");
}

MemcachedProcess::~MemcachedProcess() {
  kill();
}

void MemcachedProcess::kill() {
  kill_and_reap(pid_);
}

void MemcachedProcess::pause() {
  if (pid_ > 0) ::kill(pid_, SIGSTOP);
}

void MemcachedProcess::resume() {
  if (pid_ > 0) ::kill(pid_, SIGCONT);
}

}  // namespace soltex::testing
