#pragma once

#include <sys/types.h>

#include <string>

namespace soltex::testing {

// A real memcached on a free loopback port, for tests of the shared brick cache. Killed
// (SIGKILL) by the destructor or by kill().
class MemcachedProcess {
 public:
  // Throws std::runtime_error when memcached is not installed or does not start in 10 s.
  MemcachedProcess();
  ~MemcachedProcess();
  MemcachedProcess(const MemcachedProcess&) = delete;
  MemcachedProcess& operator=(const MemcachedProcess&) = delete;

  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  int port() const { return port_; }
  void kill();
  // Stops it (SIGSTOP): it keeps its connections and its port but answers nothing, as a hung
  // node does, until resume() (SIGCONT).
  void pause();
  void resume();

  // Where memcached is, or "" when it is not installed.
  static std::string binary();

 private:
  pid_t pid_ = -1;
  int port_ = 0;
};

}  // namespace soltex::testing
