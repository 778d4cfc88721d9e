#!/usr/bin/env python3
"""Seed 003's multi-level up-sampling of the diffuse photon irradiance
(sec. 6, Figure 9; src/render/estimate/upsample.c) from the command line, on
cornell_box: `render --upsample-levels 2` against `--upsample-levels 0` at
the same seed (the same photon maps):
  - the mean beauty and the mean indirect within 2 %;
  - the beauty's PSNR (linear RGB, peak the L = 0 image's brightest value)
    above PSNR_MIN;
  - the recompute count > 0 (the box's corners and the blocks' edges) and
    below half of the up-sampled pixels (it is not everything);
  - the estimate's invocations that traverse the photon LBVH (coarse +
    recomputed + full-resolution) below 1/2 of the full one (every pixel of
    every sample: cornell_box's camera sees a surface at each);
  - no non-finite values, the JSON naming the level;
  - a sequence (cornell_box_moving_light, two frames, temporal + A-Trous)
    with the same option: exit 0, each frame with its up-sampling counts;
  - --upsample-levels with --estimator knn refused (exit 2), and 5 (range).
usage: upsample_check.py PHOTONBRIDGE EXR_PROBE ROOT WORKDIR
Exit 77 when no Vulkan device is present."""
import json
import math
import os
import shutil
import subprocess
import sys

EXE, PROBE, ROOT, WORK = sys.argv[1:5]
CORNELL = os.path.join(ROOT, "samples", "cornell_box", "cornell_box.gltf")
SIZE, SPP = 64, 4
COMMON = ["--width", str(SIZE), "--height", str(SIZE), "--spp", str(SPP), "--iterations", "2", "--photons", "65536",
          "--seed", "3", "-q"]
