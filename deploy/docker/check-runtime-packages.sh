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
mapfile -t libraries < <(ldd "$binary" | awk '/=> \//{print $3}')
# Each library as ldd names it and as its link resolves (/lib or /usr/lib: a package records
# one of them), all in one dpkg -S, which reads its database once per call: a call for each
# library took most of a minute on a loaded machine.
queries=()
for library in "${libraries[@]}"; do queries+=("$library" "$(readlink -f "$library")"); done
declare -A package_of
while IFS= read -r line; do
  packages=${line%%: *}
  package_of[${line#*: }]=${packages%%[:,]*}
done < <(dpkg -S "${queries[@]}" 2>/dev/null || true)

missing=()
for library in "${libraries[@]}"; do
  package=${package_of[$(readlink -f "$library")]:-${package_of[$library]:-}}
  [ -n "$package" ] || { echo "no Debian package holds $library" >&2; exit 1; }
  case $package in libc6) continue ;; esac  # the base image's own
  grep -qw -- "$package" <<<"$runtime" || missing+=("$package (for $(basename "$library"))")
done

if [ ${#missing[@]} -gt 0 ]; then
  printf 'deploy/docker/Dockerfile: the runtime stage does not install %s\n' "${missing[@]}" >&2
  exit 1
fi
echo "the runtime stage installs every package soltexd links"
