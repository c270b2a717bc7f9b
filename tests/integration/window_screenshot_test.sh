#!/usr/bin/env bash
# soltex-view's window on a virtual X server (Xvfb), drawing the default scene without a
# server (--local). One run draws 20 frames and writes the window's last frame
# (--screenshot); during a second run the X screen itself is grabbed (xwd), so what reached
# the display is checked as well as what the renderer drew. Both must show the textured scene:
# not a flat colour, and more colours than the untextured first frames have (objects are drawn
# dark until their first bricks arrive). Every wait is bounded, and Xvfb and the viewer are
# stopped on exit.
#
# Usage: window_screenshot_test.sh SOLTEX_VIEW OUT_DIR
set -euo pipefail

if [ $# -ne 2 ]; then
  echo "usage: $0 SOLTEX_VIEW OUT_DIR" >&2
  exit 2
fi
viewer=$1
out=$2
mkdir -p "$out"
rm -f "$out"/*.png "$out"/*.log

min_deviation=0.02  # ImageMagick's normalized standard deviation; a flat screen has 0
min_colours=1000    # the default scene textured has about 10000, before any brick about 200
viewer_timeout=120  # seconds for a viewer run, probe included
grab_timeout=90     # seconds to wait for the window to show the scene

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

for tool in Xvfb xwd convert identify; do
  command -v "$tool" >/dev/null || fail "$tool is missing (deploy/install-deps.sh installs it)"
done

running() {  # pid: alive and not a zombie
  local state
  state=$(ps -o stat= -p "$1" 2>/dev/null || true)
  [ -n "$state" ] && [[ $state != Z* ]]
}

stop() {  # pid: TERM, up to 10 s to go, then KILL
  local pid=$1
  [ -n "$pid" ] || return 0
  kill "$pid" 2>/dev/null || true
  for _ in $(seq 1 100); do
    running "$pid" || break
    sleep 0.1
  done
  kill -9 "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
}

xvfb_pid=
viewer_pid=
cleanup() {
  stop "$viewer_pid"
  stop "$xvfb_pid"
}
trap cleanup EXIT

deviation() {  # image file -> its normalized standard deviation
  convert "$1" -format '%[fx:standard_deviation]' info:
}

colours() {  # image file -> how many distinct colours it has
  identify -format '%k' "$1"
}

shows_scene() {  # image file
  above "$(deviation "$1")" "$min_deviation" && above "$(colours "$1")" "$min_colours"
}

above() {  # a b: a > b
  awk -v a="$1" -v b="$2" 'BEGIN { exit !(a > b) }'
}

# A free display: no lock file and no socket, and Xvfb stays up and answers.
display=
for n in $(seq 90 99); do
  if [ -e "/tmp/.X$n-lock" ] || [ -e "/tmp/.X11-unix/X$n" ]; then continue; fi
  Xvfb ":$n" -screen 0 1280x800x24 -nolisten tcp >"$out/xvfb.log" 2>&1 &
  xvfb_pid=$!
  for _ in $(seq 1 100); do
    running "$xvfb_pid" || break
    if xwd -root -silent -display ":$n" >/dev/null 2>&1 && running "$xvfb_pid"; then
      display=":$n"
      break 2
    fi
    sleep 0.1
  done
  stop "$xvfb_pid"
  xvfb_pid=
done
[ -n "$display" ] || fail "could not start Xvfb on any of :90..:99 ($(cat "$out/xvfb.log"))"
echo "Xvfb on $display"

# The window's own screenshot. The x11 driver by name: SDL must not fall back to drawing
# off screen.
export DISPLAY=$display SDL_VIDEODRIVER=x11
status=0
timeout "$viewer_timeout" "$viewer" --local --frames 20 --screenshot "$out/window.png" \
  >"$out/window.log" 2>&1 || status=$?
cat "$out/window.log"
[ "$status" -eq 0 ] || fail "soltex-view --frames 20 --screenshot exited with $status"
[ -s "$out/window.png" ] || fail "no screenshot written"
size=$(identify -format '%wx%h' "$out/window.png")
echo "screenshot $out/window.png: $size, standard deviation $(deviation "$out/window.png")," \
  "$(colours "$out/window.png") colours"
shows_scene "$out/window.png" || fail "the screenshot does not show the textured scene"

# The X screen, grabbed while a second window is up and drawing.
timeout "$viewer_timeout" "$viewer" --local --frames 100000 >"$out/grab.log" 2>&1 &
viewer_pid=$!
deadline=$((SECONDS + grab_timeout))
while [ "$SECONDS" -lt "$deadline" ]; do
  running "$viewer_pid" || { cat "$out/grab.log"; fail "soltex-view exited before the grab"; }
  if xwd -root -silent -display "$display" 2>/dev/null | convert xwd:- "$out/x11.png" 2>/dev/null;
  then
    shows_scene "$out/x11.png" && break
  fi
  sleep 0.5
done
if command -v xwininfo >/dev/null; then
  xwininfo -root -tree -display "$display" | grep -i soltex || true
fi
[ -s "$out/x11.png" ] || fail "could not grab the X screen"
echo "X screen $out/x11.png: standard deviation $(deviation "$out/x11.png")," \
  "$(colours "$out/x11.png") colours"
shows_scene "$out/x11.png" ||
  fail "the X screen did not show the textured scene within $grab_timeout s"

# SIGTERM reaches SDL as a quit request: the viewer must close cleanly.
kill "$viewer_pid"
status=0
for _ in $(seq 1 200); do
  running "$viewer_pid" || break
  sleep 0.1
done
running "$viewer_pid" && fail "soltex-view did not quit within 20 s of SIGTERM"
wait "$viewer_pid" || status=$?
viewer_pid=
cat "$out/grab.log"
[ "$status" -eq 0 ] || fail "soltex-view did not quit cleanly on SIGTERM (exit $status)"
echo "PASS"
