#!/usr/bin/env bash
# Scale-out on loopback: 2 memcached + 3 soltexd replicas sharing them + nginx balancing gRPC
# streams across the replicas; clients (soltex-view, soltex-load) go through nginx. Shows:
#   1. a brick evaluated once in the cluster is served from memcached by the other replicas;
#   2. killing one soltexd mid-run: its clients reconnect (through nginx, to another replica)
#      and still converge to the same picture;
#   3. killing one memcached mid-load: no client-visible errors;
#   4. bricks/s through nginx with 1 vs 3 replicas (on this 2-core machine every replica shares
#      the same two cores, so this measures the balancer's and the replicas' overhead, not
#      scaling);
#   5. two clients behind nginx are limited separately: one holding its stream limit does not
#      refuse the other (limits follow the name of each client's bearer token);
#   6. HTTP bricks through nginx's proxy_cache: a second client's bricks all come from nginx's
#      cache (X-Cache-Status HIT) while the replicas' counters stand still; a brick has one
#      entry, and its spellings soltexd refuses are refused through the cache too;
#   7. with no replica answering, nginx's own error reads as soltexd's do: a plain-text 503 with
#      CORS and Retry-After, so a page on another origin can see it and try again.
# Every process listens on 127.0.0.1 on ports the kernel picks; everything is stopped on exit.
# Usage: deploy/scale-test.sh            (builds nothing: run after the release build)
# Environment: SOLTEX_BUILD_DIR (default build), SCALE_LOAD_SECONDS (default 5),
#              SCALE_REPORT (a file to append the figures to).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SOLTEX_BUILD_DIR:-$root/build}
load_seconds=${SCALE_LOAD_SECONDS:-5}
soltexd=$build/server/soltexd
view=$build/client/view/soltex-view
load=$build/client/load/soltex-load
for tool in "$soltexd" "$view" "$load"; do
  [ -x "$tool" ] || { echo "scale-test: $tool is missing: build first (deploy/test.sh)" >&2; exit 2; }
done
for tool in memcached nginx python3; do
  command -v "$tool" >/dev/null || { echo "scale-test: $tool is not installed (deploy/install-deps.sh)" >&2; exit 2; }
done

work=$(mktemp -d /tmp/soltex-scale-XXXXXX)
chmod 755 "$work"  # nginx workers run as nobody
pids=()
cleanup() {
  [ -f "$work/nginx/logs/nginx.pid" ] && nginx -p "$work/nginx" -c "$work/nginx/nginx.conf" -s stop 2>/dev/null || true
  [ -f "$work/nginx1/logs/nginx.pid" ] && nginx -p "$work/nginx1" -c "$work/nginx1/nginx.conf" -s stop 2>/dev/null || true
  [ -f "$work/nginx5/logs/nginx.pid" ] && nginx -p "$work/nginx5" -c "$work/nginx5/nginx.conf" -s stop 2>/dev/null || true
  [ -f "$work/nginxh/logs/nginx.pid" ] && nginx -p "$work/nginxh" -c "$work/nginxh/nginx.conf" -s stop 2>/dev/null || true
  [ -f "$work/nginxd/logs/nginx.pid" ] && nginx -p "$work/nginxd" -c "$work/nginxd/nginx.conf" -s stop 2>/dev/null || true
  for pid in "${pids[@]}"; do kill -9 "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
  [ -n "${SCALE_KEEP:-}" ] || rm -rf "$work"
}
trap cleanup EXIT

