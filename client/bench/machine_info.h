#pragma once

#include <string>

// What a reader needs to weigh the timings: which machine, and how busy it was.
namespace soltex::bench {

// "AMD EPYC 9B14, 2 cores" from /proc/cpuinfo and the cores this process may use; "unknown
// CPU, N cores" where /proc/cpuinfo has no model name.
std::string machine_description();

// The 1-minute load average (/proc/loadavg); negative when it cannot be read.
double load_average();

}  // namespace soltex::bench
