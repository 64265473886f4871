#!/usr/bin/env bash
# Real-window smoke test of `kansei app`: starts it on a fixture under Xvfb with Mesa's software
# OpenGL, takes a screenshot of the root window and checks that the fitted curve is drawn: the
# canvas (the largest white region) holds ink, and some of it is coloured (LAC segments are
# coloured by α; samples and the B-spline are grey). Installs Xvfb and Mesa with apt-get if missing.
#
# Usage: .ci/app-smoke.sh [KANSEI_BINARY]   (default: target/debug/kansei, built if absent)
set -euo pipefail
cd "$(dirname "$0")/.."

FIXTURE=fixtures/strokes/perfect-freehand-waves.json
# Screenshots are taken every POLL_S seconds until the curve shows or DEADLINE_S have passed
# (software GL is slow to start, and the fit runs in whatever build profile the binary has).
POLL_S=3
DEADLINE_S=${KANSEI_SMOKE_DEADLINE_S:-75}
DISPLAY_NUM=${KANSEI_SMOKE_DISPLAY:-:97}
SCREEN=1280x800x24
OUT=${KANSEI_SMOKE_OUT:-target/app-smoke}

need() { command -v "$1" >/dev/null 2>&1; }
missing=0
need Xvfb || missing=1
need xwd || missing=1
ls /usr/lib/*/dri/swrast_dri.so >/dev/null 2>&1 || missing=1
if [ "$missing" = 1 ]; then
  if [ "$(id -u)" != 0 ]; then
    echo "app-smoke: Xvfb/Mesa missing and not root; skipping" >&2
    exit 0
  fi
  echo "== installing Xvfb and Mesa (apt-get)"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  # The libraries winit and glutin load at run time: X11 and its extensions, xkbcommon, EGL/GLX.
  apt-get install -y -qq --no-install-recommends xvfb x11-apps libgl1-mesa-dri libegl1 libgl1 \
    libx11-6 libxcursor1 libxrandr2 libxi6 libxkbcommon-x11-0 >/dev/null
fi

BIN=${1:-target/debug/kansei}
if [ ! -x "$BIN" ]; then
  cargo build --locked --bin kansei
fi
mkdir -p "$OUT"

Xvfb "$DISPLAY_NUM" -screen 0 "$SCREEN" -nolisten tcp >"$OUT/xvfb.log" 2>&1 &
XVFB_PID=$!
APP_PID=
cleanup() {
  [ -n "$APP_PID" ] && kill "$APP_PID" 2>/dev/null || true
  kill "$XVFB_PID" 2>/dev/null || true
}
trap cleanup EXIT
sleep 1

# No recovery file from a user's session, nor from an earlier run: a fresh temporary one.
rm -f "$OUT/recovery.json"
DISPLAY=$DISPLAY_NUM LIBGL_ALWAYS_SOFTWARE=1 WAYLAND_DISPLAY= \
  "$BIN" app "$FIXTURE" --recovery "$OUT/recovery.json" >"$OUT/app.log" 2>&1 &
APP_PID=$!
waited=0
while :; do
  sleep "$POLL_S"
  waited=$((waited + POLL_S))
  if ! kill -0 "$APP_PID" 2>/dev/null; then
    echo "app-smoke: the app exited early:" >&2
    cat "$OUT/app.log" >&2
    exit 1
  fi
  DISPLAY=$DISPLAY_NUM xwd -root -silent >"$OUT/screen.xwd"
  if python3 .ci/xwd_check.py "$OUT/screen.xwd" >"$OUT/check.log" 2>&1; then
    cat "$OUT/check.log"
    echo "app-smoke: ok after ${waited}s"
    exit 0
  fi
  if [ "$waited" -ge "$DEADLINE_S" ]; then
    cat "$OUT/check.log" >&2
    echo "app-smoke: no fitted curve on screen after ${waited}s (screenshot: $OUT/screen.xwd)" >&2
    exit 1
  fi
done
