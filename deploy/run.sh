#!/usr/bin/env bash
# The main job: install what is needed, build soltex, and render the texture gallery (a slice
# through each solid texture and the texture on a lit sphere, one PNG per texture).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SOLTEX_BUILD_DIR:-$root/build}
out=${SOLTEX_OUT_DIR:-$root/out/gallery}

"$root/deploy/install-deps.sh"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --target soltex-gallery -j "${SOLTEX_JOBS:-2}"
"$build/client/gallery/soltex-gallery" --out "$out"
echo "run: $(ls "$out"/*.png | wc -l) PNG files in $out"
