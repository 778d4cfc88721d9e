#!/usr/bin/env bash
# Fault injection for the command line: each case runs
# photonbridge under one fault and asserts the exact exit code from the result
# table, a one-line error naming the path/device/buffer, and that the output
# folder holds exactly what it held before (no output, no PATH.tmp.PID).
#
#   tests/faults.sh CASE PHOTONBRIDGE
#
# Cases (tests/faults.cmake registers each as faults_CASE):
#   no_device        Vulkan loader pointed at a missing driver: render and
#                    info --devices exit 12 with what to install; validate
#                    still writes its report with the GPU render marked failed
#   no_feature       PB_GPU_MASK_FEATURES hides a required feature: exit 12
#                    naming device and feature; an optional one (timestamps)
#                    only turns the pass times into null; unknown name: exit 2
#   memory_cap       --gpu-memory-limit / PB_GPU_MEMORY_LIMIT below what the
#                    render needs: exit 11 naming buffer, size and cap
#   unwritable_cpu   output folder that cannot be written (a path under a
#                    regular file, and chmod 0555 when not root) for
#                    reference, display, compare --json, export-pov, info --json
#   unwritable_gpu   the same for render, and a --json failure after the EXR
#                    was written removes the EXR
#   disk_full_cpu    writes failing with EFBIG (ulimit -f, SIGXFSZ ignored)
#                    for an EXR (reference), a PNG (display), JSON (info,
#                    compare), POV (export-pov), and stdout on /dev/full
#   disk_full_gpu    the same for render's EXR
#   interrupt_cpu    SIGINT/SIGTERM during reference and validate (after its progress
#                    appears), and SIGINT while a finished temporary waits for
#                    its rename (PB_TEST_HOLD_OUTPUT=1, see src/core/fs.h) for
#                    an EXR, a PNG and a JSON: exit 130/143, temporary removed
#   interrupt_gpu    SIGINT/SIGTERM during render
# GPU cases exit 77 (skipped) when `info --devices` finds no usable device.
set -u
case_name=$1
exe=$2
root=$(cd "$(dirname "$0")/.." && pwd)
scene=$root/samples/cornell_box/cornell_box.gltf
pass=0
fail=0
work=$(mktemp -d)
trap 'chmod -R u+w "$work" 2>/dev/null; rm -rf "$work"' EXIT

ok() { pass=$((pass + 1)); echo "ok: $*"; }
bad() { fail=$((fail + 1)); echo "FAIL: $*"; }

# run NAME EXPECTED_EXIT REGEX DIR -- command...: runs the command with
# stderr captured, checks the exit code, that stderr is exactly one line
# matching REGEX, and that DIR lists the same names before and after.
run() {
  local name=$1 want=$2 regex=$3 dir=$4
  shift 5
  local before after rc err lines
  before=$(ls -A "$dir" 2>/dev/null)
  "$@" >"$work/stdout" 2>"$work/stderr"
  rc=$?
  after=$(ls -A "$dir" 2>/dev/null)
  err=$(cat "$work/stderr")
  lines=$(grep -c '' "$work/stderr")
  if [ "$rc" -ne "$want" ]; then
    bad "$name: exit $rc, expected $want; stderr: $err"
  elif [ "$lines" -ne 1 ]; then
    bad "$name: $lines stderr lines, expected one: $err"
  elif ! grep -Eq -- "$regex" "$work/stderr"; then
    bad "$name: stderr does not match /$regex/: $err"
  elif [ "$before" != "$after" ]; then
    bad "$name: $dir changed: before [$before] after [$after]"
  else
    ok "$name (exit $rc): $err"
  fi
}

need_device() {
  if ! "$exe" info --devices >/dev/null 2>&1; then
    echo "skip: no usable Vulkan device"
    exit 77
  fi
}

# A small EXR for display/compare.
make_exr() {
  "$exe" reference "$scene" -o "$work/in.exr" --width 16 --spp 1 --threads 1 -q || {
    echo "setup: reference failed"
    exit 1
  }
}

R="render $scene --width 16 --spp 1 --photons 4096 -q"

case $case_name in
no_device)
  d=$work/out && mkdir -p "$d"
  # Without validation layers: with PB_VK_VALIDATION=1 (set for every test)
  # the loader's own complaints about the missing driver are printed too.
  nodrv=(env -u PB_VK_VALIDATION VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json)
  run render 12 "error: .*(no Vulkan driver|no Vulkan device).*apt install mesa-vulkan-drivers" "$d" -- \
    "${nodrv[@]}" "$exe" $R -o "$d/x.exr" --png "$d/x.png" --json "$d/x.json"
  run info_devices 12 "info: error: .*apt install mesa-vulkan-drivers" "$d" -- \
    "${nodrv[@]}" "$exe" info --devices
  # validate degrades: the reference and the report still come out, the GPU
  # render is listed as failed with exit 12 (POV-Ray and Cycles left out, so
  # validate exits 1: fewer than two renderers produced an image).
  "${nodrv[@]}" "$exe" validate cornell_box --out "$d/v" --width 16 --spp 1 --ref-spp 1 --threads 1 \
    --no-povray --no-cycles >"$work/vlog" 2>&1
  rc=$?
  # Exit 1: only the reference produced an image (validate.py's rule).
  if [ $rc -eq 1 ] && python3 - "$d/v/report.json" <<'EOF'
