#!/usr/bin/env bash
# Soak: soltex-load with 64 streams against one soltexd for 60 s, bricks from every level of a
# 2^10 texture (mostly cold, so the cache fills and evicts all the time). Passes when no request
# failed and the server's resident memory never exceeded its cache budget plus the stated
# overhead. Prints the memory it saw once a second.
# Usage: deploy/soak.sh   (after the release build)
# Environment: SOLTEX_BUILD_DIR (default build), SOAK_SECONDS (60), SOAK_CACHE_MB (64),
#              SOAK_OVERHEAD_MB (64: what soltexd holds besides its cache, see docs/OPERATIONS.md)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SOLTEX_BUILD_DIR:-$root/build}
seconds=${SOAK_SECONDS:-60}
cache_mb=${SOAK_CACHE_MB:-64}
overhead_mb=${SOAK_OVERHEAD_MB:-64}
soltexd=$build/server/soltexd
load=$build/client/load/soltex-load
for tool in "$soltexd" "$load"; do
  [ -x "$tool" ] || { echo "soak: $tool is missing: build first (deploy/test.sh)" >&2; exit 2; }
done

work=$(mktemp -d /tmp/soltex-soak-XXXXXX)
server_pid=""
cleanup() {
  [ -n "$server_pid" ] && kill -9 "$server_pid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

"$soltexd" --listen 127.0.0.1:0 --metrics-listen 127.0.0.1:0 --ready-file "$work/ready" \
  --cache-mb "$cache_mb" --log-level warn >"$work/soltexd.log" 2>&1 &
server_pid=$!
for _ in $(seq 1 400); do [ -s "$work/ready" ] && break; sleep 0.05; done
port=$(sed -n 's/^grpc=//p' "$work/ready")
metrics_port=$(sed -n 's/^metrics=//p' "$work/ready")
rss_kb() { awk '/^VmRSS/ { print $2 }' "/proc/$server_pid/status"; }
idle_kb=$(rss_kb)

echo "== soak: 64 streams for ${seconds} s against soltexd with a ${cache_mb} MiB cache"
"$load" --server "127.0.0.1:$port" --connections 8 --streams 64 --in-flight 16 --mix uniform \
  --finest-level 10 --duration-s "$seconds" --verify --no-progress --format json >"$work/load.json" &
load_pid=$!
peak_kb=$idle_kb
samples=()
while kill -0 "$load_pid" 2>/dev/null; do
  now_kb=$(rss_kb)
  samples+=("$((now_kb / 1024))")
  [ "$now_kb" -gt "$peak_kb" ] && peak_kb=$now_kb
  sleep 1
done
wait "$load_pid"
hwm_kb=$(awk '/^VmHWM/ { print $2 }' "/proc/$server_pid/status")
[ "$hwm_kb" -gt "$peak_kb" ] && peak_kb=$hwm_kb
cache_bytes=$(curl -fsS "http://127.0.0.1:$metrics_port/metrics" | awk '$1 == "soltex_cache_bytes" { print $2 }')
evictions=$(curl -fsS "http://127.0.0.1:$metrics_port/metrics" | awk '$1 == "soltex_cache_evictions_total" { print $2 }')

read -r bricks rate errors p99 < <(python3 - "$work/load.json" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
errors = sum(sum(v.values()) for v in r["errors"].values()) + r["unanswered"] + r["checksum_failures"]
print(r["bricks"], round(r["bricks_per_second"]), errors, round(r["latency_ns"]["p99"] / 1e6, 2))
EOF
)
bound_kb=$(((cache_mb + overhead_mb) * 1024))
echo "   resident MiB once a second: ${samples[*]}"
echo "   $bricks bricks ($rate/s, p99 $p99 ms), $errors errors, $evictions evictions"
echo "   soltexd resident: idle $((idle_kb / 1024)) MiB, peak $((peak_kb / 1024)) MiB; cache held $((${cache_bytes%.*} / 1048576)) MiB of its $cache_mb MiB"
echo "   bound: cache budget + ${overhead_mb} MiB overhead = $((bound_kb / 1024)) MiB"
status=0
[ "$errors" -eq 0 ] || { echo "soak: FAIL: $errors errors" >&2; status=1; }
[ "$peak_kb" -le "$bound_kb" ] || { echo "soak: FAIL: peak resident memory over the bound" >&2; status=1; }
kill -TERM "$server_pid"
wait "$server_pid" || { echo "soak: FAIL: soltexd did not stop cleanly" >&2; status=1; }
server_pid=""
[ "$status" -eq 0 ] && echo "soak: passed"
exit "$status"
