#!/bin/sh
# Renders a photonbridge-exported POV-Ray scene headless to a linear EXR,
# keeping POV-Ray's log and the wall time.
#
#   validation/run_povray.sh SCENE.pov OUT.exr [W H] [-- EXTRA POVRAY OPTIONS]
#
# W and H default to the size export-pov wrote into the file's header (the
# camera's aspect is fixed by it). Default options: +FE (OpenEXR, half float,
# linear with assumed_gamma 1.0) -D (no display) +A0.0 (antialiasing on every
# pixel); EXTRA options come last and override them (e.g. -A +WT1 for an
# unantialiased single-threaded test render).
#
# Debian's povray.conf restricts file I/O to the current directory, /tmp and
# $HOME, so POV-Ray runs inside the scene's directory (where export-pov puts
# the textures) and writes there under a temporary name, which is then moved
# to OUT. $HOME is pointed at a fresh directory with an empty user config, so
# that a read-only or missing home does not matter and no personal povray.ini
# changes the result.
#
# Writes OUT, OUT.log (POV-Ray's output plus a last line "wall_s=SECONDS") and
# prints "povray: OUT WxH in SECONDS s". Exit status: POV-Ray's (77 when
# povray is not installed, the ctest skip code).
set -u
if [ $# -lt 2 ]; then
  echo "usage: $0 SCENE.pov OUT.exr [W H] [-- EXTRA POVRAY OPTIONS]" >&2
  exit 2
fi
pov=$1 out=$2
shift 2
w= h=
if [ $# -ge 2 ] && [ "$1" != "--" ]; then
  w=$1 h=$2
  shift 2
fi
[ $# -ge 1 ] && [ "$1" = "--" ] && shift
POVRAY=${POVRAY:-povray}
if ! command -v "$POVRAY" >/dev/null 2>&1; then
  echo "run_povray: $POVRAY not installed" >&2
  exit 77
fi
if [ ! -r "$pov" ]; then
  echo "run_povray: $pov: cannot read" >&2
  exit 3
fi
if [ -z "$w" ]; then
  w=$(sed -n 's/^\/\/ Render with the same size: .* +W\([0-9]*\) +H\([0-9]*\).*/\1/p' "$pov" | head -n 1)
  h=$(sed -n 's/^\/\/ Render with the same size: .* +W\([0-9]*\) +H\([0-9]*\).*/\2/p' "$pov" | head -n 1)
fi
if [ -z "$w" ] || [ -z "$h" ]; then
  echo "run_povray: $pov: no size given and none in the file's header" >&2
  exit 2
fi

case $out in /*) abs_out=$out ;; *) abs_out=$(pwd)/$out ;; esac
dir=$(dirname "$pov")
base=$(basename "$pov")
tmp_name=.pb_povray_$$.exr
log=$abs_out.log
home=$(mktemp -d "${TMPDIR:-/tmp}/pb_povray_home.XXXXXX") || exit 3
mkdir -p "$home/.povray/3.7" && : >"$home/.povray/3.7/povray.conf" && : >"$home/.povray/3.7/povray.ini"
cleanup() { rm -rf "$home"; rm -f "$dir/$tmp_name"; }
trap cleanup EXIT
trap 'exit 130' INT TERM

start=$(date +%s.%N)
(cd "$dir" && HOME=$home "$POVRAY" +I"$base" +O"$tmp_name" +FE +W"$w" +H"$h" -D +A0.0 -P -V "$@") >"$log.tmp" 2>&1
rc=$?
end=$(date +%s.%N)
wall=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }')
echo "wall_s=$wall" >>"$log.tmp"
mv -f "$log.tmp" "$log"
if [ $rc -ne 0 ] || [ ! -s "$dir/$tmp_name" ]; then
  echo "run_povray: povray failed (exit $rc) on $pov; last lines of $log:" >&2
  tail -n 15 "$log" >&2
  [ $rc -ne 0 ] || rc=1
  exit $rc
fi
mv -f "$dir/$tmp_name" "$abs_out" || exit 3
echo "povray: $out ${w}x${h} in $wall s"
