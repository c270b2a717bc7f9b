#!/usr/bin/env bash
# Installs the Debian packages soltex builds and tests with, or those named as arguments
# (arm64-check.sh's cross toolchain). Quick when they are present: apt runs only when
# something is missing. A package of another architecture (name:arm64) adds that
# architecture to dpkg first.
set -euo pipefail

if [ $# -gt 0 ]; then
  packages=("$@")
else
packages=(
  build-essential cmake ninja-build ccache pkg-config curl
  clang libclang-rt-14-dev        # libFuzzer and the sanitizer runtimes
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libabsl-dev                             # abseil (gRPC's): its mutex deadlock tracking is turned off
  libboost-dev libglm-dev libspdlog-dev libcli11-dev libstb-dev libxxhash-dev libzstd-dev liblz4-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  nlohmann-json3-dev
  libsdl2-dev xvfb x11-apps imagemagick   # soltex-view's window and its test on a virtual X server
  libmemcached-dev memcached nginx-light  # the shared brick cache and the balancer of the scale test
  python3                                 # the scale test reads soltex-load's JSON reports
  python3-prometheus-client               # the Prometheus parser the /metrics test reads the page with
  python3-grpcio python3-protobuf python3-numpy python3-lz4 python3-zstandard python3-xxhash
                                          # the Python client of docs/PROTOCOL.md (tests/python/)
  openssl                                 # certificates for the TLS tests
  libssl-dev                              # HTTPS bricks (--http-listen with --tls-cert)
  python3-matplotlib                      # soltex-bench accuracy's plot (client/bench/plot_accuracy.py)
  libmeshoptimizer-dev                    # mesh ordering and clean-up (client/scene)
  libhwy-dev                              # Highway: SIMD kernels chosen at run time
  libjemalloc-dev                         # jemalloc: the streaming programs' allocator (common/allocator)
  libpugixml-dev                          # MaterialX documents (XML)
  chromium                                # the web viewer's test in a real (headless) browser
)
# The web viewer (client/web) builds and tests with Node.js and npm; vite 7 needs Node 20.19 or
# later (Debian 13's nodejs; on Debian 12 install Node 20 from nodejs.org or NodeSource).
command -v npm >/dev/null || packages+=(nodejs npm)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "deploy: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "deploy: installing ${missing[*]}"
for p in "${missing[@]}"; do
  case "$p" in
    *:*)
      arch=${p##*:}
      dpkg --print-foreign-architectures | grep -qx "$arch" || $sudo dpkg --add-architecture "$arch"
      ;;
  esac
done
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${packages[@]}"
