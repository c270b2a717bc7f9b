#include "ready_file.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace soltex::server {
namespace {

// When process `pid` started, in clock ticks since boot (field 22 of /proc/PID/stat), or
// nothing where /proc does not say.
std::optional<uint64_t> process_start_ticks(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  if (!std::getline(in, stat)) return std::nullopt;
  // The command name (field 2) is in parentheses and may hold spaces and parentheses itself:
  // the fields after it start after the last ')'.
  const std::size_t name_end = stat.rfind(')');
  if (name_end == std::string::npos) return std::nullopt;
  std::istringstream fields(stat.substr(name_end + 1));
  std::string field;
  for (int i = 3; i <= 22; ++i) {
    if (!(fields >> field)) return std::nullopt;
  }
  char* end = nullptr;
  const unsigned long long ticks = std::strtoull(field.c_str(), &end, 10);
  if (end == field.c_str() || *end != '\0') return std::nullopt;
  return ticks;
}

// The process a ready file names, and its start time when the file gives one.
struct ReadyFileOwner {
  pid_t pid = 0;
  std::optional<uint64_t> start_ticks;
};

ReadyFileOwner ready_file_owner(const std::string& path) {
  std::ifstream in(path);
  ReadyFileOwner owner;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("pid=", 0) == 0) owner.pid = static_cast<pid_t>(std::atol(line.c_str() + 4));
    if (line.rfind("pid_start=", 0) == 0)
      owner.start_ticks = std::strtoull(line.c_str() + 10, nullptr, 10);
  }
  return owner;
}

bool lives(const ReadyFileOwner& owner) {
  if (owner.pid <= 0 || owner.pid == getpid()) return false;
  if (kill(owner.pid, 0) != 0 && errno != EPERM) return false;
  // Alive, but perhaps another process under a reused pid: the start times tell.
  if (!owner.start_ticks) return true;
  const std::optional<uint64_t> started = process_start_ticks(owner.pid);
  return !started || *started == *owner.start_ticks;
}

}  // namespace

void write_ready_file(const std::string& path, const std::string& grpc, int metrics_port,
                      int http_port) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary);
    out << "grpc=" << grpc << "\nmetrics=" << metrics_port << "\n";
    if (http_port != 0) out << "http=" << http_port << "\n";
    out << "pid=" << getpid() << "\n";
    if (const std::optional<uint64_t> started = process_start_ticks(getpid())) {
      out << "pid_start=" << *started << "\n";
    }
    out.close();
    if (!out) throw std::runtime_error("--ready-file: cannot write " + temporary);
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::filesystem::remove(temporary, error);
    throw std::runtime_error("--ready-file: cannot rename " + temporary + " to " + path + ": " +
                             error.message());
  }
}

void remove_ready_file(const std::string& path) {
  std::error_code ignored;
  if (path.empty() || !std::filesystem::is_regular_file(path, ignored)) return;
  if (!lives(ready_file_owner(path))) std::filesystem::remove(path, ignored);
}

void claim_ready_file(const std::string& path) {
  std::error_code ignored;
  if (path.empty() || !std::filesystem::is_regular_file(path, ignored)) return;
  if (const ReadyFileOwner owner = ready_file_owner(path); lives(owner)) {
    throw std::runtime_error("--ready-file " + path + " belongs to the running process " +
                             std::to_string(owner.pid) +
                             ": give each soltexd a ready file of its own");
  }
  remove_ready_file(path);
}

}  // namespace soltex::server
