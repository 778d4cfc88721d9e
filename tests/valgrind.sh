#!/usr/bin/env bash
# Memcheck over the CPU paths: each command runs under
#   valgrind --error-exitcode=99 --leak-check=full
# (leaks of kinds definite, indirect and possible are errors) and must exit
# with its own expected code, so a memory error or leak (99) fails the test.
# Suppressions: tests/valgrind.supp, third-party only (oneTBB's threads).
#
#   tests/valgrind.sh GROUP PHOTONBRIDGE
# Groups: info (every sample), render_cpu (reference 16x16 1 spp 1 thread, with
# PNG and JSON), images (compare with heat map and JSON, display), export_pov
# (every sample), corpus (a dozen broken files, each with its exit code).
# Exit 77 without valgrind.
set -u
group=$1
exe=$2
root=$(cd "$(dirname "$0")/.." && pwd)
command -v valgrind >/dev/null || { echo "skip: valgrind not installed"; exit 77; }
V=(valgrind -q --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite,indirect,possible
   --show-leak-kinds=definite,indirect,possible --suppressions="$root/tests/valgrind.supp" --num-callers=30)
pass=0
fail=0
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# vg NAME EXPECTED_EXIT CMD...
vg() {
  local name=$1 want=$2
  shift 2
  "${V[@]}" "$@" >"$work/out" 2>"$work/err"
  local rc=$?
  if [ $rc -eq "$want" ]; then
    pass=$((pass + 1))
    echo "ok: $name (exit $rc)"
  else
    fail=$((fail + 1))
    echo "FAIL: $name: exit $rc, expected $want (99: valgrind found errors)"
    head -60 "$work/err"
  fi
}

samples=$(ls "$root"/samples/*/*.gltf)
case $group in
info)
  for s in $samples; do vg "info $(basename "$s")" 0 "$exe" info "$s" --json "$work/i.json"; done
  ;;
render_cpu)
  s=$root/samples/cornell_box/cornell_box.gltf
  vg "reference cornell_box 16x16" 0 "$exe" reference "$s" -o "$work/r.exr" --png "$work/r.png" \
    --json "$work/r.json" --width 16 --spp 1 --threads 1 -q
  # SPPM caustics (ring: point light + mirror) and textures (spot_room).
  vg "reference ring 16x16 sppm" 0 "$exe" reference "$root/samples/ring/ring.gltf" -o "$work/g.exr" \
    --width 16 --spp 1 --threads 1 -q
  vg "reference spot_room 16x16" 0 "$exe" reference "$root/samples/spot_room/spot_room.gltf" -o "$work/t.exr" \
    --width 16 --spp 1 --threads 1 -q
  ;;
images)
  "$exe" reference "$root/samples/cornell_box/cornell_box.gltf" -o "$work/a.exr" --width 16 --spp 1 --threads 1 -q &&
    "$exe" reference "$root/samples/cornell_box/cornell_box.gltf" -o "$work/b.exr" --width 16 --spp 2 --threads 1 -q &&
    "$exe" reference "$root/samples/cornell_box/cornell_box.gltf" -o "$work/w.exr" --width 32 --spp 1 --threads 1 -q ||
    { echo "setup failed"; exit 1; }
  vg "compare" 0 "$exe" compare "$work/a.exr" "$work/b.exr" --heatmap "$work/h.png" --json "$work/c.json" -q
  vg "display" 0 "$exe" display "$work/a.exr" -o "$work/d.png"
  # Error paths free what they allocated too.
  vg "compare size mismatch" 9 "$exe" compare "$work/a.exr" "$work/w.exr" -q
  head -c 300 "$work/a.exr" >"$work/t.exr"
  vg "display truncated EXR" 8 "$exe" display "$work/t.exr" -o "$work/t.png"
  ;;
export_pov)
  for s in $samples; do vg "export-pov $(basename "$s")" 0 "$exe" export-pov "$s" -o "$work/s.pov" -q; done
  ;;
corpus)
  for c in bin_truncated accessor_count_past_view accessor_count_2pow40_no_view accessor_count_negative \
           position_nan image_truncated image_huge_header node_cycle json_truncated json_deep_nesting \
           glb_chunk_past_end sparse_index_out_of_range sparse_values_short skin_joint_index_oob \
           morph_target_attribute_oob sparse_accessors skin morph_animated morph_tangent_after_rigid morph_tangent_zero; do
    line=$(awk -F'\t' -v c="$c" '$1 ~ "/"c"/" {print; exit}' "$root/tests/corpus/expected.tsv")
    [ -n "$line" ] || { fail=$((fail + 1)); echo "FAIL: $c not in expected.tsv"; continue; }
    path=$(echo "$line" | cut -f1)
    want=$(echo "$line" | cut -f2)
    vg "corpus $c" "$want" "$exe" info "$root/tests/corpus/$path" -q
  done
  ;;
*)
  echo "unknown group $group"
  exit 2
  ;;
esac
echo "$pass passed, $fail failed"
[ $fail -eq 0 ] && [ $pass -gt 0 ]
