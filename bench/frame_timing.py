#!/usr/bin/env python3
"""The host's share of a frame: renders a sequence with --json and
prints, per frame, timing.frame_wall_ms, timing.frame_gpu_ms (timestamp
queries) and (wall - gpu) / wall, and the frame's host <-> device bytes
(--json "transfers": uploads and downloads outside the readback, and the
readback), then the median over the warm frames (all but the first, which
also compiles the pipelines), and the whole run's wall time. With frames in
flight (--frames-in-flight 2, the default of `render --frames`) a frame's
frame_wall_ms is the host's time on it (src/render/render.h), so the host
share compares the two modes' host time; the run wall compares throughput. FRAMES 1: a single frame (`render` without
--frames; its one frame is also the cold one).

usage: bench/frame_timing.py PHOTONBRIDGE SCENE [SIZE [FRAMES [EXTRA...]]]
SIZE: N (N x N) or WxH.
e.g.   bench/frame_timing.py build/photonbridge samples/cornell_box_moving_light/cornell_box_moving_light.gltf 256 6
       bench/frame_timing.py build/photonbridge samples/cornell_box/cornell_box.gltf 1920x1080 4 --photons 1048576"""
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

exe, scene = sys.argv[1:3]
size = sys.argv[3] if len(sys.argv) > 3 else "256"
width, height = (int(v) for v in size.split("x")) if "x" in size else (int(size), int(size))
frames = int(sys.argv[4]) if len(sys.argv) > 4 else 6
extra = sys.argv[5:]
with tempfile.TemporaryDirectory() as d:
    js = os.path.join(d, "seq.json")
    seq = ["--frames", "0:%d" % (frames - 1)] if frames > 1 else []
    cmd = [exe, "render", scene] + seq + ["--width", str(width), "--height", str(height),
           "-o", os.path.join(d, "f_#.exr" if seq else "f.exr"), "--json", js, "-q"] + extra
    run0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True)
    run_s = time.monotonic() - run0
    if p.returncode != 0:
        sys.exit(p.stderr)
    j = json.load(open(js))
if not seq:  # one frame: its record is the document itself
    j["frames"] = [dict(j, frame=0)]
print("device %s, %s, %dx%d, %s%s" % (j["device"], os.path.basename(scene), width, height, " ".join(extra),
                                      ", frames in flight %s" % j["frames_in_flight"] if "frames_in_flight" in j else ""))
# The whole run (process start to exit: scene load, pipelines, every frame and
# its EXR): what frames in flight shorten, as the host's work on one frame
# (its output) overlaps the GPU's on the next.
print("run wall %.2f s for %d frame(s)" % (run_s, frames))
shares = []
for f in j["frames"]:
    t = f["timing"]
    w, g = t["frame_wall_ms"], t["frame_gpu_ms"]
    ph = f.get("photons", {})
    share = (w - g) / w if g is not None else None
    if f is not j["frames"][0] and share is not None:
        shares.append(share)
    if not ph and "photons" in f and isinstance(f["photons"], dict):
        ph = f["photons"]
    tr = f.get("transfers", {})
    print("frame %d: wall %.1f ms, gpu %s ms, host %s ms, host share %s, photons emitted %s stored %s, "
          "up %s B, down %s B, readback %s B" %
          (f["frame"], w, "%.1f" % g if g is not None else "-", "%.1f" % (w - g) if g is not None else "-",
           "%.1f %%" % (100 * share) if share is not None else "-",
           ph.get("emitted", "-"), ph.get("stored", "-"), tr.get("upload_bytes", "-"),
           tr.get("download_bytes", "-"), tr.get("readback_bytes", "-")))
if len(j["frames"]) == 1:
    t = j["frames"][0]["timing"]
    if t["frame_gpu_ms"] is not None:
        print("single frame: host share %.1f %%, host %.1f ms" %
              (100 * (t["frame_wall_ms"] - t["frame_gpu_ms"]) / t["frame_wall_ms"],
               t["frame_wall_ms"] - t["frame_gpu_ms"]))
if shares:
    hosts = [f["timing"]["frame_wall_ms"] - f["timing"]["frame_gpu_ms"] for f in j["frames"][1:]]
    print("median of the warm frames: host share %.1f %%, host %.1f ms" %
          (100 * statistics.median(shares), statistics.median(hosts)))
    # Throughput: a frame's period (from the previous frame's output to its
    # own, the EXR writing between included) against its GPU time.
    per = [(f["timing"]["frame_interval_ms"], f["timing"]["frame_gpu_ms"]) for f in j["frames"][1:]
           if f["timing"].get("frame_interval_ms")]
    if per:
        print("median of the warm frames: period %.1f ms, idle GPU share of the period %.1f %%" %
              (statistics.median(p for p, _ in per), 100 * statistics.median((p - g) / p for p, g in per)))