failures=0
check() {  # check DESCRIPTION COMMAND...: prints ok/FAIL
  local what=$1; shift
  if "$@"; then echo "  ok    $what"; else echo "  FAIL  $what"; failures=$((failures + 1)); fi
}
free_port() {
  python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
wait_port() {  # wait until 127.0.0.1:$1 accepts connections
  for _ in $(seq 1 200); do
    (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null && return 0
    sleep 0.05
  done
  echo "scale-test: nothing listens on port $1" >&2
  return 1
}
metric() {  # metric REPLICA NAME: a sample from that replica's /metrics (0 when absent)
  curl -fsS "http://127.0.0.1:${metrics_port[$1]}/metrics" 2>/dev/null |
    awk -v name="$2" '$1 == name { print $2; found = 1 } END { if (!found) print 0 }'
}
sum_metric() {  # sum_metric NAME: over the replicas still running
  local total=0 r
  for r in 0 1 2; do
    if [ -n "${alive[$r]}" ]; then total=$(python3 -c "print(int($total + $(metric "$r" "$1")))"); fi
  done
  echo "$total"
}
converged() {  # converged FILE...: every render's report says it converged
  local f
  for f in "$@"; do grep -q "converged after" "$f" || return 1; done
}

echo "== scale-test: 2 memcached, 3 soltexd, nginx on loopback (work dir $work)"
memcached_port=()
for m in 0 1; do
  memcached_port[$m]=$(free_port)
  memcached -l 127.0.0.1 -p "${memcached_port[$m]}" -U 0 -m 64 -t 1 -u nobody &
  memcached_pid[$m]=$!
  pids+=("$!")
  wait_port "${memcached_port[$m]}"
done
nodes="127.0.0.1:${memcached_port[0]},127.0.0.1:${memcached_port[1]}"

grpc_port=() metrics_port=() http_port=() alive=()
start_replica() {  # start_replica R PORT [ARGS...]: replica R on 127.0.0.1:PORT (0: any), in the background
  local r=$1 port=$2
  rm -f "$work/ready$r"
  "$soltexd" --listen "127.0.0.1:$port" --metrics-listen 127.0.0.1:0 --ready-file "$work/ready$r" \
    --memcached "$nodes" --memcached-timeout-ms 100 --trusted-proxies 127.0.0.1 --threads 2 \
    --http-listen 127.0.0.1:0 "${@:3}" \
    --shutdown-grace-s 2 --log-level warn >>"$work/soltexd$r.log" 2>&1 &
  replica_pid[$r]=$!
  pids+=("$!")
}
replica_ready() {  # replica_ready R: wait for its ready file, read its ports
  local r=$1
  for _ in $(seq 1 400); do [ -s "$work/ready$r" ] && break; sleep 0.05; done
  grpc_port[$r]=$(sed -n 's/^grpc=//p' "$work/ready$r")
  metrics_port[$r]=$(sed -n 's/^metrics=//p' "$work/ready$r")
  http_port[$r]=$(sed -n 's/^http=//p' "$work/ready$r")
  alive[$r]=1
}
for r in 0 1 2; do start_replica "$r" 0; done
for r in 0 1 2; do replica_ready "$r"; done

start_nginx() {  # start_nginx DIR PORT UPSTREAM...
  local dir=$1 port=$2; shift 2
  mkdir -p "$dir"
  "$root/deploy/nginx/render-conf.sh" "127.0.0.1:$port" "$dir" "$@" >"$dir/nginx.conf"
  nginx -p "$dir" -c "$dir/nginx.conf" -e "$dir/logs/error.log"
  wait_port "$port"
}
lb_port=$(free_port)
start_nginx "$work/nginx" "$lb_port" "127.0.0.1:${grpc_port[0]}" "127.0.0.1:${grpc_port[1]}" \
  "127.0.0.1:${grpc_port[2]}"
echo "   memcached :${memcached_port[0]} :${memcached_port[1]}; soltexd :${grpc_port[0]} :${grpc_port[1]} :${grpc_port[2]}; nginx :$lb_port"

render() {  # render NAME TARGET FINEST_LEVEL WIDTH HEIGHT [args...]: headless soltex-view -> $work/NAME.txt
  local name=$1 target=$2 level=$3 width=$4 height=$5; shift 5
  "$view" --headless --server "$target" --finest-level "$level" --width "$width" --height "$height" \
    --threads 1 --max-time-s 60 --log-level warn --out "$work/$name.png" "$@" >"$work/$name.txt" 2>&1
}
field() {  # field FILE WORD: the number before WORD on the bricks: line (0 when absent)
  local value
  value=$(sed -n "s/^bricks: .* \([0-9][0-9]*\) $2.*/\1/p" "$1" | head -1)
  echo "${value:-0}"
}

echo "-- 1. a brick evaluated once is served from memcached by the other replicas"
render first "127.0.0.1:${grpc_port[0]}" 7 480 270
render second "127.0.0.1:${grpc_port[1]}" 7 480 270
evaluated_0=$(metric 0 soltex_bricks_evaluated_total)
evaluated_1=$(metric 1 soltex_bricks_evaluated_total)
shared_1=$(metric 1 soltex_bricks_from_shared_cache_total)
served_1=$(metric 1 soltex_bricks_served_total)
echo "   replica 0 evaluated $evaluated_0 bricks; replica 1 evaluated $evaluated_1 and read $shared_1 from memcached (it served $served_1)"
check "both renders converged" converged "$work/first.txt" "$work/second.txt"
check "replica 0 evaluated the bricks" test "${evaluated_0%.*}" -gt 0
check "replica 1 evaluated none of them" test "${evaluated_1%.*}" -eq 0
check "replica 1 read bricks from memcached" test "${shared_1%.*}" -gt 0
check "the two pictures are identical" cmp -s "$work/first.png" "$work/second.png"

echo "-- 2. one soltexd killed mid-run: clients reconnect through nginx and converge"
# Supersampled bricks at 2^10 over a 1280x720 frame: a few seconds of work for the cluster.
phase2=(10 1280 720 --mip supersampled)
# Kill a replica while it carries clients' main streams. A client of a loopback address (nginx
# here) probes no link: it opens one stream, which stays open until that client has every
# brick. Once three streams were opened in this phase and three are open, they are the three
# clients' streams, each still short of its frame; the victim is the replica with most of them.
# (A deep queue is no proof: a fast client may already hold what it needs while cancelled wants
# still sit in the replica's queue.)
stream_counts() {  # stream_counts R: "OPENED_TOTAL OPEN" for replica R
  curl -fsS "http://127.0.0.1:${metrics_port[$1]}/metrics" 2>/dev/null | awk '
    $1 == "soltex_streams_opened_total" { opened = $2 } $1 == "soltex_streams_open" { open = $2 }
    END { printf "%d %d\n", opened, open }'
}
for r in 0 1 2; do read -r opened_before[r] _ < <(stream_counts "$r"); done
for c in 0 1 2; do
  render "client$c" "127.0.0.1:$lb_port" "${phase2[@]}" &
  client_pid[$c]=$!
done
victim="" victim_streams=0
for _ in $(seq 1 600); do
  opened_sum=0 open_sum=0 busiest=0
  for r in 0 1 2; do
    read -r opened open < <(stream_counts "$r")
    opened_sum=$((opened_sum + opened - opened_before[r])) open_sum=$((open_sum + open))
    if [ "$open" -gt "$busiest" ]; then busiest=$open candidate=$r; fi
  done
  if [ "$opened_sum" -ge 3 ] && [ "$open_sum" -eq 3 ]; then victim=$candidate victim_streams=$busiest; break; fi
  sleep 0.005
done
if [ -n "$victim" ]; then
  # Let it get under way first: 100 bricks more, far short of the frame its clients need.
  served() { local v; v=$(metric "$1" soltex_bricks_served_total); echo "${v%.*}"; }
  served_then=$(served "$victim")
  for _ in $(seq 1 400); do
    [ $(($(served "$victim") - served_then)) -ge 100 ] && break
    sleep 0.005
  done
  queued=$(metric "$victim" soltex_queue_depth) into=$(($(served "$victim") - served_then))
  kill -9 "${replica_pid[$victim]}"
  wait "${replica_pid[$victim]}" 2>/dev/null || true
  alive[$victim]=""
  echo "   killed replica $victim while it carried $victim_streams of the 3 main streams, $into bricks into them, ${queued%.*} queued"
else
  echo "   the three main streams were never open at once: nothing was killed"
fi
client_failures=0
for c in 0 1 2; do wait "${client_pid[$c]}" || client_failures=$((client_failures + 1)); done
reconnects=0
for c in 0 1 2; do reconnects=$((reconnects + $(field "$work/client$c.txt" reconnects))); done
check "every client exited cleanly" test "$client_failures" -eq 0
check "every client converged" converged "$work/client0.txt" "$work/client1.txt" "$work/client2.txt"
check "the killed replica's clients reconnected ($reconnects reconnects for $victim_streams streams)" \
  test "$victim_streams" -ge 1 -a "$reconnects" -ge "$victim_streams"
check "all three pictures are identical" sh -c "cmp -s '$work/client0.png' '$work/client1.png' && cmp -s '$work/client0.png' '$work/client2.png'"
render alone "127.0.0.1:${grpc_port[$(( (${victim:-0} + 1) % 3 ))]}" "${phase2[@]}"
check "and equal to a render from one surviving replica" cmp -s "$work/client0.png" "$work/alone.png"

# Bring the killed replica back for the rest, on its port (nginx knows it by that).
if [ -n "$victim" ]; then
  start_replica "$victim" "${grpc_port[$victim]}"
  replica_ready "$victim"
fi

echo "-- 3. one memcached killed mid-load: no client-visible errors"
errors_of() {  # errors_of JSON_FILE: every error soltex-load counted
  python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); e=r["errors"]; print(sum(sum(v.values()) for v in e.values()) + r["unanswered"] + r["checksum_failures"])' "$1"
}
"$load" --server "127.0.0.1:$lb_port" --connections 4 --streams 8 --mix uniform --finest-level 10 \
  --duration-s "$load_seconds" --verify --no-progress --format json --seed 7 >"$work/memcached-kill.json" &
load_pid=$!
sleep "$(python3 -c "print($load_seconds / 2)")"
kill -9 "${memcached_pid[1]}"
wait "${memcached_pid[1]}" 2>/dev/null || true
wait "$load_pid"
errors=$(errors_of "$work/memcached-kill.json")
shared_errors=$(sum_metric soltex_shared_cache_errors_total)
bricks=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["bricks"])' "$work/memcached-kill.json")
echo "   $bricks bricks, $errors client-visible errors; the replicas counted $shared_errors memcached failures and evaluated instead"
check "no client-visible errors" test "$errors" -eq 0
check "bricks kept flowing" test "$bricks" -gt 0

