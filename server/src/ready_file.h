#pragma once

#include <string>

namespace soltex::server {

// --ready-file: what soltexd announces once it listens, for scripts and supervisors to read.
// Lines grpc=, metrics=, http= (with --http-listen), pid= and pid_start= (the process's start
// time in clock ticks since boot, from /proc: a pid alone may name another process after a
// reboot or once the pids wrap).

// Writes it whole (a temporary file renamed). Throws std::runtime_error naming the file and
// why it could not be written.
void write_ready_file(const std::string& path, const std::string& grpc, int metrics_port,
                      int http_port);

// Removes a ready file that announces no live soltexd: one of this process, or left by one
// that is gone (a crash), whose pid another process has taken since, or that wrote no pid. A
// live one's is that one's (a second instance given the same file by mistake must not take it
// away). Only a file: a path naming a folder is refused when written, not removed.
void remove_ready_file(const std::string& path);

// At start: remove_ready_file(), and a std::runtime_error naming the file and its owner when a
// live soltexd holds it (this instance would overwrite it once listening, and remove it when
// it stops, while the other goes on serving).
void claim_ready_file(const std::string& path);

}  // namespace soltex::server
