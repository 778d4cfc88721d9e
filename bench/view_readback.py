#!/usr/bin/env python3
"""photonbridge view's readback per frame (display-only readback):
the viewer under xvfb-run on cornell_box, SIZE x SIZE, a left drag of 2 px
a frame for FRAMES frames (moving: restart, motion vectors, temporal +
A-Trous), then FRAMES still frames, once with PB_VIEW_READBACK_ALL=1 (the
former readback: every AOV to the host, the beauty uploaded again for the
display pass) and once as `view` runs now (no AOV read: the display pass
reads the frame's planes on the GPU). From the --json per-frame records:
readback bytes, display upload bytes, render ms (pb_view_session_frame +
picture) and wall ms (frame to frame), means over frames 2.. (the first two
build pipelines and start the drag).

usage: view_readback.py PHOTONBRIDGE OUTDIR [--sizes 256,512] [--photons N] [--frames N] [--frames-in-flight 1|2]
Prints a markdown table.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

ap = argparse.ArgumentParser()
ap.add_argument("exe")
ap.add_argument("out")
ap.add_argument("--photons", type=int, default=1 << 16)
ap.add_argument("--frames", type=int, default=6)
ap.add_argument("--sizes", default="256,512")
ap.add_argument("--frames-in-flight", type=int, default=1, choices=(1, 2))
a = ap.parse_args()
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
scene = os.path.join(root, "samples/cornell_box/cornell_box.gltf")
os.makedirs(a.out, exist_ok=True)
xvfb = shutil.which("xvfb-run")
if not xvfb:
    sys.exit("view_readback: needs xvfb-run (apt-get install xvfb xauth)")


def view(size, full):
    n = a.frames
    lines = ["1 cursor 10 10", "1 press left"] + ["%d cursor %d 10" % (k, 10 + 2 * k) for k in range(2, n + 2)] + \
            ["%d release left" % (n + 2)]
    tag = "%d_%s" % (size, "all" if full else "display")
    script = os.path.join(a.out, "script_%s.txt" % tag)
    with open(script, "w") as f:
        f.write("\n".join(lines) + "\n")
    stats = os.path.join(a.out, "view_%s.json" % tag)
    env = dict(os.environ)
    env.pop("PB_VIEW_READBACK_ALL", None)
    if full:
        env["PB_VIEW_READBACK_ALL"] = "1"
    cmd = [xvfb, "-a", "-s", "-screen 0 1400x1000x24", "nice", a.exe, "view", scene, "--width", str(size),
           "--height", str(size), "--photons", str(a.photons), "--exit-after", str(2 * n + 2), "--script", script,
           "--json", stats, "-q", "--frames-in-flight", str(a.frames_in_flight)]
    subprocess.run(cmd, check=True, env=env)
    return json.load(open(stats))


def mean(fr, key):
    return sum(f[key] for f in fr) / max(1, len(fr))


print("| size | readback | frames | readback bytes a frame | display upload bytes | render ms | wall ms | gpu display |")
print("|---:|---|---:|---:|---:|---:|---:|---|")
device = None
for size in [int(s) for s in a.sizes.split(",")]:
    for full in (True, False):
        j = view(size, full)
        device = j["device"]
        fr = j["frames"][2:]
        print("| %d px | %s | %d | %.0f | %.0f | %.1f | %.1f | %s |" %
              (size, "all AOVs (before)" if full else "display only (now)", len(fr), mean(fr, "readback_bytes"),
               mean(fr, "display_upload_bytes"), mean(fr, "render_ms"), mean(fr, "wall_ms"), j["gpu_display"]))
print()
print("device %s; cornell_box, %d photon paths a frame, %d frame(s) in flight, %d moving + %d still frames" %
      (device, a.photons, a.frames_in_flight, a.frames, a.frames))
