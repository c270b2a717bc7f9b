#!/usr/bin/env bash
# Checks that the runtime stage of deploy/docker/Dockerfile installs the Debian package of every
# shared library a soltexd binary links (ldd, then dpkg -S), so that a new dependency cannot
# leave the image unable to start. Run on a Debian machine with the build's packages installed:
#   deploy/docker/check-runtime-packages.sh build/server/soltexd
set -euo pipefail

binary=${1:?usage: check-runtime-packages.sh SOLTEXD_BINARY}
dockerfile=$(dirname "$0")/Dockerfile

# The runtime stage's text, from its FROM line to the end.
runtime=$(sed -n '/AS runtime/,$p' "$dockerfile")
missing=()
while read -r library; do
  package=$(dpkg -S "$(readlink -f "$library")" 2>/dev/null || dpkg -S "$library" 2>/dev/null) ||
    { echo "no Debian package holds $library" >&2; exit 1; }
  package=${package%%:*}
  case $package in libc6) continue ;; esac  # the base image's own
  grep -qw -- "$package" <<<"$runtime" || missing+=("$package (for $(basename "$library"))")
done < <(ldd "$binary" | awk '/=> \//{print $3}')

if [ ${#missing[@]} -gt 0 ]; then
  printf 'deploy/docker/Dockerfile: the runtime stage does not install %s\n' "${missing[@]}" >&2
  exit 1
fi
echo "the runtime stage installs every package soltexd links"
