#!/usr/bin/env bash
# Makes the PACK that bench/device_run.sh unpacks on a borrowed GPU machine
# without our Debian packages: bin.tar (photonbridge and the bench programs
# of BUILD) and devlib.tar.xz (every shared library they load, from ldd,
# but the C library's own, which the machine has: libc, libm, libpthread,
# libdl, librt, the dynamic loader). Run it in the repository root; the
# device run then needs this tree (samples/) and PACK.
#   bench/device_pack.sh BUILD PACK
set -eu
build=$1 pack=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/bin" "$tmp/devlib" "$pack"
for exe in photonbridge pb_bench_lbvh pb_bench_rays pb_bench_filters pb_bench_anim; do
  [ -x "$build/$exe" ] || continue
  cp "$build/$exe" "$tmp/bin/"
  strip "$tmp/bin/$exe"
  ldd "$build/$exe" | awk '$3 ~ /^\// {print $3}' | while read -r lib; do
    case $(basename "$lib") in
      libc.so*|libm.so*|libpthread.so*|libdl.so*|librt.so*|ld-linux*) ;;
      *) cp -L "$lib" "$tmp/devlib/" ;;
    esac
  done
done
tar -cf "$pack/bin.tar" -C "$tmp" bin
tar -cJf "$pack/devlib.tar.xz" -C "$tmp" devlib
ls -l "$pack"
