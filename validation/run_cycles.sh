#!/bin/sh
# Cycles render of a sample or of any glTF / GLB, headless; keeps Blender's log.
#
#   validation/run_cycles.sh NAME OUT.exr [run_cycles.py options]
#   validation/run_cycles.sh FILE.gltf|FILE.glb OUT.exr --info INFO.json [run_cycles.py options]
#   validation/run_cycles.sh FILE.blend OUT.exr [run_cycles.py options]
#
# NAME is a sample of exporters/blender/make_samples.py (the scene is built by
# that script); a .gltf / .glb goes through Blender's glTF importer with its
# materials rebuilt as glTF's model (validation/cycles_gltf.py), and needs
# `photonbridge info FILE --json INFO.json` for photonbridge's camera and units.
# Options: --width W --height H --samples N --threads N --seed N --bounces N
# --materials M --halves (validation/run_cycles.py).
#
# Writes OUT.exr, OUT.exr.json (render time, samples, Blender version, source,
# material model, notes; "error" when the importer cannot read the file) and
# OUT.exr.log (Blender's output plus "wall_s=SECONDS"). Exit 77 when Blender is
# not installed (the ctest skip code).
set -u
if [ $# -lt 2 ]; then
  echo "usage: $0 NAME|FILE.gltf|FILE.glb OUT.exr [--info INFO.json] [--width W] [--samples N] [--threads N]" >&2
  exit 2
fi
scene=$1 out=$2
shift 2
case $scene in
  *.gltf|*.glb|*.GLTF|*.GLB) source=--gltf ;;
  *.blend|*.BLEND) source=--blend ;;
  *) source=--scene ;;
esac
BLENDER=${BLENDER:-blender}
if ! command -v "$BLENDER" >/dev/null 2>&1; then
  echo "run_cycles: $BLENDER not installed" >&2
  exit 77
fi
# Blender's Python finds its standard library through the first python3 on
# PATH; a pyenv interpreter there breaks it (and lacks Debian's numpy).
PATH=$(printf '%s' "$PATH" | tr ':' '\n' | grep -v pyenv | paste -sd: -)
export PATH
here=$(cd "$(dirname "$0")" && pwd)
log=$out.log
start=$(date +%s.%N)
"$BLENDER" -b --factory-startup --python-exit-code 1 -P "$here/run_cycles.py" -- \
  "$source" "$scene" --out "$out" "$@" >"$log.tmp" 2>&1
rc=$?
end=$(date +%s.%N)
echo "wall_s=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }')" >>"$log.tmp"
mv -f "$log.tmp" "$log"
if [ $rc -ne 0 ] || [ ! -s "$out" ]; then
  # The one-line reason when the script gave one, else Blender's last lines.
  if grep -q '^run_cycles: error: ' "$log"; then
    grep '^run_cycles: error: ' "$log" | tail -n 1 >&2
  else
    echo "run_cycles: Blender failed (exit $rc); last lines of $log:" >&2
    tail -n 15 "$log" >&2
  fi
  [ $rc -ne 0 ] || rc=1
  exit $rc
fi
grep '^run_cycles:' "$log"
