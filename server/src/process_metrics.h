#pragma once

#include <optional>

namespace soltex::server {

// What every Prometheus exporter reports about its process (the process_* families), read
// from /proc at scrape time.
struct ProcessStats {
  double cpu_seconds = 0;         // user + system
  double resident_bytes = 0;      // RSS
  double virtual_bytes = 0;       // VSZ
  double open_fds = 0;            // entries of /proc/self/fd
  double max_fds = 0;             // RLIMIT_NOFILE soft limit
  double start_time_seconds = 0;  // since the Unix epoch
};

// Empty when /proc/self/stat cannot be read (not Linux, or /proc not mounted).
std::optional<ProcessStats> read_process_stats();

}  // namespace soltex::server
