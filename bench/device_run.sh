#!/usr/bin/env bash
# The NVIDIA measurements (rays, the photon map, the filters), as one script for a borrowed GPU
# machine that has none of our Debian packages: PACK holds devlib.tar.xz (our
# shared libraries: Embree, OpenEXR, OpenColorIO, the Vulkan loader, ...) and
# bin.tar (photonbridge and the bench programs, built on Debian 12); results
# go to OUT (and, after every step, into the archive PB_DEVICE_TAR when set,
# so a run stopped at its limit still returns what it measured). Every step
# has its own time limit and the script goes on after a failure.
# bench/device_pack.sh BUILD PACK makes PACK from a Debian 12 build.
#   bench/device_run.sh PACK OUT [STEPS]
# STEPS: comma-separated step names to run (default: all), e.g.
# "devices,lbvh,lbvh_paths,cornell_1080p,cornell_1080p_1m_warm,cornell_1080p_1m,cornell_128" for
# the photon map's numbers alone (about 3 minutes), or
# "devices,frame_timing_1080p,frame_timing_1080p_sync,frame_timing_1080p_single"
# for the frame's host share (about 3 minutes).
set -u
pack=$1 out=$2 only=${3:-}
mkdir -p /tmp/pb "$out"
tar -xJf "$pack/devlib.tar.xz" -C /tmp/pb && tar -xf "$pack/bin.tar" -C /tmp/pb || exit 1
export LD_LIBRARY_PATH=/tmp/pb/devlib
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[ -f "$icd" ] && export VK_DRIVER_FILES=$icd
b=/tmp/pb/bin
step() { # NAME SECONDS CMD...: output to OUT/NAME.txt, exit code and time appended
  local name=$1 limit=$2; shift 2
  case ",$only," in ",,"|*",$name,"*) ;; *) return 0 ;; esac
  local t0=$(date +%s.%N)
  timeout "$limit" "$@" > "$out/$name.txt" 2>&1
  local rc=$?
  echo "exit=$rc seconds=$(awk "BEGIN{print $(date +%s.%N) - $t0}")" >> "$out/$name.txt"
  echo "$name: exit $rc"
  [ -n "${PB_DEVICE_TAR:-}" ] && tar -czf "$PB_DEVICE_TAR" -C "$(dirname "$out")" "$(basename "$out")"
}
{ nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv; nproc; uname -r; } > "$out/machine.txt" 2>&1
step devices 60 $b/photonbridge info --devices
s=samples
# A 1080p frame of sun_atrium (1 spp, 2^18 photon paths, 7 bounces);
# the first render also compiles the pipelines, so it runs twice.
step atrium_warm 120 $b/photonbridge render $s/sun_atrium/sun_atrium.gltf --width 1920 --height 1080 -o /tmp/a.exr -q
step atrium_1080p 120 $b/photonbridge render $s/sun_atrium/sun_atrium.gltf --width 1920 --height 1080 -o /tmp/a.exr --json "$out/atrium_1080p.json"
step cornell_1080p 120 $b/photonbridge render $s/cornell_box/cornell_box.gltf --width 1920 --height 1080 -o /tmp/c.exr --json "$out/cornell_1080p.json"
# The gather at 1080p over at least 1 M stored photons (2^20 paths
# store about 1.1 M on cornell_box); twice, the first compiles the pipelines.
step cornell_1080p_1m_warm 120 $b/photonbridge render $s/cornell_box/cornell_box.gltf --width 1920 --height 1080 --photons 1048576 -o /tmp/c.exr -q
step cornell_1080p_1m 120 $b/photonbridge render $s/cornell_box/cornell_box.gltf --width 1920 --height 1080 --photons 1048576 -o /tmp/c.exr --json "$out/cornell_1080p_1m.json"
# The frame's host share at 1080p over >= 1 M stored photons
# (2^20 paths), wall <= 1.25 x GPU the goal: a sequence (orbit: motion
# vectors, temporal filter, 4 A-Trous passes each frame, filters on the GPU)
# and a single frame; per frame wall, GPU, host share and transfers.
step frame_timing_1080p 150 python3 bench/frame_timing.py $b/photonbridge $s/cornell_box/cornell_box.gltf 1920x1080 5 --photons 1048576 --orbit --orbit-seconds 8
# Frames in flight (the default since the readback ring): the same sequence one
# frame at a time, for the before/after of the host share.
step frame_timing_1080p_sync 150 python3 bench/frame_timing.py $b/photonbridge $s/cornell_box/cornell_box.gltf 1920x1080 5 --photons 1048576 --orbit --orbit-seconds 8 --frames-in-flight 1
# The submission ring (gpu.h PB_GPU_FRAMES) on a discrete GPU: device-local
# buffers are not mapped there, so deferred writes and their settle take
# the paths lavapipe never does. 1080p 1 M: records_overlapped, records_running
# and gpu_ring in the JSON's summary; then a short run under synchronization
# validation (zero messages; skipped where the layer is missing).
step inflight_1080p_1m 150 $b/photonbridge render $s/cornell_box/cornell_box.gltf --width 1920 --height 1080 --photons 1048576 --frames 0:5 --frames-in-flight 2 -o /tmp/i_#.exr -q --json "$out/inflight_1080p_1m.json"
step inflight_sync 120 env PB_SYNC_VALIDATION=1 $b/photonbridge render $s/cornell_box/cornell_box.gltf --width 256 --frames 0:3 --frames-in-flight 2 --orbit --orbit-seconds 8 -o /tmp/s_#.exr --json "$out/inflight_sync.json"
step frame_timing_1080p_single 90 python3 bench/frame_timing.py $b/photonbridge $s/cornell_box/cornell_box.gltf 1920x1080 1 --photons 1048576 --atrous-iterations 4
# Cross-driver check: the same seed as on lavapipe (compared on the host).
step cornell_128 60 $b/photonbridge render $s/cornell_box/cornell_box.gltf --width 128 --spp 4 --iterations 4 --seed 1 -o "$out/cornell_128_nvidia.exr"
# The filters at 1920x1080, and a 1080p fly-through with both filters.
step filters 60 $b/pb_bench_filters --repeat 10 1920x1080
step flythrough 90 $b/photonbridge render $s/sun_atrium_flythrough/sun_atrium_flythrough.gltf --frames 0:11 --width 1920 --height 1080 -o /tmp/f_##.exr --json "$out/flythrough_1080p.json" -q
# Ray throughput (with ray queries beside the GLSL BVH on a device that has
# them: the RQ columns); LBVH build rates.
step rays 90 bash -c "for sc in cornell_box spot_room sun_atrium; do $b/pb_bench_rays $s/\$sc/\$sc.gltf 1920 5; done"
# Per pass, ray queries against the GLSL BVH at 1080p, the same seed, in one
# run (bench/traversal.py; docs/traversal.md).
step traversal 240 python3 bench/traversal.py --exe $b/photonbridge --icd '' --width 1920 --out "$out/traversal"
# LBVH build (stages) and radix sort against photon count, 10^4 to
# the device's limit (3.2 x 10^7 records of 96 bytes fit 4 GiB buffers), the
# default sort path (subgroups); then the portable path against it.
step lbvh 120 $b/pb_bench_lbvh --repeat 3 10000 100000 1000000 4194304 16777216 33554432
step lbvh_paths 90 bash -c "$b/pb_bench_lbvh --repeat 3 --sort portable 1000000 16777216; $b/pb_bench_lbvh --repeat 3 --sort subgroup 1000000 16777216"
[ -x $b/pb_bench_anim ] && step anim 45 $b/pb_bench_anim $s/cornell_caustics_moving_sphere/cornell_caustics_moving_sphere.gltf 0 1
echo done
