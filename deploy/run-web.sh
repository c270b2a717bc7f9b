#!/usr/bin/env bash
# deploy/run.sh --web: soltexd with --http-listen, nginx serving the built web viewer and
# caching bricks in front of soltexd, all on loopback; prints the URL and runs until
# interrupted (Ctrl-C stops both). Expects the build directory configured (run.sh does it).
#   deploy/run-web.sh [SCENE.json]        (default: the built-in scene and the knot)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SOLTEX_BUILD_DIR:-$root/build}
out=${SOLTEX_OUT_DIR:-$root/out}
web=$out/web
# Whether every folder from / down to $1 lets others in.
others_may_enter() {
  local dir=$1
  while [ "$dir" != / ]; do
    [[ $(stat -c %A "$dir") == d????????[xt] ]] || return 1
    dir=$(dirname "$dir")
  done
}
# nginx started as root runs its workers as nobody, who must reach the page and the cache: a
# clone under a private folder (/root) keeps them under one everybody may enter instead.
mkdir -p "$out"
if [ "$(id -u)" = 0 ] && ! others_may_enter "$out"; then
  web=$(mktemp -d "${TMPDIR:-/tmp}/soltex-web.XXXXXX")
  echo "run: $out is private; the page and nginx's cache go to $web"
fi
cmake --build "$build" --target soltexd soltex-scene-export -j "${SOLTEX_JOBS:-2}"
(cd "$root/client/web" && npm ci --no-audit --no-fund --loglevel=error && npx vite build --logLevel warn)

rm -rf "$web" && mkdir -p "$web/site/scenes" "$web/nginx"
chmod 755 "$web" "$web/site"  # nginx workers run as nobody
[[ $web != "$out"/* ]] || chmod 755 "$out"
cp -r "$root/client/web/dist/." "$web/site/"
export_scene() { "$build/client/web/soltex-scene-export" --out "$web/site/scenes/$1.json" "${@:2}"; }
export_scene default
export_scene knot --scene "$root/deploy/scenes/knot-marble.json"
[ -z "${1:-}" ] || export_scene "$(basename "$1" .json)" --scene "$1"
chmod -R a+rX "$web/site"

ready="$web/soltexd.ready"
"$build/server/soltexd" --listen 127.0.0.1:0 --metrics-listen 127.0.0.1:0 --http-listen 127.0.0.1:0 \
  --trusted-proxies 127.0.0.1 --ready-file "$ready" >"$web/soltexd.log" 2>&1 &
server=$!
stop() {
  nginx -p "$web/nginx" -c "$web/nginx/nginx.conf" -s stop 2>/dev/null || true
  kill "$server" 2>/dev/null || true
}
trap stop EXIT
trap 'exit 130' INT TERM  # through the EXIT trap: nothing is left running
for _ in $(seq 1 200); do [ -s "$ready" ] && grep -q '^http=' "$ready" && break; sleep 0.05; done
http=$(sed -n 's/^http=//p' "$ready")
[ -n "$http" ] || { cat "$web/soltexd.log"; echo "run: soltexd did not start" >&2; exit 1; }
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
NGINX_WEB_ROOT="$web/site" NGINX_WORKERS=1 "$root/deploy/nginx/render-http-conf.sh" \
  "127.0.0.1:$port" "$web/nginx" "127.0.0.1:$http" >"$web/nginx/nginx.conf"
nginx -p "$web/nginx" -c "$web/nginx/nginx.conf" -e "$web/nginx/logs/error.log"
scene=default
[ -z "${1:-}" ] || scene=$(basename "$1" .json)
echo "run: soltexd HTTP bricks on 127.0.0.1:$http, nginx (page and brick cache) on 127.0.0.1:$port"
echo "run: open http://127.0.0.1:$port/?scene=scenes/$scene.json   (also scenes/knot.json; Ctrl-C stops)"
wait "$server"
