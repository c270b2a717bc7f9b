#!/bin/bash
# soltex-view --headless draws the example graph scene (textures read from MaterialX documents)
# over a real soltexd on loopback: the picture is written and the server served its bricks.
#   graph_scene_view_test.sh <soltexd> <soltex-view> <source-dir> <work-dir>
set -euo pipefail
soltexd=$1 view=$2 source=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
"$soltexd" --listen 127.0.0.1:0 --metrics-listen 127.0.0.1:0 --ready-file "$work/ready" \
  > "$work/soltexd.log" 2>&1 &
server=$!
trap 'kill "$server" 2> /dev/null || true; wait "$server" 2> /dev/null || true' EXIT
for _ in $(seq 200); do
  grep -q '^metrics=' "$work/ready" 2> /dev/null && break
  sleep 0.1
done
port=$(sed -n 's/^grpc=//p' "$work/ready")
metrics=$(sed -n 's/^metrics=//p' "$work/ready")
test -n "$port"
"$view" --headless --server "127.0.0.1:$port" --scene "$source/deploy/scenes/graph-examples-mtlx.json" \
  --width 320 --height 135 --out "$work/graphs.png" 2>&1 | tee "$work/view.txt"
test -s "$work/graphs.png"
# Graphs are read through the brick cache: the picture came from the server's bricks.
received=$(sed -n 's/^bricks: *\([0-9]*\) received.*/\1/p' "$work/view.txt")
test "${received:-0}" -gt 0
# The server registered the four graph textures and evaluated their bricks.
page=$(curl -s "http://127.0.0.1:$metrics/metrics")
sum() { echo "$page" | awk -v name="$1" '$1 == name || index($1, name "{") == 1 { s += $NF } END { print s + 0 }'; }
echo "textures registered: $(sum soltex_textures_registered), bricks evaluated: $(sum soltex_bricks_evaluated_total)"
test "$(sum soltex_textures_registered)" -ge 4
awk -v n="$(sum soltex_bricks_evaluated_total)" 'BEGIN { exit !(n > 0) }'
