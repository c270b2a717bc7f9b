#pragma once

// Running a runtime-dispatched kernel's test on each Highway target in turn.

#include <hwy/targets.h>

#include <cstdint>
#include <vector>

namespace soltex::test {

// Makes HWY_DYNAMIC_DISPATCH choose `target` until destroyed, however a test ends.
struct ForcedTarget {
  explicit ForcedTarget(int64_t target) { hwy::SetSupportedTargetsForTest(target); }
  ~ForcedTarget() { hwy::SetSupportedTargetsForTest(0); }
  ForcedTarget(const ForcedTarget&) = delete;
  ForcedTarget& operator=(const ForcedTarget&) = delete;
};

// Each target both compiled into a kernel file (its `compiled_targets()`) and run by this CPU,
// one bit per entry.
inline std::vector<int64_t> targets_to_run(int64_t compiled) {
  std::vector<int64_t> targets;
  const int64_t available = compiled & hwy::SupportedTargets();
  for (int64_t rest = available; rest != 0; rest &= rest - 1) targets.push_back(rest & -rest);
  return targets;
}

}  // namespace soltex::test
