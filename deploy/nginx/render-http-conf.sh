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
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
# shellcheck source=nginx-template.sh
. "$here/nginx-template.sh"

# @PAGE@: what answers at /, the web viewer's folder or a 404 naming the routes.
fill_block() {
  [ "$1" = "@PAGE@" ] || return 1
  if [ -n "${NGINX_WEB_ROOT:-}" ]; then
    # Module scripts need their MIME type; nothing else here names one.
    printf '        location / {\n            root %s;\n            index index.html;\n' "$NGINX_WEB_ROOT"
    printf '            types { text/html html; text/javascript js; application/json json; text/css css; }\n'
    # Scenes are JSON of up to megabytes (a mesh inline): about a fifth of that compressed.
    printf '            gzip on;\n            gzip_types application/json text/javascript text/css;\n'
    printf '        }\n'
  else
    printf '        location / {\n            return 404 "no resource here; the routes are under /v1/textures\\n";\n        }\n'
  fi
}

nginx_template_args "$@"
nginx_prefix_dirs cache

echo "# soltex HTTP brick cache for nginx 1.22. Rendered from deploy/nginx/soltex-http.conf.in:"
echo "#   render-http-conf.sh $listen $prefix ${upstream_args[*]}"
echo "# Start:  nginx -p PREFIX -c PREFIX/nginx.conf   (-g 'daemon off;' for foreground)"
echo "# Stop:   nginx -p PREFIX -c PREFIX/nginx.conf -s quit"
nginx_fill_template "$here/soltex-http.conf.in"