import json, sys
r = {x["name"]: x for x in json.load(open(sys.argv[1]))["renders"]}
assert r["reference"]["status"] == "ok", r
g = r["photonbridge"]
assert g["status"] == "failed" and g["reason"].startswith("exit 12:"), g
assert not any(f.startswith("photonbridge.exr") for f in __import__("os").listdir(sys.argv[1].rsplit("/", 1)[0]))
EOF
  then ok "validate without a device: report written, GPU render failed with exit 12"
  else bad "validate without a device: exit $rc; $(tail -5 "$work/vlog")"; fi
  ;;
no_feature)
  need_device
  d=$work/out && mkdir -p "$d"
  for f in storage-buffers vulkan-1.1 compute workgroup-64; do
    run "mask_$f" 12 "render: error: no usable Vulkan device: .+ lacks $f \\(masked by PB_GPU_MASK_FEATURES\\)" "$d" -- \
      env PB_GPU_MASK_FEATURES=$f "$exe" $R -o "$d/x.exr"
  done
  run mask_device0 12 "render: error: --device 0 \\(.+\\) lacks storage-buffers \\(masked" "$d" -- \
    env PB_GPU_MASK_FEATURES=storage-buffers "$exe" $R --device 0 -o "$d/x.exr"
  run mask_unknown 2 "PB_GPU_MASK_FEATURES: unknown feature 'raytracing'" "$d" -- \
    env PB_GPU_MASK_FEATURES=raytracing "$exe" $R -o "$d/x.exr"
  # info --devices lists the device as unusable and says why.
  if PB_GPU_MASK_FEATURES=compute "$exe" info --devices --json - | python3 -c '
import json, sys
d = json.load(sys.stdin)["devices"]
assert d and all(not x["usable"] and "compute" in x["missing"] and not x["default"] for x in d), d'
  then ok "info --devices: masked device unusable, missing names compute"
  else bad "info --devices with compute masked"; fi
  # Timestamps are optional: the render succeeds, its pass times are null.
  if PB_GPU_MASK_FEATURES=timestamps "$exe" $R -o "$d/t.exr" --json - 2>"$work/stderr" | python3 -c '
import json, sys
j = json.load(sys.stdin)
assert j["timestamps"] is False and j["passes_ms"]["gbuffer"] is None, j' && [ -s "$d/t.exr" ]
  then ok "timestamps masked: render succeeds, pass times null"
  else bad "timestamps masked: $(cat "$work/stderr")"; fi
  ;;
memory_cap)
  need_device
  d=$work/out && mkdir -p "$d"
  run cap_option 11 "render: error: [a-z_.]+: GPU buffer of [0-9.]+ MiB would bring GPU memory in use to [0-9.]+ MiB, over the cap of 1.0 MiB" "$d" -- \
    "$exe" $R -o "$d/x.exr" --png "$d/x.png" --json "$d/x.json" --gpu-memory-limit 1
  run cap_env 11 "over the cap of 0.5 MiB \\(--gpu-memory-limit / PB_GPU_MEMORY_LIMIT\\)" "$d" -- \
    env PB_GPU_MEMORY_LIMIT=0.5 "$exe" $R -o "$d/x.exr"
  run cap_env_bad 2 "PB_GPU_MEMORY_LIMIT: 'lots' is not a positive number of MiB" "$d" -- \
    env PB_GPU_MEMORY_LIMIT=lots "$exe" $R -o "$d/x.exr"
  # A cap above the need changes nothing; the option overrides the variable.
  if PB_GPU_MEMORY_LIMIT=0.5 "$exe" $R -o "$d/ok.exr" --gpu-memory-limit 4096 2>"$work/stderr" && [ -s "$d/ok.exr" ]
  then ok "cap of 4096 MiB (option over PB_GPU_MEMORY_LIMIT=0.5): render succeeds"
  else bad "cap of 4096 MiB: $(cat "$work/stderr")"; fi
  ;;
