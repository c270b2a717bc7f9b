// soltexd's memory as the kernel sees it (/proc/PID), over loopback: the bricks of a cold start
// fill transparent huge pages, not a page fault for every 4 KiB (common/allocator).
#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>
#include <string>

#include "brick_test_client.h"
#include "soltex/common/text_file.h"
#include "soltexd_process.h"

namespace soltex {
namespace {

using namespace testing;

std::string proc_file(pid_t pid, const std::string& name) {
  return read_text_file("/proc/" + std::to_string(pid) + "/" + name, "process");
}

// The kernel's transparent huge page mode, "[always]", "[madvise]" or "[never]" among the
// others; "" where the kernel has none.
std::string huge_page_mode() {
  try {
    return read_text_file("/sys/kernel/mm/transparent_hugepage/enabled", "kernel setting");
  } catch (const std::runtime_error&) {
    return "";
  }
}

// The process's minor page faults so far: field 10 of /proc/PID/stat, counted after the
// command name's closing parenthesis (the name may hold spaces).
long long minor_faults(pid_t pid) {
  const std::string stat = proc_file(pid, "stat");
  std::istringstream fields(stat.substr(stat.rfind(')') + 2));
  std::string field;
  for (int i = 3; i <= 10; ++i) fields >> field;
  return std::stoll(field);
}

// A "Name:   N kB" line of /proc/PID/smaps_rollup, in bytes; -1 when it is missing.
long long smaps_bytes(pid_t pid, const std::string& name) {
  std::istringstream lines(proc_file(pid, "smaps_rollup"));
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind(name + ":", 0) == 0) return std::stoll(line.substr(name.size() + 1)) * 1024;
  }
  return -1;
}

TEST(SoltexdMemory, ColdBricksFillHugePagesNotAPageFaultPer4KiB) {
  const std::string thp = huge_page_mode();
  if (thp.empty() || thp.find("[never]") != std::string::npos) {
    GTEST_SKIP() << "transparent huge pages are off on this machine: " << thp;
  }
  SoltexdProcess server;
  if (proc_file(server.pid(), "maps").find("libjemalloc") == std::string::npos) {
    GTEST_SKIP() << "soltexd is built without jemalloc (SOLTEX_JEMALLOC=OFF, or a sanitizer "
                    "build): glibc's malloc gives its thread arenas no huge pages";
  }
  auto stub = connect(server);
  // 2^8 in bricks of 16: 16^3 bricks at the finest level, each 17^3 RGB samples raw.
  const v1::TextureHandle handle = register_texture(*stub, marble_request(8, 16));
  const std::vector<v1::BrickKey> keys = level_keys(handle.id(), 0, 16);
  constexpr size_t kBricks = 2048;  // about 30 MB of cold bricks
  constexpr size_t kPerRequest = 1024;
  const long long faults_before = minor_faults(server.pid());
  for (size_t first = 0; first < kBricks; first += kPerRequest) {
    const std::vector<v1::BrickKey> part(keys.begin() + first, keys.begin() + first + kPerRequest);
    const StreamResult result = stream_once(*stub, want(part, v1::CODEC_RAW));
    ASSERT_TRUE(result.status.ok()) << result.status.error_message();
    ASSERT_EQ(result.bricks.size(), part.size());
  }
  const long long faults = minor_faults(server.pid()) - faults_before;
  const double cached = metric_value(metrics(server), "soltex_cache_bytes");
  ASSERT_GT(cached, 25e6);
  // In 4 KiB pages the cache alone takes cached / 4096 faults (7,500 here; 10,000 measured in
  // all with MALLOC_CONF=thp:never); in 2 MiB pages a few dozen, and the rest (2,100-2,500
  // measured) is memory the kernel still gives 4 KiB at a time.
  EXPECT_LT(faults, cached / 4096 / 2)
      << faults << " minor faults for " << cached << " bytes of cached bricks";
  EXPECT_GT(smaps_bytes(server.pid(), "AnonHugePages"), cached / 2);
}

}  // namespace
}  // namespace soltex