echo "-- 4. bricks/s through nginx: 1 replica vs 3 (hot set, warm caches; 2 shared cores)"
lb1_port=$(free_port)
start_nginx "$work/nginx1" "$lb1_port" "127.0.0.1:${grpc_port[0]}"
hot=(--connections 4 --streams 16 --mix hot --hot-set 256 --in-flight 16 --warmup-s 1
     --duration-s "$load_seconds" --no-progress --format json)
"$load" --server "127.0.0.1:$lb1_port" "${hot[@]}" >"$work/one.json"
"$load" --server "127.0.0.1:$lb_port" "${hot[@]}" >"$work/three.json"
"$load" --server "127.0.0.1:$lb1_port" "${hot[@]}" >"$work/one-again.json"
rate() { python3 -c 'import json,sys; print(round(json.load(open(sys.argv[1]))["bricks_per_second"]))' "$1"; }
one=$(rate "$work/one.json") three=$(rate "$work/three.json") again=$(rate "$work/one-again.json")
summary="bricks/s through nginx, hot set: 1 replica $one and $again (before and after), 3 replicas $three (ratio $(python3 -c "print(round($three / (($one + $again) / 2), 2))"))"
echo "   $summary"
check "no errors under either" test "$(errors_of "$work/one.json")$(errors_of "$work/three.json")" = "00"
if [ -n "${SCALE_REPORT:-}" ]; then echo "$summary" >>"$SCALE_REPORT"; fi

