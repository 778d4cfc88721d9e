#!/usr/bin/env python3
"""Same pixels as before: the GPU-resident frame's resolve pass
(shaders/frame/resolve.comp) and readback give the AOVs the host resolve gave,
channel for channel, for every sample scene (small, same seed), a scene
with normal maps (eq. 20's AOVs), a direct-only render and a short sequence
(temporal filter, motion vectors, A-Trous).

Reference: the same binary with PB_RESOLVE_ON_HOST=1 (the former host
resolve, kept in src/render/frame/readback.c as the test's reference), and, when
a baseline binary is given (the 5th argument or PB_BASELINE_EXE, e.g. a
build of the commit before the GPU-resident frame), that binary's output too.
Two renders agree to float rounding, not bit for bit: the photon store's
order follows the GPU's scheduling (atomic slots in photon_trace.comp), so
the tolerance is 1e-5 of each channel's peak, as in tests/render_drive.py.
Also checks that --json reports timing.frame_wall_ms and frame_gpu_ms (a
number with timestamps) and no non-finite values.

usage: frame_same_pixels.py PHOTONBRIDGE EXR_PROBE ROOT WORKDIR [BASELINE] [PART...]
PART: samples, extra, in_flight, still_gpu (default samples and extra). Exit 77 when no Vulkan device is present."""
import glob
import json
import os
import shutil
import subprocess
import sys

EXE, PROBE, ROOT, WORK = sys.argv[1:5]
rest = sys.argv[5:]
BASE = os.environ.get("PB_BASELINE_EXE") or None
if rest and (rest[0] == "" or os.path.sep in rest[0]):
    BASE = rest.pop(0) or BASE