unwritable_cpu | unwritable_gpu)
  [ $case_name = unwritable_gpu ] && need_device
  [ $case_name = unwritable_cpu ] && make_exr
  d=$work/out && mkdir -p "$d"
  echo "a regular file" >"$d/file.txt"
  # A path under a regular file cannot be created, even by root.
  dirs=("$d/file.txt")
  # Permission bits stop writes only when not root.
  if [ "$(id -u)" -ne 0 ]; then
    mkdir -p "$d/ro" && chmod 0555 "$d/ro" && dirs+=("$d/ro")
  else
    echo "note: running as root: chmod 0555 does not stop writes, only the file-as-folder path is tested"
  fi
  for u in "${dirs[@]}"; do
    k=$(basename "$u")
    if [ $case_name = unwritable_cpu ]; then
      run "reference_$k" 3 "reference: error: $u/x.exr: cannot" "$d" -- \
        "$exe" reference "$scene" --width 16 --spp 1 --threads 1 -q -o "$u/x.exr"
      run "display_$k" 3 "display: error: $u/x.png: cannot write" "$d" -- "$exe" display "$work/in.exr" -o "$u/x.png"
      run "compare_json_$k" 3 "compare: error: $u/c.json: cannot write" "$d" -- \
        "$exe" compare "$work/in.exr" "$work/in.exr" --json "$u/c.json" -q
      run "export_pov_$k" 3 "export-pov: error: $u/s.pov: cannot write" "$d" -- "$exe" export-pov "$scene" -o "$u/s.pov" -q
      run "info_json_$k" 3 "info: error: $u/i.json: cannot write" "$d" -- "$exe" info "$scene" --json "$u/i.json" -q
      run "validate_$k" 3 "validate: error: $u/v: cannot create the output folder" "$d" -- \
        "$exe" validate cornell_box --out "$u/v" --width 16
    else
      run "render_$k" 3 "render: error: $u/x.exr: cannot" "$d" -- "$exe" $R -o "$u/x.exr"
      # The EXR is written, then the PNG/JSON fails: the EXR is removed again.
      run "render_png_$k" 3 "render: error: $u/x.png: cannot write" "$d" -- "$exe" $R -o "$d/x.exr" --png "$u/x.png"
      run "render_json_$k" 3 "render: error: $u/x.json: cannot write" "$d" -- "$exe" $R -o "$d/x.exr" --json "$u/x.json"
    fi
  done
  ;;
disk_full_cpu | disk_full_gpu)
  [ $case_name = disk_full_gpu ] && need_device
  [ $case_name = disk_full_cpu ] && make_exr
  d=$work/out && mkdir -p "$d"
  # full KB CMD...: the command with files limited to KB KiB (writes past it
  # fail with EFBIG, as on a full disk; SIGXFSZ is ignored so write() returns).
  # The limit applies to every file the process writes, so its stderr goes
  # through a pipe to a cat outside the limit, and its stdout to /dev/null.
  full() {
    local kb=$1 rc
    shift
    set -o pipefail
    (ulimit -f "$kb" && trap '' XFSZ && exec "$@" 2>&1 >/dev/null) | cat >&2
    rc=$?
    set +o pipefail
    return $rc
  }
  if [ $case_name = disk_full_cpu ]; then
    # 8 KiB: the EXR header fits, its pixels do not.
    run reference_exr 3 "reference: error: $d/x.exr: .*(File too large|write)" "$d" -- \
      full 8 "$exe" reference "$scene" --width 64 --spp 1 --threads 1 -q -o "$d/x.exr"
    run display_png 3 "display: error: $d/x.png: write failed: File too large" "$d" -- \
      full 0 "$exe" display "$work/in.exr" -o "$d/x.png"
    run info_json 3 "info: error: $d/i.json: write failed: File too large" "$d" -- \
      full 0 "$exe" info "$scene" --json "$d/i.json" -q
    run compare_json 3 "compare: error: $d/c.json: write failed: File too large" "$d" -- \
      full 0 "$exe" compare "$work/in.exr" "$work/in.exr" --json "$d/c.json" -q
    run export_pov 3 "export-pov: error: $d/s.pov: write failed: File too large" "$d" -- \
      full 0 "$exe" export-pov "$scene" -o "$d/s.pov" -q
    # stdout on a full device (/dev/full: ENOSPC).
    run info_stdout 3 "info: error: standard output: write failed: No space left on device" "$d" -- \
      sh -c '"$0" info "$1" >/dev/full' "$exe" "$scene"
    run info_json_stdout 3 "info: error: standard output: write failed" "$d" -- \
      sh -c '"$0" info "$1" --json - -q >/dev/full' "$exe" "$scene"
  else
    run render_exr 3 "render: error: $d/x.exr: .*File too large" "$d" -- \
      full 2 "$exe" $R -o "$d/x.exr"
    # (A PNG or JSON failing after the EXR was written is covered by
    # unwritable_gpu; a file-size cap cannot fail them alone, the EXR being
    # the largest. Their writers' full-disk path is covered by disk_full_cpu.)
  fi
  ;;