echo "-- 5. two clients behind nginx are limited separately (limits follow each client's token)"
# A fourth replica with named tokens and at most 4 streams per client, alone behind its own
# nginx so that every stream meets the same limit. nginx is the peer of every stream; soltexd
# believes its x-forwarded-for (--trusted-proxies), but on loopback every client has the same
# address, so the token's name is what tells the two apart.
printf '# NAME TOKEN\nalice scale-alice-token\nbob scale-bob-token\n' >"$work/tokens"
echo scale-alice-token >"$work/alice.token"
echo scale-bob-token >"$work/bob.token"
start_replica 3 0 --token-file "$work/tokens" --max-streams-per-client 4
replica_ready 3
lb5_port=$(free_port)
start_nginx "$work/nginx5" "$lb5_port" "127.0.0.1:${grpc_port[3]}"
limited=(--connections 1 --mix hot --hot-set 64 --in-flight 4 --duration-s 4 --no-progress --format json)
# alice asks for 8 streams: 4 are served and held for the whole run, 4 refused.
"$load" --server "127.0.0.1:$lb5_port" --token-file "$work/alice.token" --streams 8 "${limited[@]}" \
  >"$work/alice.json" &
alice_pid=$!
for _ in $(seq 1 400); do  # until alice holds her 4
  [ "$(metric 3 soltex_streams_open)" = 4 ] && break
  sleep 0.01
