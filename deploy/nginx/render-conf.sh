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
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
# shellcheck source=nginx-template.sh
. "$here/nginx-template.sh"

nginx_template_args "$@"
nginx_prefix_dirs

echo "# soltex gRPC load balancer for nginx 1.22. Rendered from deploy/nginx/soltex-grpc.conf.in:"
echo "#   render-conf.sh $listen $prefix ${upstream_args[*]}"
echo "# Start:  nginx -p PREFIX -c PREFIX/nginx.conf   (-g 'daemon off;' for foreground)"
echo "# Stop:   nginx -p PREFIX -c PREFIX/nginx.conf -s quit   (open streams finish first)"
echo "# Paths below are relative to the prefix (-p), so it runs as any user."
nginx_fill_template "$here/soltex-grpc.conf.in"
