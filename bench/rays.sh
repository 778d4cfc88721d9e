#!/usr/bin/env bash
# Ray-throughput benchmark over the sample scenes (see bench/rays.c):
#   bench/rays.sh [BUILD_DIR] [WIDTH]
# Prints the machine (CPU, cores, Vulkan device) and one table per scene.
set -euo pipefail
build=${1:-build}
width=${2:-640}
exe=$build/pb_bench_rays
echo "machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
echo "date: $(date -u +%Y-%m-%d)"
for s in cornell_box spot_room sun_atrium; do
  "$exe" "samples/$s/$s.gltf" "$width" 3
  echo
done
