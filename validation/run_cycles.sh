#!/bin/sh
# Cycles reference for a sample, headless; keeps Blender's log.
#
#   validation/run_cycles.sh NAME OUT.exr [run_cycles.py options: --width W --samples N --threads N]
#
# Writes OUT.exr, OUT.exr.json (render time, samples, Blender version) and
# OUT.exr.log (Blender's output plus "wall_s=SECONDS"). Exit 77 when Blender is
# not installed (the ctest skip code).
set -u
if [ $# -lt 2 ]; then
  echo "usage: $0 NAME OUT.exr [--width W] [--samples N] [--threads N]" >&2
  exit 2
fi
name=$1 out=$2
shift 2
BLENDER=${BLENDER:-blender}
if ! command -v "$BLENDER" >/dev/null 2>&1; then
  echo "run_cycles: $BLENDER not installed" >&2
  exit 77
fi
here=$(cd "$(dirname "$0")" && pwd)
log=$out.log
start=$(date +%s.%N)
"$BLENDER" -b --factory-startup --python-exit-code 1 -P "$here/run_cycles.py" -- \
  --scene "$name" --out "$out" "$@" >"$log.tmp" 2>&1
rc=$?
end=$(date +%s.%N)
echo "wall_s=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }')" >>"$log.tmp"
mv -f "$log.tmp" "$log"
if [ $rc -ne 0 ] || [ ! -s "$out" ]; then
  echo "run_cycles: Blender failed (exit $rc); last lines of $log:" >&2
  tail -n 15 "$log" >&2
  [ $rc -ne 0 ] || rc=1
  exit $rc
fi
grep '^run_cycles:' "$log"
