#!/usr/bin/env python3
"""The GPU-resident frame moves no pixels but the readback's: per
frame, --json "transfers" counts the bytes of pb_gpu_buffer_upload and
_download outside the readback module and what the readback brought to the
host. A sequence (cornell_box --orbit: motion vectors, temporal filter,
A-Trous every frame), a moving caustic (the caustics' own temporal filter)
and a normal-mapped single frame (eq. 20 on the GPU) are rendered at two
sizes: uploads and downloads must not grow with the pixel count (constants,
scene data, photon counts: no AOV, history or motion vector goes up or
down), and stay under one float per pixel of the smaller image; the
readback must grow with it. The host path (PB_RESOLVE_ON_HOST=1, the
former per-pass round trips, kept as the reference) must show the round
trip the counters exist to catch, and the GPU's temporal statistics
(workgroup sums, atomics) must match the host's to 1e-3. Last, the host's
share of a warm 128 px sequence frame stays under 10 %.

usage: frame_transfers.py PHOTONBRIDGE ROOT WORKDIR. Exit 77 without a Vulkan device."""
import json
import os
import shutil
import subprocess
import sys

EXE, ROOT, WORK = sys.argv[1:4]
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def scene(*p):
    return os.path.join(ROOT, *p)


def run(label, args, w, h, host=False):
    d = os.path.join(WORK, label)
    os.makedirs(d, exist_ok=True)
    js = os.path.join(d, "%dx%d%s.json" % (w, h, "_host" if host else ""))
    env = dict(os.environ)
    env.setdefault("PB_VK_VALIDATION", "1")
    if host:
        env["PB_RESOLVE_ON_HOST"] = "1"
    cmd = [EXE, "render"] + args + ["--width", str(w), "--height", str(h), "--json", js, "-q",
                                    "-o", os.path.join(d, "f_#.exr" if "--frames" in args else "f.exr")]
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    check(p.returncode == 0, "%s %dx%d%s exits 0 %s" % (label, w, h, " (host)" if host else "",
                                                          p.stderr.strip()[-300:]))
    if p.returncode != 0:
        return []
    j = json.load(open(js))
    return j["frames"] if "frames" in j else [j]


COMMON = ["--spp", "2", "--iterations", "2", "--photons", "8192", "--seed", "3"]
CASES = [
    ("orbit", [scene("samples", "cornell_box", "cornell_box.gltf"), "--frames", "0:3", "--orbit",
               "--orbit-seconds", "8", "--atrous-iterations", "3"] + COMMON),
    ("caustics", [scene("samples", "cornell_caustics_moving_sphere", "cornell_caustics_moving_sphere.gltf"),
                  "--frames", "0:2"] + COMMON),
    ("normal_map", [scene("tests", "data", "normal_map", "normal_map.gltf"), "--atrous-iterations", "2"] + COMMON),
]
SMALL, LARGE = (48, 40), (96, 80)

if subprocess.run([EXE, "info", "--devices"], capture_output=True).returncode != 0:
    print("skip: no Vulkan device")
    sys.exit(77)
shutil.rmtree(WORK, ignore_errors=True)
for label, args in CASES:
    small, large = run(label, args, *SMALL), run(label, args, *LARGE)
    if not small or len(small) != len(large):
        continue
    n_small, n_large = SMALL[0] * SMALL[1], LARGE[0] * LARGE[1]
    for i, (a, b) in enumerate(zip(small, large)):
        ta, tb = a["transfers"], b["transfers"]
        what = "%s frame %d" % (label, i)
        # Geometry that moves uploads its new pose and BVH (scene data, the
        # same at every size; an animated scene's first frame too); nothing
        # per pixel goes up or down.
        bound = 1 << 62 if b.get("geometry_moved") or (label == "caustics" and i == 0) else 4 * n_small
        check(ta["upload_bytes"] == tb["upload_bytes"] and tb["upload_bytes"] < bound,
              "%s: uploads %d / %d bytes at %d / %d px (no per-pixel upload)" %
              (what, ta["upload_bytes"], tb["upload_bytes"], n_small, n_large))
        check(ta["download_bytes"] == tb["download_bytes"] and tb["download_bytes"] < 4 * n_small,
              "%s: downloads outside the readback %d / %d bytes (photon counts only)" %
              (what, ta["download_bytes"], tb["download_bytes"]))
        # Every AOV (18 floats a pixel at least) comes back once: readback.c.
        check(tb["readback_bytes"] >= 18 * 4 * n_large and
              tb["readback_bytes"] - ta["readback_bytes"] >= 18 * 4 * (n_large - n_small),
              "%s: the readback grows with the image (%d -> %d bytes)" %
              (what, ta["readback_bytes"], tb["readback_bytes"]))
    host = run(label, args, *SMALL, host=True)
    if label == "orbit" and len(host) == len(small):
        # The former path uploads the filters' inputs and downloads their
        # outputs every frame: the counters see it.
        moved = [h["transfers"]["upload_bytes"] >= 3 * 16 * n_small and
                 h["transfers"]["download_bytes"] >= 16 * n_small for h in host]
        check(all(moved), "orbit: the host path's round trips are counted (%s)" %
              [(h["transfers"]["upload_bytes"], h["transfers"]["download_bytes"]) for h in host])
        for i, (g, h) in enumerate(zip(small, host)):
            tg, th = g.get("temporal", {}), h.get("temporal", {})
            check(tg and th and abs(tg["mean_history"] - th["mean_history"]) <= 1e-3 and
                  abs(tg["reset_fraction"] - th["reset_fraction"]) <= 1e-9,
                  "orbit frame %d: temporal statistics on the GPU %s, host %s" % (i, tg, th))
# The host's share of a warm sequence frame on this device (at
# most 10 % on lavapipe at 256 px; here 128 px, which has less GPU work to
# hide the host's behind, so the bound is the stricter test): the moving
# light of cornell_box_moving_light, temporal filter, motion vectors and 4
# A-Trous passes every frame, median over frames 1-5.
seq = run("share", [scene("samples", "cornell_box_moving_light", "cornell_box_moving_light.gltf"), "--frames", "0:5",
                    "--photons", "16384", "--seed", "0"], 128, 128)
warm = [(f["timing"]["frame_wall_ms"] - f["timing"]["frame_gpu_ms"]) / f["timing"]["frame_wall_ms"]
        for f in seq[1:] if f["timing"].get("frame_gpu_ms") is not None]
if warm:
    share = sorted(warm)[len(warm) // 2]
    check(share <= 0.10, "host share of a warm 128 px sequence frame %.1f %% (<= 10 %%; frames %s)" %
          (100 * share, ["%.1f %%" % (100 * w) for w in warm]))
if failures:
    print("%d failed" % len(failures))
    sys.exit(1)
print("all passed")
