#!/usr/bin/env bash
# Prints deploy/nginx/soltex-grpc.conf.in with its placeholders filled in, and creates the
# prefix directory's logs/ and tmp/ so nginx can run there as any user.
#   render-conf.sh LISTEN_PORT PREFIX_DIR UPSTREAM [UPSTREAM...]
#   e.g. mkdir -p /tmp/soltex-nginx && render-conf.sh 7450 /tmp/soltex-nginx 127.0.0.1:7451 127.0.0.1:7452 > /tmp/soltex-nginx/nginx.conf
#        nginx -p /tmp/soltex-nginx -c /tmp/soltex-nginx/nginx.conf -g 'daemon off;'
# LISTEN_PORT may be PORT or ADDR:PORT. An UPSTREAM may carry server parameters after a space,
# e.g. "127.0.0.1:7451 max_fails=2". PREFIX_DIR "-" skips creating directories.
# Environment: NGINX_WORKERS (default auto), NGINX_ACCESS_LOG (default logs/access.log;
# /dev/stderr or "off" also work), NGINX_MAX_FAILS (default 1), NGINX_FAIL_TIMEOUT (default 5s).
set -euo pipefail

if [ $# -lt 3 ]; then
  echo "usage: $0 LISTEN_PORT PREFIX_DIR UPSTREAM [UPSTREAM...]" >&2
  exit 2
fi
listen=$1 prefix=$2
shift 2
template="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/soltex-grpc.conf.in"

if [ "$prefix" != "-" ]; then
  mkdir -p "$prefix/logs" "$prefix"/tmp/{client_body,proxy,fastcgi,uwsgi,scgi}
fi

upstreams=""
for u in "$@"; do
  # A replica that fails is skipped for fail_timeout; a draining one refuses new streams.
  upstreams+="        server $u max_fails=${NGINX_MAX_FAILS:-1} fail_timeout=${NGINX_FAIL_TIMEOUT:-5s};"$'\n'
done
upstreams=${upstreams%$'\n'}

workers=${NGINX_WORKERS:-auto}
access_log=${NGINX_ACCESS_LOG:-logs/access.log}

# The template's leading comment block documents the placeholders; the output gets its own.
echo "# soltex gRPC load balancer for nginx 1.22. Rendered from deploy/nginx/soltex-grpc.conf.in:"
echo "#   render-conf.sh $listen $prefix $*"
echo "# Start:  nginx -p PREFIX -c PREFIX/nginx.conf   (-g 'daemon off;' for foreground)"
echo "# Stop:   nginx -p PREFIX -c PREFIX/nginx.conf -s quit   (open streams finish first)"
echo "# Paths below are relative to the prefix (-p), so it runs as any user."
header=1
while IFS= read -r line || [ -n "$line" ]; do
  if [ $header -eq 1 ]; then
    case $line in '#'*) continue ;; *) header=0 ;; esac
  fi
  case $line in
    @UPSTREAMS@) printf '%s\n' "$upstreams"; continue ;;
  esac
  line=${line//@LISTEN@/$listen}
  line=${line//@WORKERS@/$workers}
  line=${line//@ACCESS_LOG@/$access_log}
  printf '%s\n' "$line"
done < "$template"