# Measured (lavapipe, 64 x 64, 4 spp, 2 x 65536 photons, seed 3): beauty 52.2 dB,
# indirect 29.1 dB (the peak the indirect's own), mean beauty -0.36 %, mean
# indirect -0.83 %, 3095 of 14122 up-sampled pixels recomputed, 3995 of 16384
# traversals; the bounds keep 3-4 dB of margin.
PSNR_MIN = 48.0
PSNR_INDIRECT_MIN = 26.0
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def run(args):
    env = dict(os.environ)
    env.setdefault("PB_VK_VALIDATION", "1")
    p = subprocess.run([EXE] + args, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        print(" ".join([EXE] + args))
        print(p.stdout[-3000:])
        print(p.stderr[-3000:])
    return p


def exr(path):
    p = subprocess.run([PROBE, path], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(p.stderr)
    return json.loads(p.stdout)["channels"]


def rgb(ch, prefix):
    names = [prefix + c for c in "RGB"]
    if not all(n in ch for n in names):
        names = [c for c in "RGB"]
    return [v for n in names for v in ch[n]]


if subprocess.run([EXE, "info", "--devices"], capture_output=True, text=True).returncode != 0:
    print("skip: no Vulkan device")
    sys.exit(77)
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
res = {}
for lv in (0, 2):
    out, js = os.path.join(WORK, "l%d.exr" % lv), os.path.join(WORK, "l%d.json" % lv)
    p = run(["render", CORNELL, "-o", out, "--json", js, "--upsample-levels", str(lv)] + COMMON)
    check(p.returncode == 0, "render --upsample-levels %d exits 0" % lv)
    if p.returncode == 0:
        res[lv] = (exr(out), json.load(open(js)))
if len(res) == 2:
    (i0, j0), (i2, j2) = res[0], res[2]
    b0, b2 = rgb(i0, ""), rgb(i2, "")
    n0, n2 = rgb(i0, "indirect."), rgb(i2, "indirect.")
    mb = sum(b2) / sum(b0) - 1
    mi = sum(n2) / sum(n0) - 1
    check(abs(mb) <= 0.02, "mean beauty at L 2 %+.2f %% of L 0's" % (100 * mb))
    check(abs(mi) <= 0.02, "mean indirect at L 2 %+.2f %% of L 0's" % (100 * mi))
    peak = max(b0)
    mse = sum((a - b) ** 2 for a, b in zip(b2, b0)) / len(b0)
    psnr = 10 * math.log10(peak * peak / mse) if mse > 0 else float("inf")
    check(psnr > PSNR_MIN, "beauty PSNR of L 2 against L 0: %.2f dB (> %.1f)" % (psnr, PSNR_MIN))
    peak = max(n0)
    mse = sum((a - b) ** 2 for a, b in zip(n2, n0)) / len(n0)
    psnr = 10 * math.log10(peak * peak / mse) if mse > 0 else float("inf")
    check(psnr > PSNR_INDIRECT_MIN, "indirect PSNR of L 2 against L 0 (peak the indirect's): %.2f dB (> %.1f)" %
          (psnr, PSNR_INDIRECT_MIN))
    e = j2.get("estimator", {})
    full = SIZE * SIZE * SPP
    est = e.get("upsample_estimates", -1)
    rec = e.get("upsample_recomputed", -1)
    interp = e.get("upsample_interpolated", -1)
    print("L 2: coarse %s, recomputed %s, interpolated %s, full-res %s, estimates %s of %d (%.3f), gather %.2f ms "
          "(L 0: %.2f ms)" % (e.get("upsample_coarse"), rec, interp, e.get("upsample_full_res"), est, full,
                              est / full, j2["passes_ms"].get("gather", -1), j0["passes_ms"].get("gather", -1)))
    check(e.get("upsample_levels") == 2 and j2["photons"].get("upsample_levels") == 2,
          "--json: estimator.upsample_levels %s, photons.upsample_levels %s" %
          (e.get("upsample_levels"), j2["photons"].get("upsample_levels")))
    check(rec > 0 and rec < 0.5 * (rec + interp), "recomputed %s of %s up-sampled pixels (> 0, < 1/2)" %
          (rec, rec + interp))
    check(0 < est < 0.5 * full, "the estimate's traversals %s below 1/2 of the full %d" % (est, full))
    check("upsample_levels" not in j0.get("estimator", {}), "L 0: no up-sampling statistics")
    for lv in (0, 2):
        check(res[lv][1]["guarded"]["nonfinite_values"] == 0, "L %d: no non-finite values" % lv)
        bad = sum(1 for ch in res[lv][0].values() for v in ch if not isinstance(v, (int, float)) or v != v)
        check(bad == 0, "L %d: every channel finite (%d bad)" % (lv, bad))
seq = os.path.join(ROOT, "samples", "cornell_box_moving_light", "cornell_box_moving_light.gltf")
js = os.path.join(WORK, "seq.json")
p = run(["render", seq, "-o", os.path.join(WORK, "seq_#.exr"), "--frames", "0:1", "--upsample-levels", "2",
         "--json", js, "--width", "32", "--height", "32", "--spp", "2", "--photons", "16384", "-q"])
check(p.returncode == 0, "sequence --upsample-levels 2 exits 0")
if p.returncode == 0:
    frames = json.load(open(js))["frames"]
    check(len(frames) == 2 and all(f.get("estimator", {}).get("upsample_coarse", 0) > 0 for f in frames),
          "sequence: up-sampling counts in each of %d frames" % len(frames))
for extra, what in [(["--upsample-levels", "2", "--estimator", "knn"], "with --estimator knn"),
                    (["--upsample-levels", "5"], "5 levels")]:
    p = subprocess.run([EXE, "render", CORNELL, "-o", os.path.join(WORK, "no.exr")] + extra,
                       capture_output=True, text=True)
    check(p.returncode == 2 and not os.path.exists(os.path.join(WORK, "no.exr")),
          "--upsample-levels %s refused: exit %d, %s" % (what, p.returncode, p.stderr.strip()[:120]))
if failures:
    print("%d failed" % len(failures))
    sys.exit(1)
print("all passed")
