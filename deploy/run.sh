#!/usr/bin/env bash
# The main job: install what is needed, build soltex, start soltexd on loopback, render the
# default scene with soltex-view (headless) into a PNG, print what happened, stop the server.
# With --web instead: start soltexd (HTTP bricks) and nginx serving the web viewer
# (client/web) with a brick cache in front, all on loopback, print the page's URL and keep
# running until interrupted. `--web SCENE.json` shows that scene instead of the default one.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# ccache hits across clones in different directories: hash paths relative to the clone.
export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
build=${SOLTEX_BUILD_DIR:-$root/build}
out=${SOLTEX_OUT_DIR:-$root/out}

"$root/deploy/install-deps.sh"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
if [ "${1:-}" = "--web" ]; then
  exec "$root/deploy/run-web.sh" "${@:2}"
fi
cmake --build "$build" --target soltexd soltex-view -j "${SOLTEX_JOBS:-2}"

mkdir -p "$out"
ready="$out/soltexd.ready"
rm -f "$ready"
"$build/server/soltexd" --listen 127.0.0.1:0 --metrics-listen 127.0.0.1:0 \
  --ready-file "$ready" >"$out/soltexd.log" 2>&1 &
server=$!
trap 'kill "$server" 2>/dev/null || true' EXIT
for _ in $(seq 1 200); do [ -s "$ready" ] && break; sleep 0.05; done
[ -s "$ready" ] || { cat "$out/soltexd.log"; echo "run: soltexd did not start" >&2; exit 1; }
port=$(sed -n 's/^grpc=//p' "$ready")
metrics=$(sed -n 's/^metrics=//p' "$ready")
echo "run: soltexd listening on 127.0.0.1:$port (metrics on 127.0.0.1:$metrics)"

# Its exit code is the job's (README.md, "Exit codes": 3 is a picture that did not converge),
# once the server's figures are printed and the server is stopped.
view_status=0
"$build/client/view/soltex-view" --headless --server "127.0.0.1:$port" \
  --out "$out/soltex-view.png" "$@" || view_status=$?

served=$(curl -s "http://127.0.0.1:$metrics/metrics" 2>/dev/null |
  awk '/^soltex_bricks_served_total /{print $2}' || true)
echo "run: soltexd served ${served:-?} bricks"
kill -TERM "$server"
wait "$server" && echo "run: soltexd stopped cleanly" || echo "run: soltexd exited with $?"
trap - EXIT
if [ "$view_status" -ne 0 ]; then
  echo "run: soltex-view exited with $view_status (README.md, \"Exit codes\")" >&2
  exit "$view_status"
fi
