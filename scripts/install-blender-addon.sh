#!/usr/bin/env bash
# Installs the photonbridge Blender add-on for this user: links
# exporters/blender/photonbridge into Blender's user add-on folder, enables
# it, points its preferences at this checkout's binary and saves Blender's
# user preferences. Run by `make blender-addon` (after the build).
#   [BLENDER=/path/to/blender] scripts/install-blender-addon.sh [PHOTONBRIDGE_BINARY]
# BLENDER names the Blender to install into (default: the `blender` on PATH).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=$(readlink -f "${1:-$ROOT/build/photonbridge}")
BLENDER=${BLENDER:-blender}
command -v "$BLENDER" >/dev/null || { echo "install-blender-addon: $BLENDER not found (set BLENDER=/path/to/blender, or apt-get install blender)" >&2; exit 1; }
[ -x "$BIN" ] || { echo "install-blender-addon: $BIN is not an executable; run 'make build' first" >&2; exit 1; }
# Blender's bundled Python picks up the first python3 on PATH: keep pyenv's out.
PATH=$(echo "$PATH" | tr : '\n' | grep -v pyenv | paste -sd:)
export PATH
ADDONS=$("$BLENDER" -b --factory-startup --python-expr \
  "import bpy; print('ADDONS=' + bpy.utils.user_resource('SCRIPTS', path='addons', create=True))" 2>/dev/null |
  sed -n 's/^ADDONS=//p')
[ -n "$ADDONS" ] || { echo "install-blender-addon: could not ask Blender for its add-on folder" >&2; exit 1; }
mkdir -p "$ADDONS"
ln -sfn "$ROOT/exporters/blender/photonbridge" "$ADDONS/photonbridge"
"$BLENDER" -b --python-expr "
import addon_utils, bpy
addon_utils.enable('photonbridge', default_set=True, handle_error=None)
bpy.context.preferences.addons['photonbridge'].preferences.binary = '$BIN'
bpy.ops.wm.save_userpref()
print('install-blender-addon: enabled; binary $BIN')" 2>&1 | grep '^install-blender-addon' || {
  echo "install-blender-addon: Blender could not enable the add-on" >&2; exit 1; }
echo "install-blender-addon: $ADDONS/photonbridge -> $ROOT/exporters/blender/photonbridge"
