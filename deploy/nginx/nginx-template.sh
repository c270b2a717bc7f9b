# Sourced by render-conf.sh and render-http-conf.sh: what filling in either template shares.
# Arguments (LISTEN_PORT PREFIX_DIR UPSTREAM...), the prefix's directories, the upstream
# servers and the common placeholders; a script handles its own block placeholders in a
# function `fill_block LINE` that returns 0 where it printed the block.

# Sets listen, prefix and upstream_args from the script's arguments, or exits 2 with usage.
nginx_template_args() {
  if [ $# -lt 3 ]; then
    echo "usage: $0 LISTEN_PORT PREFIX_DIR UPSTREAM [UPSTREAM...]" >&2
    exit 2
  fi
  listen=$1 prefix=$2
  upstream_args=("${@:3}")
}

# logs/ and nginx's temporary folders under the prefix, and any named in the arguments, so that
# nginx runs there as any user; PREFIX_DIR "-" creates nothing.
nginx_prefix_dirs() {
  [ "$prefix" = "-" ] && return 0
  local extra
  mkdir -p "$prefix/logs" "$prefix"/tmp/{client_body,proxy,fastcgi,uwsgi,scgi}
  for extra in "$@"; do mkdir -p "$prefix/$extra"; done
}

# The template after its leading comment block (which documents the placeholders), filled in.
nginx_fill_template() {
  local template=$1 header=1 line u upstreams=""
  for u in "${upstream_args[@]}"; do
    # A replica that fails is skipped for fail_timeout; parameters the upstream names itself
    # win over these defaults (nginx would take the last of two).
    local defaults=""
    [[ " $u " == *" max_fails="* ]] || defaults+=" max_fails=${NGINX_MAX_FAILS:-1}"
    [[ " $u " == *" fail_timeout="* ]] || defaults+=" fail_timeout=${NGINX_FAIL_TIMEOUT:-5s}"
    upstreams+="        server $u$defaults;"$'\n'
  done
  upstreams=${upstreams%$'\n'}
  while IFS= read -r line || [ -n "$line" ]; do
    if [ $header -eq 1 ]; then
      case $line in '#'*) continue ;; *) header=0 ;; esac
    fi
    if [ "$line" = "@UPSTREAMS@" ]; then printf '%s\n' "$upstreams"; continue; fi
    if declare -F fill_block >/dev/null && fill_block "$line"; then continue; fi
    line=${line//@LISTEN@/$listen}
    line=${line//@WORKERS@/${NGINX_WORKERS:-auto}}
    line=${line//@ACCESS_LOG@/${NGINX_ACCESS_LOG:-logs/access.log}}
    line=${line//@CACHE_SIZE@/${NGINX_CACHE_SIZE:-1g}}
    printf '%s\n' "$line"
  done < "$template"
}
