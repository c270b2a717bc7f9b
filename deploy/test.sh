#!/usr/bin/env bash
# Builds soltex and runs every test through ctest (unit, integration over loopback), the
# scale-out test (memcached + three soltexd + nginx) and the soak, then the unit tests again
# under AddressSanitizer + UndefinedBehaviorSanitizer, then the libFuzzer targets for a
# bounded time, then the core's unit and stability tests built for 64-bit ARM.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# ccache hits across clones in different directories: hash paths relative to the clone.
export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
build=${SOLTEX_BUILD_DIR:-$root/build}
asan=${SOLTEX_ASAN_DIR:-$root/build-asan}
fuzz=${SOLTEX_FUZZ_DIR:-$root/build-fuzz}
jobs=${SOLTEX_JOBS:-2}

"$root/deploy/install-deps.sh"

echo "== web viewer: npm packages from package-lock.json"
(cd "$root/client/web" && npm ci --no-audit --no-fund --loglevel=error)

echo "== release build and all tests"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$jobs"
ctest --test-dir "$build" --output-on-failure -j "$jobs"

echo "== scale-out on loopback: memcached, three soltexd, nginx"
SOLTEX_BUILD_DIR="$build" "$root/deploy/scale-test.sh"
echo "== soak: 64 streams for 60 s, errors and memory"
SOLTEX_BUILD_DIR="$build" "$root/deploy/soak.sh"

echo "== ASan+UBSan build and unit tests"
cmake -S "$root" -B "$asan" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSOLTEX_SANITIZE=ON \
  -DSOLTEX_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$asan" --target unit_tests -j "$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$asan" -L unit --output-on-failure -j "$jobs"

echo "== libFuzzer (clang): decoders and parsers, ${SOLTEX_FUZZ_SECONDS:-30} s each"
CC=clang CXX=clang++ cmake -S "$root" -B "$fuzz" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSOLTEX_FUZZ=ON -DSOLTEX_NATIVE=OFF -DSOLTEX_BUILD_BENCHMARKS=OFF \
  -DSOLTEX_FUZZ_SECONDS="${SOLTEX_FUZZ_SECONDS:-30}" >/dev/null
cmake --build "$fuzz" --target fuzz_targets -j "$jobs"
ctest --test-dir "$fuzz" -L fuzz --output-on-failure

echo "== aarch64: the client's core cross-built, its unit and stability tests under qemu"
SOLTEX_JOBS="$jobs" "$root/deploy/arm64-check.sh"
