#!/usr/bin/env bash
# Prints deploy/nginx/soltex-http.conf.in with its placeholders filled in, and creates the
# prefix directory's logs/, tmp/ and cache/ so nginx can run there as any user.
#   render-http-conf.sh LISTEN_PORT PREFIX_DIR UPSTREAM [UPSTREAM...]
#   e.g. mkdir -p /tmp/soltex-http && render-http-conf.sh 8440 /tmp/soltex-http 127.0.0.1:8441 > /tmp/soltex-http/nginx.conf
# LISTEN_PORT may be PORT or ADDR:PORT; each UPSTREAM a soltexd --http-listen address.
# Environment: NGINX_WORKERS (default auto), NGINX_ACCESS_LOG (default logs/access.log; "off"
# also works), NGINX_CACHE_SIZE (default 1g), NGINX_MAX_FAILS (default 1),
# NGINX_FAIL_TIMEOUT (default 5s), NGINX_WEB_ROOT (a folder to serve at /: the built web
# viewer, client/web/dist, with its scenes; default none: / answers 404).
set -euo pipefail

if [ $# -lt 3 ]; then
  echo "usage: $0 LISTEN_PORT PREFIX_DIR UPSTREAM [UPSTREAM...]" >&2
  exit 2
fi
listen=$1 prefix=$2
shift 2
template="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/soltex-http.conf.in"

if [ "$prefix" != "-" ]; then
  mkdir -p "$prefix/logs" "$prefix/cache" "$prefix"/tmp/{client_body,proxy,fastcgi,uwsgi,scgi}
fi

upstreams=""
for u in "$@"; do
  upstreams+="        server $u max_fails=${NGINX_MAX_FAILS:-1} fail_timeout=${NGINX_FAIL_TIMEOUT:-5s};"$'\n'
done
upstreams=${upstreams%$'\n'}

echo "# soltex HTTP brick cache for nginx 1.22. Rendered from deploy/nginx/soltex-http.conf.in:"
echo "#   render-http-conf.sh $listen $prefix $*"
echo "# Start:  nginx -p PREFIX -c PREFIX/nginx.conf   (-g 'daemon off;' for foreground)"
echo "# Stop:   nginx -p PREFIX -c PREFIX/nginx.conf -s quit"
header=1
while IFS= read -r line || [ -n "$line" ]; do
  if [ $header -eq 1 ]; then
    case $line in '#'*) continue ;; *) header=0 ;; esac
  fi
  case $line in
    @UPSTREAMS@) printf '%s\n' "$upstreams"; continue ;;
    @PAGE@)
      if [ -n "${NGINX_WEB_ROOT:-}" ]; then
        # Module scripts need their MIME type; nothing else here names one.
        printf '        location / {\n            root %s;\n            index index.html;\n' "$NGINX_WEB_ROOT"
        printf '            types { text/html html; text/javascript js; application/json json; text/css css; }\n'
        printf '        }\n' 
      else
        printf '        location / {\n            return 404 "no resource here; the routes are under /v1/textures\\n";\n        }\n'
      fi
      continue ;;
  esac
  line=${line//@LISTEN@/$listen}
  line=${line//@WORKERS@/${NGINX_WORKERS:-auto}}
  line=${line//@ACCESS_LOG@/${NGINX_ACCESS_LOG:-logs/access.log}}
  line=${line//@CACHE_SIZE@/${NGINX_CACHE_SIZE:-1g}}
  printf '%s\n' "$line"
done < "$template"