done
held=$(metric 3 soltex_streams_open)
"$load" --server "127.0.0.1:$lb5_port" --token-file "$work/bob.token" --streams 2 \
  --connections 1 --mix hot --hot-set 64 --in-flight 4 --duration-s 1 --no-progress --format json \
  >"$work/bob.json" || true
wait "$alice_pid" || true
streams_refused() {  # streams_refused JSON_FILE: streams that ended RESOURCE_EXHAUSTED
  python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["errors"]["streams"].get("RESOURCE_EXHAUSTED", 0))' "$1"
}
bricks_of() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["bricks"])' "$1"; }
alice_refused=$(streams_refused "$work/alice.json") bob_errors=$(errors_of "$work/bob.json")
bob_bricks=$(bricks_of "$work/bob.json")
echo "   alice: 8 streams asked, $alice_refused refused (limit 4), ${held%.*} open when bob started; bob: $bob_bricks bricks, $bob_errors errors"
check "alice was held to her 4 streams" test "$alice_refused" -eq 4
check "alice held all 4 when bob started" test "${held%.*}" -eq 4
check "bob was served while alice held her limit" test "$bob_bricks" -gt 0 -a "$bob_errors" -eq 0
check "the replica named alice by her token" grep -q "token:alice" "$work/soltexd3.log"

echo "-- 6. HTTP bricks through nginx's cache: a second client costs the replicas nothing"
http_lb_port=$(free_port)
mkdir -p "$work/nginxh"
"$root/deploy/nginx/render-http-conf.sh" "127.0.0.1:$http_lb_port" "$work/nginxh" \
  "127.0.0.1:${http_port[0]}" "127.0.0.1:${http_port[1]}" "127.0.0.1:${http_port[2]}" \
  >"$work/nginxh/nginx.conf"
nginx -p "$work/nginxh" -c "$work/nginxh/nginx.conf" -e "$work/nginxh/logs/error.log"
wait_port "$http_lb_port"
# Both clients ask for the same 128 bricks (same seed), one request at a time per connection.
http_load=(--http --connections 2 --mix hot --hot-set 128 --duration-s 1 --verify --no-progress
           --format json --seed 11)
