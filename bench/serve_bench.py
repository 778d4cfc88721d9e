#!/usr/bin/env python3
"""`photonbridge serve` timings (bench/README.md, "serve"): one session on a
scene, wall-clock seconds seen by the client for: start to the ready line
(scene load + GPU scene), the first frame, still frames (median), a camera
request to its frame (the move restarts the still run), a resolution
request to its frame (a new sequence), a reload to its reply, and a frame
after the reload. Not a test: the numbers go into bench/README.md with the
machine, scene, size and photons.

usage: serve_bench.py PHOTONBRIDGE SCENE [--width W] [--photons N] [--still K]"""
import argparse
import json
import math
import statistics
import subprocess
import time

ap = argparse.ArgumentParser()
ap.add_argument("exe")
ap.add_argument("scene")
ap.add_argument("--width", type=int, default=128)
ap.add_argument("--photons", type=int, default=32768)
ap.add_argument("--still", type=int, default=8)
a = ap.parse_args()

t0 = time.perf_counter()
p = subprocess.Popen([a.exe, "serve", a.scene, "--width", str(a.width), "--photons", str(a.photons), "-q"],
                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1)


def ask(obj):
    t = time.perf_counter()
    p.stdin.write(json.dumps(obj) + "\n")
    p.stdin.flush()
    r = json.loads(p.stdout.readline())
    if not r.get("ok"):
        raise SystemExit("serve: %r" % r)
    return r, time.perf_counter() - t


ready = json.loads(p.stdout.readline())
t_ready = time.perf_counter() - t0
first, t_first = ask({"cmd": "frame"})
still = [ask({"cmd": "frame"})[1] for _ in range(a.still)]
# A camera turned 0.2 rad about Y and moved sideways (a small orbit step).
ask({"cmd": "camera", "index": 0})
cam = {"cmd": "camera", "view": [math.cos(0.2), 0, -math.sin(0.2), -0.8, 0, 1, 0, -1, math.sin(0.2), 0,
                                 math.cos(0.2), -3.9, 0, 0, 0, 1],
       "projection": [2.7, 0, 0, 0, 0, 2.7, 0, 0, 0, 0, -1.0005, -0.10002, 0, 0, -1, 0]}
_, t_cam = ask(cam)
r, t_cam_frame = ask({"cmd": "frame"})
_, t_res = ask({"cmd": "resolution", "width": a.width * 2, "height": a.width * 2})
_, t_res_frame = ask({"cmd": "frame"})
_, t_reload = ask({"cmd": "reload"})
_, t_reload_frame = ask({"cmd": "frame"})
p.stdin.close()
p.wait(60)
out = {"device": ready["device"], "scene": a.scene, "width": a.width, "photons": a.photons,
       "photons_stored": first["photons_stored"], "ready_s": t_ready, "first_frame_s": t_first,
       "still_frame_s_median": statistics.median(still), "camera_request_s": t_cam,
       "camera_to_frame_s": t_cam_frame, "resolution_x2_to_frame_s": t_res + t_res_frame,
       "reload_s": t_reload, "frame_after_reload_s": t_reload_frame}
print(json.dumps(out, indent=1))
