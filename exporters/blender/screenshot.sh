#!/usr/bin/env bash
# A screenshot of Blender's window (the README's and docs/blender.md's): the photonbridge panel
# and a finished F12 render of a sample in the image editor, under Xvfb.
#   exporters/blender/screenshot.sh [SAMPLE] [OUT.png]
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
SAMPLE=${1:-spot_room}
OUT=$(readlink -f "${2:-$ROOT/exporters/blender/screenshot.png}")
command -v Xvfb >/dev/null || { echo "screenshot: needs Xvfb (apt-get install xvfb)" >&2; exit 1; }
PATH=$(echo "$PATH" | tr : '\n' | grep -v pyenv | paste -sd:)
export PATH
SCRIPTS=$(mktemp -d)
mkdir -p "$SCRIPTS/addons"
ln -s "$ROOT/exporters/blender/photonbridge" "$SCRIPTS/addons/photonbridge"
Xvfb :77 -screen 0 1600x900x24 -nolisten tcp >/dev/null 2>&1 &
XPID=$!
trap 'kill $XPID 2>/dev/null; rm -rf "$SCRIPTS"' EXIT
sleep 2
DISPLAY=:77 BLENDER_USER_SCRIPTS=$SCRIPTS PHOTONBRIDGE_BIN=${PHOTONBRIDGE_BIN:-$ROOT/build/photonbridge} \
  timeout 600 blender --factory-startup "$ROOT/samples/$SAMPLE/$SAMPLE.blend" \
  --python "$ROOT/exporters/blender/screenshot.py" -- "$OUT"
[ -s "$OUT" ] && echo "screenshot: $OUT"
