#!/usr/bin/env bash
# Runs the libFuzzer targets of a PB_FUZZ build tree (tests/fuzz/fuzz.cmake).
#
#   tests/fuzz/run.sh BUILD SECONDS [TARGET...]   fuzz each target SECONDS s, one after another
#   tests/fuzz/run.sh --replay BUILD              run the seeds, regressions and findings once
#   tests/fuzz/run.sh --check                     exit 0 when clang-14 links a libFuzzer program
#
# TARGET is gltf, exr or image (default: all three). Every run first replays
# the seeds and the kept regression inputs (tests/fuzz/regressions/TARGET/) and
# earlier findings still in crashes/TARGET/ (so one fails every run until
# fixed), then fuzzes with the seeds (samples, broken-file corpus, feature
# files, Blender exports, textures, EXR variants) and the corpus grown by
# earlier runs, then merges that corpus (-merge=1: only inputs that add
# coverage stay), so it does not grow without bound. Everything lives under
# BUILD/fuzz/:
#   seeds/TARGET/    rewritten every run (make_seeds.py, make_image_seeds.py,
#                    fuzz_exr_seeds)
#   corpus/TARGET/   inputs libFuzzer found interesting, kept between runs
#   crashes/TARGET/  crash-*, leak-*, timeout-*, oom-* inputs: a finding
#   logs/TARGET.log  the last run's output
#   summary.tsv      one line per run: date, target, seconds, executions, exec/s, ...
# A finding makes the script exit 1 and print the file and the command that
# reproduces it (BUILD/fuzz_TARGET FILE). Environment: NICE (default 0: the
# nice level of the fuzzers), FUZZ_TIMEOUT (default 10: seconds per input
# before libFuzzer reports a timeout), FUZZ_ARGS (extra libFuzzer flags, e.g.
# -runs=N to stop after N executions).
set -u
HERE=$(cd "$(dirname "$0")" && pwd)

if [ "${1:-}" = "--check" ]; then
  command -v clang-14 >/dev/null 2>&1 || { echo "clang-14 not found"; exit 1; }
  t=$(mktemp -d) || exit 1
  printf '#include <stddef.h>\n#include <stdint.h>\nint LLVMFuzzerTestOneInput(const uint8_t *d, size_t n);\nint LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { (void)d; (void)n; return 0; }\n' >"$t/t.c"
  if clang-14 -fsanitize=fuzzer,address,undefined "$t/t.c" -o "$t/t" >"$t/log" 2>&1 && "$t/t" -runs=1 >>"$t/log" 2>&1; then
    rm -rf "$t"; exit 0
  fi
  echo "clang-14 cannot build or run a libFuzzer program:"; tail -3 "$t/log"; rm -rf "$t"; exit 1
fi

replay=0
if [ "${1:-}" = "--replay" ]; then replay=1; shift; fi
[ $# -ge 1 ] || { sed -n '2,28p' "$0"; exit 2; }
BUILD=$(cd "$1" && pwd) || exit 2
shift
SECONDS_EACH=0
if [ $replay = 0 ]; then
  [ $# -ge 1 ] || { echo "run.sh: SECONDS missing" >&2; exit 2; }
  SECONDS_EACH=$1
  shift
  case "$SECONDS_EACH" in ''|*[!0-9]*) echo "run.sh: SECONDS must be a whole number" >&2; exit 2 ;; esac
fi
TARGETS=${*:-gltf exr image}
NICE=${NICE:-0}
FUZZ_TIMEOUT=${FUZZ_TIMEOUT:-10}
W=$BUILD/fuzz
# The targets write their inputs under $TMPDIR, one folder per run of this
# script (a crash skips the targets' own clean-up).
export TMPDIR=$W/tmp/run.$$
mkdir -p "$W/logs" "$TMPDIR"
trap 'rm -rf "$TMPDIR"' EXIT
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:symbolize=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

ROOT=$(cd "$HERE/../.." && pwd)
# Debian's python3 carries Pillow (python3-pil) for the image seeds; another
# python3 on PATH may not.
IMAGE_PYTHON=python3
[ -x /usr/bin/python3 ] && IMAGE_PYTHON=/usr/bin/python3

seeds() {  # TARGET -> prints the seed folder
  local t=$1 d=$W/seeds/$1
  rm -rf "$d" && mkdir -p "$d"
  case $t in
    gltf) python3 "$HERE/make_seeds.py" "$d" >"$W/logs/seeds_gltf.log" 2>&1 ;;
    exr) "$BUILD/fuzz_exr_seeds" "$d" >"$W/logs/seeds_exr.log" 2>&1 ;;
    # Textures of every PNG/JPEG variant (Blender-written ones too where
    # Blender is installed), the samples' own, and the EXR seeds.
    image) "$IMAGE_PYTHON" "$HERE/make_image_seeds.py" "$d" --blender >"$W/logs/seeds_image.log" 2>&1 &&
           find "$ROOT/samples" "$ROOT/tests/corpus/valid/base" -name '*.png' -o -name '*.jpg' |
             while read -r f; do cp "$f" "$d/real_$(basename "$(dirname "$f")")_$(basename "$f")"; done &&
           "$BUILD/fuzz_exr_seeds" "$d" >>"$W/logs/seeds_image.log" 2>&1 ;;
  esac || { echo "run.sh: seed preparation for $t failed:" >&2; cat "$W/logs/seeds_$t.log" >&2; return 1; }
}