replica_work() {  # bricks the replicas made or looked up for anyone, HTTP or gRPC
  echo "$(sum_metric soltex_bricks_evaluated_total) $(sum_metric soltex_cache_hits_total)" \
       "$(sum_metric soltex_cache_misses_total) $(sum_metric soltex_http_bricks_served_total)"
}
"$load" --server "127.0.0.1:$http_lb_port" "${http_load[@]}" >"$work/http-first.json"
work_before=$(replica_work)
"$load" --server "127.0.0.1:$http_lb_port" "${http_load[@]}" >"$work/http-second.json"
work_after=$(replica_work)
http_field() {  # http_field FILE EXPRESSION: a value of a soltex-load --http JSON report
  python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))' "$1" "$2"
}
first_hits=$(http_field "$work/http-first.json" 'r["cache_statuses"].get("HIT", 0)')
first_requests=$(http_field "$work/http-first.json" 'r["requests"]')
second_requests=$(http_field "$work/http-second.json" 'r["requests"]')
second_hits=$(http_field "$work/http-second.json" 'r["cache_statuses"].get("HIT", 0)')
second_ok=$(http_field "$work/http-second.json" 'r["statuses"].get("200", 0)')
http_rate() { http_field "$1" 'round(r["bricks_per_second"])'; }
http_p99() { http_field "$1" 'round(r["latency_us"]["p99"])'; }
summary="HTTP through nginx's cache, 2 connections: first client $(http_rate "$work/http-first.json") bricks/s ($first_hits of $first_requests cache hits, p99 $(http_p99 "$work/http-first.json") us), second $(http_rate "$work/http-second.json") bricks/s ($second_hits of $second_requests hits, p99 $(http_p99 "$work/http-second.json") us)"
echo "   $summary"
echo "   replicas' bricks evaluated, cache hits, cache misses, HTTP bricks served: before the second client $work_before, after $work_after"
check "the second client got every brick" test "$second_requests" -gt 0 -a "$second_ok" -eq "$second_requests"
check "every one of them from nginx's cache (X-Cache-Status HIT)" test "$second_hits" -eq "$second_requests"
check "the replicas did no work for it (their counters unchanged)" test "$work_before" = "$work_after"
check "no checksum failures" test "$(http_field "$work/http-first.json" 'r["checksum_failures"]')$(http_field "$work/http-second.json" 'r["checksum_failures"]')" = "00"
if [ -n "${SCALE_REPORT:-}" ]; then echo "$summary" >>"$SCALE_REPORT"; fi
# One spelling, one entry: a spelling soltexd refuses is refused through the cache too, and
# ?codec=zstd is the entry of the default codec.
lb="http://127.0.0.1:$http_lb_port"
handle=$(curl -fsS --data '{"texture": {"wood": {}}}' "$lb/v1/textures")
id=$(echo "$handle" | python3 -c 'import json,sys; print(json.load(sys.stdin)["id"])')
spec=$(echo "$handle" | python3 -c 'import json,sys; print(json.load(sys.stdin)["spec"])')
answer() {  # answer PATH [QUERY]: status and X-Cache-Status, with the spec any replica reads
  curl -sS -o /dev/null -D - "$lb/v1/textures/$id/bricks/$1?spec=$spec${2:-}" |
    tr -d '\r' | awk 'NR == 1 {code = $2} tolower($1) == "x-cache-status:" {c = $2}
                      END {print code, c}'
}
check "a canonical brick URL is cached" test "$(answer 1/0/0/1) $(answer 1/0/0/1)" = "200 MISS 200 HIT"
check "its other spellings are refused, not answered from its entry" \
  test "$(answer 1/0/0/%31 | cut -d' ' -f1) $(answer 1//0/0/1 | cut -d' ' -f1)" = "400 404"
check "codec=zstd is the default codec's entry" test "$(answer 1/0/0/1 '&codec=zstd')" = "200 HIT"
check "a query soltexd refuses is refused through the cache too" \
  test "$(answer 1/0/0/1 '&codec=' | cut -d' ' -f1) $(answer 1/0/0/1 '&cdec=raw' | cut -d' ' -f1)" = "400 400"

echo "-- 7. no replica answering: nginx's error in soltexd's form"
dead_lb_port=$(free_port)
mkdir -p "$work/nginxd"
"$root/deploy/nginx/render-http-conf.sh" "127.0.0.1:$dead_lb_port" "$work/nginxd" \
  "127.0.0.1:$(free_port)" >"$work/nginxd/nginx.conf"
nginx -p "$work/nginxd" -c "$work/nginxd/nginx.conf" -e "$work/nginxd/logs/error.log"
wait_port "$dead_lb_port"
curl -sS -D "$work/dead-headers.txt" -o "$work/dead-body.txt" -H 'Origin: http://page.example' \
  "http://127.0.0.1:$dead_lb_port/v1/textures/0123456789abcdef/bricks/0/0/0/0?codec=raw" || true
dead_header() { tr -d '\r' <"$work/dead-headers.txt" | awk -v n="$1" 'tolower($1) == tolower(n) ":" {print $2}'; }
check "status 503" grep -q '^HTTP/1.1 503' "$work/dead-headers.txt"
check "plain text" test "$(dead_header Content-Type)" = "text/plain"
check "CORS: Access-Control-Allow-Origin *" test "$(dead_header Access-Control-Allow-Origin)" = "*"
check "Retry-After 1, exposed to the page" test "$(dead_header Retry-After) $(dead_header Access-Control-Expose-Headers)" = "1 Retry-After"

if [ "$failures" -gt 0 ]; then
  echo "scale-test: $failures checks failed; logs:"
  tail -n 20 "$work"/*.log "$work"/*.txt >&2 || true
  exit 1
fi
echo "scale-test: all checks passed"
