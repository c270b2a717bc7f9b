#!/usr/bin/env bash
# Builds soltex and runs every test through ctest, then builds the unit tests again with
# AddressSanitizer + UndefinedBehaviorSanitizer and runs them.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SOLTEX_BUILD_DIR:-$root/build}
asan=${SOLTEX_ASAN_DIR:-$root/build-asan}
jobs=${SOLTEX_JOBS:-2}

"$root/deploy/install-deps.sh"

echo "== release build and all tests"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$jobs"
ctest --test-dir "$build" --output-on-failure -j "$jobs"

echo "== ASan+UBSan build and unit tests"
cmake -S "$root" -B "$asan" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSOLTEX_SANITIZE=ON \
  -DSOLTEX_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$asan" --target unit_tests -j "$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$asan" -L unit --output-on-failure -j "$jobs"