# Inputs longer than this are cut by libFuzzer: 64 KiB holds every seed
# (make_seeds.py leaves out larger ones) and keeps an execution to about a
# millisecond; the 256 KiB of earlier runs gave fuzz_gltf 330 executions/s.
MAX_LEN=65536

status=0
for t in $TARGETS; do
  bin=$BUILD/fuzz_$t
  [ -x "$bin" ] || { echo "run.sh: $bin not built" >&2; status=1; continue; }
  seeds "$t" || { status=1; continue; }
  reg=$HERE/regressions/$t
  mkdir -p "$W/corpus/$t" "$W/crashes/$t"
  log=$W/logs/$t.log
  dirs=("$W/seeds/$t")
  [ -d "$reg" ] && dirs+=("$reg")
  # 1. Replay: every seed, regression input and earlier finding once (a
  #    finding keeps failing the run until the code is fixed).
  found=()
  [ -n "$(ls -A "$W/crashes/$t")" ] && found=("$W/crashes/$t")
  if ! "$bin" -runs=0 -timeout="$FUZZ_TIMEOUT" -rss_limit_mb=2048 -artifact_prefix="$W/crashes/$t/" \
       "${dirs[@]}" "${found[@]}" >"$log.replay" 2>&1; then
    echo "fuzz_$t: FAILED replaying the seeds, regressions and earlier findings (log: $log.replay):"
    grep -E "^(==|SUMMARY|fuzz_$t: contract)|runtime error|artifact_prefix" "$log.replay" | head -20
    status=1
    continue
  fi
  n=$(find "${dirs[@]}" "${found[@]}" -type f | wc -l)
  echo "fuzz_$t: replayed $n seed, regression and earlier finding inputs"
  [ $replay = 1 ] && continue
  # 2. Fuzz for SECONDS_EACH seconds; new inputs go to corpus/TARGET.
  before=$(find "$W/crashes/$t" -type f | wc -l)
  dict=()
  if [ "$t" = image ]; then  # PNG, JPEG and the EXR inputs
    cat "$HERE/image.dict" "$HERE/exr.dict" >"$W/image.dict" && dict=(-dict="$W/image.dict")
  elif [ -f "$HERE/$t.dict" ]; then
    dict=(-dict="$HERE/$t.dict")
  fi
  start=$(date +%s)
  # shellcheck disable=SC2086
  nice -n "$NICE" "$bin" -max_total_time="$SECONDS_EACH" -timeout="$FUZZ_TIMEOUT" -rss_limit_mb=2048 \
    -max_len=$MAX_LEN -print_final_stats=1 -artifact_prefix="$W/crashes/$t/" "${dict[@]}" \
    ${FUZZ_ARGS:-} "$W/corpus/$t" "${dirs[@]}" >"$log" 2>&1
  rc=$?
  wall=$(( $(date +%s) - start ))
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  last=$(grep -E '^#[0-9]+' "$log" | tail -1)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  grown=$(find "$W/corpus/$t" -type f | wc -l)
  after=$(find "$W/crashes/$t" -type f | wc -l)
  result=ok
  if [ $rc -ne 0 ] || [ "$after" -gt "$before" ]; then result=FINDING; status=1; fi
  # 3. Merge: keep only the corpus inputs that add coverage (a finding stops
  #    here, so its run's corpus stays as it was for the reproduction).
  if [ $result = ok ] && [ "$grown" -gt 0 ]; then
    rm -rf "$W/corpus/$t.merged" && mkdir -p "$W/corpus/$t.merged"
    if nice -n "$NICE" "$bin" -merge=1 -timeout="$FUZZ_TIMEOUT" -rss_limit_mb=2048 -max_len=$MAX_LEN \
         "$W/corpus/$t.merged" "$W/corpus/$t" >"$log.merge" 2>&1; then
      rm -rf "$W/corpus/$t" && mv "$W/corpus/$t.merged" "$W/corpus/$t"
    else
      echo "fuzz_$t: corpus merge failed (log: $log.merge); corpus kept as it was"
      rm -rf "$W/corpus/$t.merged"
    fi
  fi
  corp=$(find "$W/corpus/$t" -type f | wc -l)
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$(date -u +%Y-%m-%dT%H:%MZ)" "fuzz_$t" "$wall" \
    "${execs:-?}" "${rate:-?}" "${cov:-?}" "${ft:-?}" "$corp" "$result" >>"$W/summary.tsv"
  echo "fuzz_$t: ${wall}s, ${execs:-?} executions (${rate:-?}/s), cov ${cov:-?}, ft ${ft:-?}, corpus $corp (merged from $grown): $result"
  if [ $result != ok ]; then
    grep -E "^(==[0-9]+==|SUMMARY|fuzz_$t: contract)|runtime error|Test unit written" "$log" | head -20
    newest=$(ls -t "$W/crashes/$t" 2>/dev/null | head -1)
    [ -n "$newest" ] && echo "fuzz_$t: input kept in $W/crashes/$t/$newest; reproduce: $bin $W/crashes/$t/$newest"
    echo "fuzz_$t: full log: $log"
  fi
done
exit $status
