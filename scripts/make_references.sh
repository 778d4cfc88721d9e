#!/usr/bin/env bash
# Converged CPU references for every sample: samples/NAME/NAME.gltf ->
# OUT/NAME.exr (+ NAME.png preview, NAME.json statistics with the
# reference's own noise estimate), rendered by `photonbridge reference
# --estimate-noise`. A reference is reused (not rendered again) when its EXR
# and JSON exist, are newer than the scene's files and the binary, and were
# made with the same options (OUT/NAME.args). References are not committed;
# the benchmark regenerates and caches them with this script.
#
#   scripts/make_references.sh [options] [NAME...]
#     --exe PATH        photonbridge binary (default: build/photonbridge)
#     --out DIR         output folder (default: out/ref)
#     --spp N           samples per pixel (default 1024)
#     --time-limit S    per scene; stops after the pass that ends past S
#     --width W         image width (default: 640; height from the camera)
#     --force           render even when a cached reference matches
#     any other option (-q, --seed N, ...) is passed to `photonbridge reference`
# Prints one line per scene and writes OUT/summary.tsv (scene, mode, spp,
# seconds, rays per second per core, noise RMSE, relMSE, PSNR).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
exe="$root/build/photonbridge"
out="$root/out/ref"
spp=1024
width=640
time_limit=""
force=0
extra=()
names=()
while [ $# -gt 0 ]; do
  case "$1" in
    --exe) exe="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --spp) spp="$2"; shift 2 ;;
    --time-limit) time_limit="$2"; shift 2 ;;
    --width) width="$2"; shift 2 ;;
    --force) force=1; shift ;;
    -h|--help) sed -n '2,20p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) extra+=("$1"); if [ $# -gt 1 ] && [ "${2#--}" = "$2" ]; then extra+=("$2"); shift; fi; shift ;;
    *) names+=("$1"); shift ;;
  esac
done
if [ ! -x "$exe" ]; then
  echo "make_references: no photonbridge at $exe (build first, or pass --exe)" >&2
  exit 1
fi
mkdir -p "$out"
if [ ${#names[@]} -eq 0 ]; then
  for d in "$root"/samples/*/; do
    n="$(basename "$d")"
    [ -f "$d/$n.gltf" ] && names+=("$n")
  done
fi

# A JSON number by key from our own --json output (one key per line).
json_num() { sed -n "s/^ *\"$2\": \([-0-9.eE+]*\),\{0,1\}$/\1/p" "$1" | head -n 1; }

summary="$out/summary.tsv"
printf 'scene\tmode\tspp\ttime_s\trays_per_s_per_core\trays_per_cpu_s\tnoise_rmse\tnoise_relmse\tnoise_psnr_db\n' > "$summary.tmp"
status=0
for n in "${names[@]}"; do
  scene="$root/samples/$n/$n.gltf"
  if [ ! -f "$scene" ]; then
    echo "make_references: $n: no $scene" >&2
    status=1
    continue
  fi
  args=(reference "$scene" -o "$out/$n.exr" --png "$out/$n.png" --json "$out/$n.json"
        --estimate-noise --spp "$spp" --width "$width")
  [ -n "$time_limit" ] && args+=(--time-limit "$time_limit")
  args+=("${extra[@]+"${extra[@]}"}")
  key="${args[*]}"
  cached=0
  if [ $force -eq 0 ] && [ -f "$out/$n.exr" ] && [ -f "$out/$n.json" ] && [ -f "$out/$n.args" ] &&
     [ "$(cat "$out/$n.args")" = "$key" ] && [ "$out/$n.exr" -nt "$exe" ]; then
    cached=1
    for f in "$root/samples/$n"/*; do
      if [ "$f" -nt "$out/$n.exr" ]; then cached=0; fi
    done
  fi
  if [ $cached -eq 1 ]; then
    echo "$n: cached ($out/$n.exr)"
  else
    echo "$n: rendering ($spp spp${time_limit:+, at most ${time_limit} s})"
    rm -f "$out/$n.args"
    if ! "$exe" "${args[@]}"; then
      echo "make_references: $n: reference failed" >&2
      status=1
      continue
    fi
    printf '%s' "$key" > "$out/$n.args"
  fi
  j="$out/$n.json"
  mode="$(sed -n 's/^ *"mode": "\([a-z]*\)",$/\1/p' "$j" | head -n 1)"
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$n" "$mode" "$(json_num "$j" spp)" \
    "$(json_num "$j" time_s)" "$(json_num "$j" rays_per_s_per_core)" \
    "$(json_num "$j" rays_per_cpu_s)" "$(json_num "$j" rmse)" "$(json_num "$j" relmse)" \
    "$(json_num "$j" psnr_db)" >> "$summary.tmp"
done
mv "$summary.tmp" "$summary"
column -t -s "$(printf '\t')" "$summary" 2>/dev/null || cat "$summary"
exit $status