PARTS = rest or ["samples", "extra"]
ROUNDING = 1e-5
COMMON = ["--width", "40", "--height", "32", "--spp", "2", "--iterations", "2", "--photons", "4096", "--seed", "5",
          "-q"]
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def run(exe, args, env_extra=None):
    env = dict(os.environ)
    env.setdefault("PB_VK_VALIDATION", "1")
    env.update(env_extra or {})
    p = subprocess.run([exe] + args, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        print(" ".join([exe] + args))
        print(p.stdout[-3000:])
        print(p.stderr[-3000:])
    return p


def exr(path):
    p = subprocess.run([PROBE, path], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(p.stderr)
    return json.loads(p.stdout)["channels"]


def worst_rel(a, b):
    peak = max(max((abs(v) for v in a), default=0.0), 1e-6)
    return max((abs(x - y) for x, y in zip(a, b)), default=0.0) / peak


def compare(label, got, want):
    a, b = exr(got), exr(want)
    check(sorted(a) == sorted(b), "%s: the same channels (%d)" % (label, len(a)))
    worst, name = 0.0, ""
    for ch in sorted(set(a) & set(b)):
        w = worst_rel(a[ch], b[ch]) if len(a[ch]) == len(b[ch]) else float("inf")
        if w > worst:
            worst, name = w, ch
    check(worst <= ROUNDING, "%s: every channel equal to float rounding (worst %.3g of the peak, %s)" %
          (label, worst, name or "-"))


def render(label, scene, extra, d):
    """Renders scene with the GPU resolve, the host reference and the
    baseline; compares the pictures."""
    outs = {}
    for kind, exe, env in [("gpu", EXE, None), ("host", EXE, {"PB_RESOLVE_ON_HOST": "1"}), ("base", BASE, None)]:
        if not exe:
            continue
        out = os.path.join(d, "%s_%s.exr" % (label, kind))
        js = os.path.join(d, "%s_%s.json" % (label, kind))
        args = ["render", scene, "-o", out] + COMMON + extra
        if kind != "base":
            args += ["--json", js]
        p = run(exe, args, env)
        check(p.returncode == 0, "%s: %s render exits 0" % (label, kind))
        if p.returncode != 0:
            return
        outs[kind] = out
        if kind == "gpu":
            j = json.load(open(js))
            t = j.get("timing", {})
            check(isinstance(t.get("frame_wall_ms"), (int, float)) and t["frame_wall_ms"] > 0 and
                  (t.get("frame_gpu_ms") is None or 0 < t["frame_gpu_ms"]),
                  "%s: timing.frame_wall_ms %s, frame_gpu_ms %s" % (label, t.get("frame_wall_ms"),
                                                                    t.get("frame_gpu_ms")))
            check(j["guarded"]["nonfinite_values"] == 0, "%s: no non-finite values" % label)
    if "gpu" in outs and "host" in outs:
        compare(label + " GPU resolve vs host resolve", outs["gpu"], outs["host"])
    if "gpu" in outs and "base" in outs:
        compare(label + " vs the baseline binary", outs["gpu"], outs["base"])


def fresh(sub):
    d = os.path.join(WORK, sub)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    return d


def part_samples():
    d = fresh("samples")
    scenes = sorted(glob.glob(os.path.join(ROOT, "samples", "*", "*.gltf")))
    check(len(scenes) >= 8, "%d sample scenes" % len(scenes))
    for sc in scenes:
        render(os.path.basename(os.path.dirname(sc)), sc, [], d)


def part_extra():
    d = fresh("extra")
    render("normal_map", os.path.join(ROOT, "tests", "data", "normal_map", "normal_map.gltf"), [], d)
    cornell = os.path.join(ROOT, "samples", "cornell_box", "cornell_box.gltf")
    render("direct_only", cornell, ["--direct-only"], d)
    render("atrous", cornell, ["--atrous-iterations", "2"], d)
    # A sequence: moving light, temporal filter, motion vectors, A-Trous.
    seq = os.path.join(ROOT, "samples", "cornell_box_moving_light", "cornell_box_moving_light.gltf")
    outs = {}
    for kind, exe, env in [("gpu", EXE, None), ("host", EXE, {"PB_RESOLVE_ON_HOST": "1"}), ("base", BASE, None)]:
        if not exe:
            continue
        pat = os.path.join(d, "seq_%s_#.exr" % kind)
        args = ["render", seq, "-o", pat, "--frames", "0:2"] + COMMON
        js = os.path.join(d, "seq_%s.json" % kind)
        if kind == "gpu":
            args += ["--json", js]
        p = run(exe, args, env)
        check(p.returncode == 0, "sequence: %s render exits 0" % kind)
        if p.returncode == 0:
            outs[kind] = pat
        if kind == "gpu" and p.returncode == 0:
            frames = json.load(open(js))["frames"]
            ok = all(isinstance(f.get("timing", {}).get("frame_wall_ms"), (int, float)) for f in frames)
            check(len(frames) == 3 and ok, "sequence: timing.frame_wall_ms for each of %d frames" % len(frames))
    for f in range(3):
        for other in ("host", "base"):
            if "gpu" in outs and other in outs:
                compare("sequence frame %d vs %s" % (f, other), outs["gpu"].replace("#", str(f)),
                        outs[other].replace("#", str(f)))


def part_in_flight():
    """Frames in flight (src/render/frame/sequence.h): a sequence rendered
    with --frames-in-flight 2 (the frame's last submission and the readback's
    copy into the ring run while the host goes on; frames come out one late)
    against --frames-in-flight 1 (one frame at a time), same seed: the same
    pixels to float rounding (the photon store's order, as above), the same
    per-frame records. A moving light (temporal filter, motion vectors,
    A-Trous), a still camera (the progressive accumulation, which the
    in-flight path runs one frame late), and a warm-up frame."""
    d = fresh("in_flight")
    cases = [("moving_light", os.path.join(ROOT, "samples", "cornell_box_moving_light",
                                           "cornell_box_moving_light.gltf"), ["--frames", "0:3"]),
             ("still", os.path.join(ROOT, "samples", "cornell_box", "cornell_box.gltf"),
              ["--frames", "0:3", "--warmup", "1"])]
    for label, scene, extra in cases:
        outs, recs = {}, {}
        for n in ("1", "2"):
            pat = os.path.join(d, "%s_%s_#.exr" % (label, n))
            js = os.path.join(d, "%s_%s.json" % (label, n))
            p = run(EXE, ["render", scene, "-o", pat, "--json", js, "--frames-in-flight", n] + COMMON + extra)
            check(p.returncode == 0, "%s: --frames-in-flight %s exits 0" % (label, n))
            if p.returncode != 0:
                continue
            outs[n] = pat
            j = json.load(open(js))
            check(j.get("frames_in_flight") == int(n), "%s: --json frames_in_flight %s" % (label, j.get("frames_in_flight")))
            recs[n] = j["frames"]
        if len(outs) < 2:
            continue
        a, b = recs["2"], recs["1"]
        check([f["frame"] for f in a] == [f["frame"] for f in b] == list(range(4)),
              "%s: frames 0-3 in order (%s)" % (label, [f["frame"] for f in a]))
        keys = lambda fs: [(f.get("still"), f.get("photons", {}).get("stored"), f.get("spp")) for f in fs]
        check(keys(a) == keys(b), "%s: the same still flags, photons stored and spp per frame" % label)
        ok = all(isinstance(f.get("timing", {}).get("frame_wall_ms"), (int, float)) and f["timing"]["frame_wall_ms"] > 0
                 for f in a)
        check(ok, "%s: timing.frame_wall_ms for every frame in flight" % label)
        flags = ([f["timing"].get("in_flight") for f in a], [f["timing"].get("in_flight") for f in b])
        check(flags == ([True] * 4, [False] * 4),
              "%s: timing.in_flight true for every frame with 2 in flight, false with 1 (%s)" % (label, flags))
        for f in range(4):
            compare("%s frame %d, 2 in flight vs 1" % (label, f), outs["2"].replace("#", str(f)),
                    outs["1"].replace("#", str(f)))


def part_still_gpu():
    """A still run's progressive accumulation on the GPU
    (shaders/frame/accumulate.comp, the running means in a target of the sequence)
    against the host arrays it replaced (PB_STILL_ON_HOST=1, sequence.c's
    accumulate()), same seed: every frame of a still camera (5 frames: the
    beauty, direct and caustic means) to float rounding, with 1 and 2 frames
    in flight, and the --json per-frame record says where it ran."""
    d = fresh("still_gpu")
    scene = os.path.join(ROOT, "samples", "cornell_box", "cornell_box.gltf")
    for n in ("1", "2"):
        outs = {}
        for kind, env in (("gpu", None), ("host", {"PB_STILL_ON_HOST": "1"})):
            pat = os.path.join(d, "still_%s_%s_#.exr" % (n, kind))
            js = os.path.join(d, "still_%s_%s.json" % (n, kind))
            p = run(EXE, ["render", scene, "-o", pat, "--json", js, "--frames", "0:4", "--frames-in-flight", n] +
                    COMMON, env)
            check(p.returncode == 0, "still %s in flight, %s means: exits 0" % (n, kind))
            if p.returncode != 0:
                continue
            outs[kind] = pat
            fr = json.load(open(js))["frames"]
            where = [f.get("timing", {}).get("still_on_gpu") for f in fr]
            check(where == [kind == "gpu"] * 5, "still %s in flight, %s means: timing.still_on_gpu %s" % (n, kind, where))
        if len(outs) == 2:
            for f in range(5):
                compare("still frame %d (%s in flight), GPU means vs host means" % (f, n),
                        outs["gpu"].replace("#", str(f)), outs["host"].replace("#", str(f)))


if subprocess.run([EXE, "info", "--devices"], capture_output=True, text=True).returncode != 0:
    print("skip: no Vulkan device")
    sys.exit(77)
for part in PARTS:
    globals()["part_" + part]()
if failures:
    print("%d failed" % len(failures))
    sys.exit(1)
print("all passed" + ("" if BASE else " (no baseline binary given: against the host reference only)"))
