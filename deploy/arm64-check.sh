#!/usr/bin/env bash
# The texture core, scene, rasterizer and renderer built for 64-bit ARM, and their unit and
# stability tests run there under qemu's user-mode emulator: the Highway kernels compile for
# ARM and their NEON code gives the scalar definitions' bits, as every x86 target does.
# Debian's cross compiler and the arm64 packages of the libraries (multiarch);
# SOLTEX_CORE_ONLY leaves out what needs gRPC, protobuf, Boost or spdlog (the server, the
# network client, the tools).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
build=${SOLTEX_ARM64_DIR:-$root/build-arm64}
jobs=${SOLTEX_JOBS:-2}

"$root/deploy/install-deps.sh" g++-aarch64-linux-gnu qemu-user libhwy-dev:arm64 \
  libgtest-dev:arm64 libgmock-dev:arm64 libzstd-dev:arm64 liblz4-dev:arm64 libxxhash-dev:arm64 \
  libmeshoptimizer-dev:arm64 libpugixml-dev:arm64 libglm-dev nlohmann-json3-dev libstb-dev

cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSOLTEX_CORE_ONLY=ON \
  -DSOLTEX_BUILD_BENCHMARKS=OFF -DCMAKE_TOOLCHAIN_FILE="$root/cmake/aarch64-linux-gnu.cmake" \
  >/dev/null
cmake --build "$build" -j "$jobs"
ctest --test-dir "$build" --output-on-failure -j "$jobs"