interrupt_cpu | interrupt_gpu)
  [ $case_name = interrupt_gpu ] && need_device
  [ $case_name = interrupt_cpu ] && make_exr
  d=$work/out && mkdir -p "$d"
  # interrupt NAME SIGNAL EXIT MARKER CMD...: starts CMD in the background,
  # waits (up to 60 s) for MARKER in its stderr, sends SIGNAL, and checks the
  # exit code and that the folder is as before.
  interrupt() {
    local name=$1 sig=$2 want=$3 marker=$4
    shift 4
    local before after rc pid i
    before=$(ls -A "$d")
    : >"$work/ierr"
    "$@" 2>"$work/ierr" >/dev/null &
    pid=$!
    for i in $(seq 600); do
      grep -q -- "$marker" "$work/ierr" && break
      kill -0 $pid 2>/dev/null || break
      sleep 0.1
    done
    if ! grep -q -- "$marker" "$work/ierr"; then
      kill -KILL $pid 2>/dev/null
      wait $pid 2>/dev/null
      bad "$name: '$marker' never appeared: $(cat "$work/ierr")"
      return
    fi
    local held=
    held=$(sed -n 's/^photonbridge: test hook: holding //p' "$work/ierr")
    if [ -n "$held" ] && [ ! -e "$held" ]; then
      bad "$name: the temporary $held is not there while held"
    fi
    sleep 0.3
    kill -"$sig" $pid
    wait $pid
    rc=$?
    after=$(ls -A "$d")
    if [ $rc -ne "$want" ]; then
      bad "$name: exit $rc, expected $want: $(cat "$work/ierr")"
    elif [ "$before" != "$after" ]; then
      bad "$name: folder changed: before [$before] after [$after]"
    elif ! tail -1 "$work/ierr" | grep -Eq "^photonbridge [a-z-]+: interrupted by SIG$sig; no output written\$"; then
      bad "$name: last stderr line is not 'photonbridge CMD: interrupted by SIG$sig; no output written': $(tail -2 "$work/ierr")"
    elif [ "$(grep -c '^$' "$work/ierr")" -ne 0 ]; then
      bad "$name: empty lines on stderr (not a terminal)"
    else
      ok "$name: exit $rc, nothing left${held:+ (temporary $held removed)}"
    fi
  }
  if [ $case_name = interrupt_cpu ]; then
    REF=("$exe" reference "$scene" --width 256 --spp 100000 --threads 1)
    interrupt reference_sigint INT 130 "reference: " "${REF[@]}" -o "$d/x.exr" --png "$d/x.png" --json "$d/x.json"
    interrupt reference_sigterm TERM 143 "reference: " "${REF[@]}" -o "$d/x.exr"
    # A finished temporary waiting for its rename is removed by the handler.
    interrupt hold_exr INT 130 "test hook: holding" env PB_TEST_HOLD_OUTPUT=1 \
      "$exe" reference "$scene" --width 16 --spp 1 --threads 1 -q -o "$d/x.exr"
    interrupt hold_png INT 130 "test hook: holding" env PB_TEST_HOLD_OUTPUT=1 \
      "$exe" display "$work/in.exr" -o "$d/x.png"
    interrupt hold_json INT 130 "test hook: holding" env PB_TEST_HOLD_OUTPUT=1 \
      "$exe" info "$scene" --json "$d/i.json" -q
    # validate passes the signal on to its script and the renderers it runs;
    # the report folder it created goes too.
    VAL=("$exe" validate "$scene" --width 64 --ref-spp 100000 --threads 1 --no-gpu --no-povray --no-cycles)
    interrupt validate_sigint INT 130 "validate: reference" "${VAL[@]}" --out "$d/v"
    interrupt validate_sigterm TERM 143 "validate: reference" "${VAL[@]}" --out "$d/v"
  else
    interrupt render_sigint INT 130 "render: .* on " \
      "$exe" render "$scene" --width 256 --spp 4096 -v -o "$d/x.exr" --png "$d/x.png" --json "$d/x.json"
    interrupt render_sigterm TERM 143 "render: .* on " "$exe" render "$scene" --width 256 --spp 4096 -v -o "$d/x.exr"
    interrupt render_hold_exr INT 130 "test hook: holding" env PB_TEST_HOLD_OUTPUT=1 "$exe" $R -o "$d/x.exr"
  fi
  ;;
*)
  echo "unknown case $case_name"
  exit 2
  ;;
esac
echo "$pass passed, $fail failed"
[ $fail -eq 0 ] && [ $pass -gt 0 ]
