#!/usr/bin/env python3
"""Frames in flight (gpu.h PB_GPU_FRAMES, render/frame/frame.c): the next frame is
posed and recorded while the previous frame's last submission still runs.

1. Synchronization validation (PB_SYNC_VALIDATION=1: the Khronos layer with
   VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT) over a
   4-frame in-flight sequence, a still one and an orbit (motion vectors,
   temporal filter, A-Trous): exit 0 and not one validation message (any
   message makes the run fail with PB_ERR_VULKAN; stderr is checked too).
2. The overlap is structural: with --frames-in-flight 2 every frame after
   the first is recorded before the host waited for the previous frame
   (summary.records_overlapped == frames - 1), the host writes made
   meanwhile are deferred into the next command buffer
   (gpu_ring.deferred_writes > 0), no held context is reused before its
   timestamps are read (gpu_ring.held_stolen == 0); with 1 in flight none.
Timings (records_running, wall against GPU) are reported, not asserted.

usage: frame_in_flight.py PHOTONBRIDGE ROOT WORKDIR. Exit 77 without a Vulkan device."""
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


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
p = subprocess.run([EXE, "info", "--devices"], capture_output=True, text=True)
if p.returncode != 0:
    print("skip: no Vulkan device")
    sys.exit(77)

SCENE = os.path.join(ROOT, "samples", "cornell_box", "cornell_box.gltf")
COMMON = ["--spp", "2", "--iterations", "2", "--photons", "8192", "--seed", "3", "-q"]


def run(label, extra, in_flight, env_extra, w=32):
    d = os.path.join(WORK, label)
    os.makedirs(d, exist_ok=True)
    js = os.path.join(d, "seq.json")
    env = dict(os.environ)
    env.update(env_extra)
    cmd = [EXE, "render", SCENE, "--width", str(w), "--height", str(w), "--json", js,
           "--frames-in-flight", str(in_flight), "-o", os.path.join(d, "f_#.exr")] + COMMON + extra
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    msgs = [l for l in p.stderr.splitlines() if "Vulkan validation" in l]
    check(p.returncode == 0, "%s: exits 0 (%d) %s" % (label, p.returncode, p.stderr.strip()[-400:]))
    check(not msgs, "%s: %d validation messages%s" % (label, len(msgs), (": " + msgs[0][:300]) if msgs else ""))
    if p.returncode != 0:
        return None
    return json.load(open(js))


SYNC = {"PB_SYNC_VALIDATION": "1"}
for label, extra in [("still", ["--frames", "0:3"]),
                     ("orbit", ["--frames", "0:3", "--orbit", "--orbit-seconds", "8", "--atrous-iterations", "2"])]:
    j = run("sync_" + label, extra, 2, SYNC)
    if j:
        s = j["summary"]
        check(s.get("records_overlapped") == 3,
              "sync_%s: 3 of 4 frames recorded while the previous one was in flight (%s)" % (label, s.get("records_overlapped")))

j2 = run("overlap_2", ["--frames", "0:5"], 2, {})
j1 = run("overlap_1", ["--frames", "0:5"], 1, {})
if j2 and j1:
    s2, s1 = j2["summary"], j1["summary"]
    ring = s2.get("gpu_ring", {})
    check(s2.get("records_overlapped", 0) > 0 and s2.get("records_overlapped") == 5,
          "2 in flight: records_overlapped %s of 6 frames (5 expected)" % s2.get("records_overlapped"))
    check(s1.get("records_overlapped") == 0, "1 in flight: records_overlapped %s (0 expected)" % s1.get("records_overlapped"))
    check(ring.get("deferred_writes", 0) > 0, "2 in flight: host writes deferred into the next command buffer (%s)" % ring.get("deferred_writes"))
    check(ring.get("late_writes") == 0, "2 in flight: no host write while recording after deferred writes (%s)" % ring.get("late_writes"))
    check(ring.get("held_stolen") == 0, "2 in flight: no held context reused before its timestamps were read (%s)" % ring.get("held_stolen"))
    check(all(f["timing"].get("frame_gpu_ms") is None or f["timing"]["frame_gpu_ms"] > 0 for f in j2["frames"]),
          "2 in flight: every frame has its GPU time (its own timestamps)")
    print("info: records_running %s; gpu_ring %s" % (s2.get("records_running"), ring))
    for f in j2["frames"]:
        t = f["timing"]
        print("info: frame %d wall %.1f ms gpu %s ms interval %.1f ms" % (f["frame"], t["frame_wall_ms"], t.get("frame_gpu_ms"), t["frame_interval_ms"]))

if failures:
    print("%d failure(s)" % len(failures))
    sys.exit(1)
print("all passed")
