#!/usr/bin/env python3
"""The host's share of a frame (issue 17): renders a sequence with --json and
prints, per frame, timing.frame_wall_ms, timing.frame_gpu_ms (timestamp
queries) and (wall - gpu) / wall, then the median over the warm frames (all
but the first, which also compiles the pipelines).

usage: bench/frame_timing.py PHOTONBRIDGE SCENE [SIZE [FRAMES [EXTRA...]]]
e.g.   bench/frame_timing.py build/photonbridge samples/cornell_box_moving_light/cornell_box_moving_light.gltf 256 6"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

exe, scene = sys.argv[1:3]
size = int(sys.argv[3]) if len(sys.argv) > 3 else 256
frames = int(sys.argv[4]) if len(sys.argv) > 4 else 6
extra = sys.argv[5:]
with tempfile.TemporaryDirectory() as d:
    js = os.path.join(d, "seq.json")
    cmd = [exe, "render", scene, "--frames", "0:%d" % (frames - 1), "--width", str(size), "--height", str(size),
           "-o", os.path.join(d, "f_#.exr"), "--json", js, "-q"] + extra
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(p.stderr)
    j = json.load(open(js))
print("device %s, %s, %dx%d, %s" % (j["device"], os.path.basename(scene), j["width"], j["height"], " ".join(extra)))
shares = []
for f in j["frames"]:
    t = f["timing"]
    w, g = t["frame_wall_ms"], t["frame_gpu_ms"]
    ph = f.get("photons", {})
    share = (w - g) / w if g is not None else None
    if f is not j["frames"][0] and share is not None:
        shares.append(share)
    print("frame %d: wall %.1f ms, gpu %s ms, host %s ms, host share %s, photons emitted %s stored %s" %
          (f["frame"], w, "%.1f" % g if g is not None else "-", "%.1f" % (w - g) if g is not None else "-",
           "%.1f %%" % (100 * share) if share is not None else "-",
           ph.get("emitted", "-"), ph.get("stored", "-")))
if shares:
    hosts = [f["timing"]["frame_wall_ms"] - f["timing"]["frame_gpu_ms"] for f in j["frames"][1:]]
    print("median of the warm frames: host share %.1f %%, host %.1f ms" %
          (100 * statistics.median(shares), statistics.median(hosts)))
