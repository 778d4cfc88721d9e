#!/usr/bin/env python3
"""photonbridge view's speed: frames per second while orbiting and
while still, and the time from a camera move to a picture within 1 dB of the
converged one. Runs the viewer under xvfb-run with --script input and reads
its --json per-frame records (wall time between frames, PSNR).

  fps        SIZE px, cornell_box: a left drag of 2 px every frame for
             FRAMES frames (every frame moves: restart, motion vectors,
             temporal + A-Trous), then FRAMES still frames (refinement)
  converge   256 px: the view starts orbited away, Home at frame 3 moves it
             back to the scene camera; each later frame's beauty is compared
             (`compare`'s PSNR) with a reference-renderer image of the scene
             camera (Embree path tracer, REF_SPP samples); the converged PSNR
             is the last frame's (CONVERGE_FRAMES still frames after the
             move); reported: the wall time from the move to the first frame
             within 1 dB of it, and that frame's number

usage: view_bench.py PHOTONBRIDGE OUTDIR [--photons N] [--frames N] [--frames-in-flight 1|2]
Prints a markdown table (machine, device, scene, sizes, photons) for
bench/README.md.
"""
import argparse
import json
import os
import platform
import shutil
import subprocess
import sys

ap = argparse.ArgumentParser()
ap.add_argument("exe")
ap.add_argument("out")
ap.add_argument("--photons", type=int, default=1 << 18)
ap.add_argument("--frames", type=int, default=12)
ap.add_argument("--converge-frames", type=int, default=48)
ap.add_argument("--ref-spp", type=int, default=1024)
ap.add_argument("--sizes", default="256,512")
ap.add_argument("--frames-in-flight", type=int, default=1, choices=(1, 2),
                help="view --frames-in-flight (2: the window one frame behind the renderer)")
a = ap.parse_args()
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
scene = os.path.join(root, "samples/cornell_box/cornell_box.gltf")
os.makedirs(a.out, exist_ok=True)
xvfb = shutil.which("xvfb-run")
if not xvfb:
    sys.exit("view_bench: needs xvfb-run (apt-get install xvfb xauth)")


def view(size, script_lines, frames, extra=()):
    script = os.path.join(a.out, "script_%d.txt" % size)
    with open(script, "w") as f:
        f.write("\n".join(script_lines) + "\n")
    stats = os.path.join(a.out, "view_%d.json" % size)
    cmd = [xvfb, "-a", "-s", "-screen 0 1400x1000x24", "nice", a.exe, "view", scene, "--width", str(size),
           "--photons", str(a.photons), "--exit-after", str(frames), "--script", script, "--json", stats, "-q",
           "--frames-in-flight", str(a.frames_in_flight)]
    subprocess.run(cmd + list(extra), check=True)
    return json.load(open(stats))


def fps(frames):
    ms = sum(f["wall_ms"] for f in frames)
    return 1e3 * len(frames) / ms if ms > 0 else float("nan")


rows = []
device = None
for size in [int(s) for s in a.sizes.split(",")]:
    n = a.frames
    lines = ["1 cursor 10 10", "1 press left"] + ["%d cursor %d 10" % (k, 10 + 2 * k) for k in range(2, n + 2)] + \
            ["%d release left" % (n + 2)]
    j = view(size, lines, 2 * n + 2)
    device = j["device"]
    fr = j["frames"]
    moving = [f for f in fr[2:n + 2] if not f["still"]]
    still = [f for f in fr[n + 3:] if f["still"]]
    rows.append((size, fps(moving), len(moving), fps(still), len(still),
                 sum(f["render_ms"] for f in still) / max(1, len(still)), j["photons_stored"]))

# Time to within 1 dB after a move, at 256 px.
size = 256
ref = os.path.join(a.out, "reference_%d.exr" % size)
if not os.path.exists(ref):
    subprocess.run(["nice", a.exe, "reference", scene, "--width", str(size), "--spp", str(a.ref_spp), "-o", ref, "-q"],
                   check=True)
lines = ["0 cursor 10 10", "0 press left", "0 cursor 40 10", "0 release left", "3 key home"]
j = view(size, lines, 3 + a.converge_frames, ["--reference", ref])
fr = j["frames"]
after = fr[3:]
p_conv = after[-1]["psnr"]
t = 0.0
hit = None
for k, f in enumerate(after):
    t += f["wall_ms"] if k else f["render_ms"] + f["present_ms"]
    if f["psnr"] >= p_conv - 1.0:
        hit = (k, t)
        break

print("machine: %s, %d cores (%s); device %s; cornell_box, %d photon paths a frame, %d stored; %d frame(s) in flight" %
      (platform.processor() or platform.machine(), os.cpu_count(), platform.node(), device, a.photons, rows[0][6],
       a.frames_in_flight))
print()
print("| size | fps orbiting (frames) | fps still (frames) | ms a still frame (render + resolve + filters) |")
print("|---:|---:|---:|---:|")
for size, fm, nm, fs, ns, ms, _ in rows:
    print("| %d px | %.2f (%d) | %.2f (%d) | %.0f |" % (size, fm, nm, fs, ns, ms))
print()
print("move at 256 px (Home after an orbit): converged PSNR %.2f dB after %d still frames (reference: %d spp path "
      "tracer); within 1 dB (%.2f dB) at frame %d after the move, %.2f s after it" %
      (p_conv, len(after) - 1, a.ref_spp, hit and after[hit[0]]["psnr"] or float("nan"), hit[0] if hit else -1,
       hit[1] / 1e3 if hit else float("nan")))
print("PSNR per frame after the move:", " ".join("%.2f" % f["psnr"] for f in after))
