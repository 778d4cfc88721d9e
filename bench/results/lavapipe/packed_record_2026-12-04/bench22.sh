#!/bin/bash
# Interleaved old (96-byte sorted record, /work/main) vs new (48-byte, /work/wt)
out=/tmp/b22; mkdir -p $out
for r in $(seq ${R0:-1} ${R1:-3}); do
  for b in old new; do
    root=/work/main; [ $b = new ] && root=/work/wt
    /usr/bin/time -f "%U %S" -o $out/${b}_$r.time $root/build/photonbridge render /work/main/samples/cornell_box/cornell_box.gltf -o $out/${b}_$r.exr --width 256 --height 256 --spp 1 --seed 3 --json $out/${b}_$r.json > /dev/null 2>&1
    $root/build/pb_bench_lbvh --repeat 3 100000 1000000 > $out/${b}_lbvh_$r.json 2>/dev/null
  done
done
echo done
