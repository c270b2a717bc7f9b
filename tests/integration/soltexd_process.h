#pragma once

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

namespace soltex::testing {

// A real soltexd started on loopback with port 0 (free ports chosen by the kernel), for tests.
// The destructor stops it with SIGKILL if a test did not stop it itself.
class SoltexdProcess {
 public:
  // Starts `binary` with --listen 127.0.0.1:PORT (default 0: a free port chosen by the
  // kernel) --metrics-listen 127.0.0.1:0 plus `extra_args`, and waits (up to 20 s) until it
  // has written its ready file. `max_descriptors` > 0: its RLIMIT_NOFILE, soft and hard.
  explicit SoltexdProcess(std::vector<std::string> extra_args = {}, int port = 0,
                          int max_descriptors = 0);
  ~SoltexdProcess();

  SoltexdProcess(const SoltexdProcess&) = delete;
  SoltexdProcess& operator=(const SoltexdProcess&) = delete;

  std::string grpc_address() const { return "127.0.0.1:" + std::to_string(grpc_port_); }
  int grpc_port() const { return grpc_port_; }
  int metrics_port() const { return metrics_port_; }
  int http_port() const { return http_port_; }  // 0 without --http-listen
  pid_t pid() const { return pid_; }            // for reading /proc/PID; -1 once it has exited

  // Sends SIGTERM and returns the exit status (or -signal if killed), waiting up to 30 s.
  int terminate();
  // Waits up to `timeout` (a server told to stop: send_signal) for it to exit: its exit status
  // (or -signal), or -1000 while it still runs.
  int wait_for_exit(std::chrono::milliseconds timeout = std::chrono::seconds(30));
  // SIGKILL: the server dies mid-stream, as in a crash.
  void kill_now();
  // Sends `signal` (SIGHUP: reload) and returns at once.
  void send_signal(int signal);

  // The daemon's log (stdout and stderr) so far.
  std::string log() const;

 private:
  pid_t pid_ = -1;
  int grpc_port_ = 0;
  int metrics_port_ = 0;
  int http_port_ = 0;
  std::string directory_;
};

// Starts args[0] (a path) with the rest of `args` as a child process, its stdout and stderr
// going to `log_path` when one is given, with at most `max_descriptors` open files when that
// is > 0; returns its pid. Throws when fork() fails.
pid_t spawn_process(std::vector<std::string> args, const std::string& log_path = "",
                    int max_descriptors = 0);

// SIGKILLs the child `pid` and reaps it, then sets `pid` to -1; nothing when pid <= 0.
void kill_and_reap(pid_t& pid);

// A loopback port that was free a moment ago (for restarting a server on the same port).
int free_port();

// GET http://127.0.0.1:port/path; returns the body ("" on failure, with `status` set to 0).
std::string http_get(int port, const std::string& path, int* status = nullptr);

// The value of an unlabelled (or exactly labelled) sample in Prometheus text, or -1.
double metric_value(const std::string& exposition, const std::string& name);

}  // namespace soltex::testing
