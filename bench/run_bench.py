#!/usr/bin/env python3
"""Speed against error: every renderer, every sample scene, one run.

    python3 bench/run_bench.py [--quick] [--exe build/photonbridge] [--device N]
                               [--scenes a,b] [--width W] [--out DIR] [--markdown FILE]

`make bench` / `make bench-quick` / `make bench-estimators` run it (DEVICE=N passes --device N).

For each scene at one resolution it sweeps the renderers of CONFIGS below:
photonbridge (GPU pipeline) over photon budgets and iterations, the reference
path tracer over spp, POV-Ray over quality presets and Cycles over spp (where
Blender is installed). Every point is its own child process, timed from
spawn to exit (wall seconds, including start-up, scene load and writing the
EXR), with its peak resident memory from os.wait4's rusage (ru_maxrss of the
child and the children it waited for: run_povray.sh's povray, Blender), and
its error against a converged reference (`photonbridge compare`: PSNR and
SSIM on the display image, RMSE and relMSE scene-linear). The converged
reference is rendered once per scene/width/spp/seed and cached under
bench/cache/ with its own noise estimate (`reference --estimate-noise`); the
reference renderer's sweep uses another seed, so its points are independent
of it.

Then the pipeline internals (seed 000): the per-pass breakdown (Fig. 5), a
leaf-size sweep against T_auto (Table 1), k_PD and the footprint radius
histogram (Table 3), and LBVH build / radix-sort rates against photon count
(bench/lbvh.c).

Writes DIR/results.json (everything, with settings, tool versions, device,
machine and load), DIR/results.csv (one row per point), DIR/*.svg and *.png
(matplotlib, when importable; Debian's python3-matplotlib) and the Markdown
report (DIR/BENCHMARKS.md; a full run also writes the repository's
BENCHMARKS.md, naming its device and listing the other result sets without
their numbers). DIR defaults to
bench/results/DEVICE-SLUG/{full,quick}: results of different devices are
kept apart and never compared as absolute times; the photonbridge / best
peer ratios are taken within one run.
"""
import argparse
import csv
import hashlib
import json
import math
import os
import platform
import re
import shutil
import signal
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
THRESHOLDS_DB = (25.0, 30.0, 35.0)
PEERS = ("reference", "povray", "cycles")

# ---- what is swept ---------------------------------------------------------
# One entry per curve: a label and its points (each a dict of settings).
# photonbridge: photons per map, maps (iterations), spp (>= iterations; the
# direct light's samples), optional extra options. New density estimators and
# filters add curves here (an entry's "needs" names a `render` option: the
# curve is skipped, with a note, when this build's `render --help-all` lacks it).


def pb_curve(label, photons, maps_spp, extra=(), needs=None):
    """maps_spp: (photon maps K, samples per pixel) per point."""
    pts = [{"photons": photons, "iterations": k, "spp": spp, "extra": list(extra)} for k, spp in maps_spp]
    return {"label": label, "points": pts, "needs": needs}


CONFIGS = {
    "full": {
        "width": 128,
        "scenes": ["cornell_box", "cornell_caustics", "ring", "spot_room"],
        # Converged references: spp per scene (noise PSNR about 40 dB or more).
        "reference_spp": {"cornell_box": 4096, "default": 2048},
        "photonbridge": [
            pb_curve("2^16 photons/map", 1 << 16, [(1, 1), (1, 4), (2, 4), (4, 8), (8, 16), (16, 32)]),
            pb_curve("2^18 photons/map", 1 << 18, [(1, 4), (4, 8), (16, 32)]),
            pb_curve("2^16, progressive", 1 << 16, [(4, 8), (16, 32)], extra=["--progressive"]),
            pb_curve("2^16, constant kernel", 1 << 16, [(4, 8), (16, 32)], extra=["--constant-kernel"]),
            pb_curve("2^16, RSM first bounce", 1 << 16, [(4, 8), (16, 32)], extra=["--first-bounce", "rsm"],
                     needs="--first-bounce"),
            # One map of many paths from the RSM, its caustic share at the
            # default 0.5 (ring: one map beats several of the same
            # paths, bench/README.md "The caustic share").
            {"label": "RSM, one map, caustic share", "needs": "--caustic-share",
             "points": [{"photons": n, "iterations": 1, "spp": spp, "extra": ["--first-bounce", "rsm"]}
                        for n, spp in ((1 << 17, 8), (1 << 17, 16), (1 << 18, 16), (1 << 18, 32))]},
            pb_curve("2^16, A-Trous 5 passes", 1 << 16, [(1, 4), (4, 8), (16, 32)],
                     extra=["--atrous-iterations", "5"], needs="--atrous-iterations"),
            # The density estimators: kNN at its default k = 64.
            pb_curve("2^16, kNN (k 64)", 1 << 16, [(1, 4), (4, 8), (16, 32)], extra=["--estimator", "knn"],
                     needs="--estimator"),
            # Seed 001's screen-space splatting and seed 004's view-sample
            # hierarchy at their defaults, on the same maps.
            pb_curve("2^16, splat", 1 << 16, [(1, 4), (4, 8), (16, 32)], extra=["--estimator", "splat"],
                     needs="--splat-ntile"),
            pb_curve("2^16, vsch", 1 << 16, [(1, 4), (4, 8), (16, 32)], extra=["--estimator", "vsch"],
                     needs="--vsch-radius"),
            # Seed 003's image-space photon tracer: 8 cube maps
            # instead of the BVH; its misses are in the section below.
            pb_curve("2^16, images tracer (8 maps)", 1 << 16, [(4, 8), (16, 32)], extra=["--tracer", "images"],
                     needs="--tracer"),
        ],
        "reference": [4, 16, 64, 256, 1024],
        # POV-Ray's medium radiosity + caustic photons on cornell_caustics
        # took 62 s at 48 px and 156 s at 64 px (loaded machine): draft only.
        "povray": {"default": ["draft", "medium"], "cornell_caustics": ["draft"]},
        "cycles": [16, 256],
        "leaf_scenes": ["cornell_box", "cornell_caustics", "ring", "spot_room"],
        "leaf_sizes": [1, 2, 4, 8, 16, 32, 64, 128, 256, 512],
        "leaf_setup": {"width": 96, "photons": 1 << 17, "iterations": 2, "spp": 2, "repeat": 2},
        "lbvh_counts": [1e4, 3e4, 1e5, 3e5, 1e6, 1.39e6, 3e6, 1e7],
        "timeout_s": 600,
    },
    "quick": {
        "width": 96,
        "scenes": ["cornell_box", "cornell_caustics"],
        "reference_spp": {"default": 2048},
        "photonbridge": [
            pb_curve("2^16 photons/map", 1 << 16, [(1, 1), (1, 4), (4, 8), (16, 32)]),
            pb_curve("2^16, progressive", 1 << 16, [(4, 8), (16, 32)], extra=["--progressive"]),
            pb_curve("2^16, A-Trous 5 passes", 1 << 16, [(4, 8), (16, 32)], extra=["--atrous-iterations", "5"],
                     needs="--atrous-iterations"),
            pb_curve("2^16, kNN (k 64)", 1 << 16, [(4, 8), (16, 32)], extra=["--estimator", "knn"],
                     needs="--estimator"),
            pb_curve("2^16, splat", 1 << 16, [(4, 8), (16, 32)], extra=["--estimator", "splat"],
                     needs="--splat-ntile"),
            pb_curve("2^16, vsch", 1 << 16, [(4, 8), (16, 32)], extra=["--estimator", "vsch"],
                     needs="--vsch-radius"),
        ],
        "reference": [4, 16, 64, 256],
        # POV-Ray's medium radiosity + photons takes minutes on cornell_caustics.
        "povray": {"default": ["draft"], "cornell_box": ["draft", "medium"]},
        "cycles": [16, 128],
        "leaf_scenes": ["cornell_box"],
        "leaf_sizes": [1, 4, 16, 64, 256, 512],
        "leaf_setup": {"width": 64, "photons": 1 << 16, "iterations": 1, "spp": 1, "repeat": 2},
        "lbvh_counts": [1e4, 1e5, 1e6],
        "timeout_s": 300,
    },
    # The density estimators side by side: the four on the same
    # maps of every sample, one run (`make bench-estimators`).
    "estimators": {
        "width": 96,
        "scenes": ["cornell_box", "cornell_caustics", "ring", "spot_room"],
        "reference_spp": {"default": 2048},
        "photonbridge": [
            pb_curve("2^16, LBVH gather", 1 << 16, [(1, 4), (4, 8), (16, 32)], extra=["--estimator", "lbvh"],
                     needs="--estimator"),
            pb_curve("2^16, kNN (k 64)", 1 << 16, [(1, 4), (4, 8), (16, 32)], extra=["--estimator", "knn"],
                     needs="--estimator"),
            pb_curve("2^16, splat", 1 << 16, [(1, 4), (4, 8), (16, 32)], extra=["--estimator", "splat"],
                     needs="--splat-ntile"),
            pb_curve("2^16, vsch", 1 << 16, [(1, 4), (4, 8), (16, 32)], extra=["--estimator", "vsch"],
                     needs="--vsch-radius"),
            pb_curve("2^16, vsch directional", 1 << 16, [(1, 4), (4, 8), (16, 32)],
                     extra=["--estimator", "vsch", "--vsch-directional"], needs="--vsch-directional"),
        ],
        "reference": [16, 64],
        "povray": {"default": []},
        "cycles": [],
        "leaf_scenes": [],
        "leaf_sizes": [],
        "leaf_setup": {"width": 64, "photons": 1 << 16, "iterations": 1, "spp": 1, "repeat": 1},
        "lbvh_counts": [],
        "timeout_s": 600,
    },
    # The test suite's end-to-end check of this driver (tests/bench.cmake).
    "smoke": {
        "width": 32,
        "scenes": ["cornell_box"],
        "reference_spp": {"default": 256},
        "photonbridge": [pb_curve("2^14 photons/map", 1 << 14, [(1, 1), (4, 4)])],
        "reference": [1, 16],
        "povray": {"default": ["draft"]},
        "cycles": [],
        "leaf_scenes": ["cornell_box"],
        "leaf_sizes": [1, 512],
        "leaf_setup": {"width": 32, "photons": 1 << 14, "iterations": 1, "spp": 1, "repeat": 1},
        "lbvh_counts": [1e4],
        "timeout_s": 120,
    },
}

# ---- running one point -----------------------------------------------------


def loadavg():
    try:
        return float(open("/proc/loadavg").read().split()[0])
    except (OSError, ValueError, IndexError):
        return None


PEAK = {"exe": None, "how": "wait4 from Python (includes the interpreter's ~17 MiB floor)"}


def build_peak_helper(cache):
    """bench/peak.c compiled into the cache (cc is in install-deps.sh's
    build-essential): peak RSS measured from a 1 MiB parent, not from
    Python, whose resident set a forked child keeps as its high-water mark."""
    src, exe = os.path.join(HERE, "peak.c"), os.path.join(cache, "pb_peak")
    if not (os.access(exe, os.X_OK) and os.path.getmtime(exe) >= os.path.getmtime(src)):
        cc = shutil.which(os.environ.get("CC", "cc"))
        if not cc or subprocess.run([cc, "-O2", "-o", exe, src]).returncode != 0:
            return
    PEAK.update(exe=exe, how="ru_maxrss from wait4 in bench/peak.c (child and the descendants it waited for)")


def run_point(cmd, log, timeout, env=None):
    """Runs cmd as a child; returns rc, wall seconds, peak RSS (MiB) of the
    child and the descendants it waited for, and its output (also in log)."""
    rss_file = log + ".rss"
    if PEAK["exe"]:
        cmd = [PEAK["exe"], rss_file] + list(cmd)
    t0 = time.monotonic()
    with open(log, "w") as f:
        f.write("$ " + " ".join(cmd) + "\n")
        f.flush()
        try:
            p = subprocess.Popen(cmd, stdout=f, stderr=subprocess.STDOUT, env=env, start_new_session=True)
        except OSError as e:
            f.write(str(e) + "\n")
            return {"rc": 127, "wall_s": 0.0, "maxrss_mb": None, "out": str(e)}
        killed = []

        def kill():
            killed.append(1)
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except OSError:
                pass

        timer = threading.Timer(timeout, kill)
        timer.start()
        try:
            _, status, ru = os.wait4(p.pid, 0)
        finally:
            timer.cancel()
        p.returncode = os.waitstatus_to_exitcode(status) if hasattr(os, "waitstatus_to_exitcode") else status >> 8
        wall = time.monotonic() - t0
        rc = 124 if killed else p.returncode
        maxrss = ru.ru_maxrss
        if PEAK["exe"]:
            try:
                with open(rss_file) as g:
                    maxrss = int(g.read())
                os.unlink(rss_file)
            except (OSError, ValueError):
                maxrss = None
        f.write("\nexit=%d wall_s=%.3f maxrss_kb=%s\n" % (rc, wall, maxrss))
    with open(log) as f:
        out = f.read()
    # CPU seconds of the child and the descendants it waited for (wait4's
    # rusage): on a shared machine a better measure than wall time of work
    # done on the CPU, lavapipe's included (bench/alternating.py).
    cpu = ru.ru_utime + ru.ru_stime
    return {"rc": rc, "wall_s": round(wall, 4), "maxrss_mb": round(maxrss / 1024.0, 1) if maxrss else None,
            "cpu_s": round(cpu, 4), "out": out}


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def tail(text, n=300):
    return " ".join(text.strip().split())[-n:]


class Bench:
    def __init__(self, a, cfg):
        self.a = a
        self.cfg = cfg
        self.exe = os.path.abspath(a.exe)
        self.out = os.path.abspath(a.out)
        self.work = os.path.join(self.out, "work")
        self.cache = os.path.abspath(a.cache)
        self.width = a.width or cfg["width"]
        self.timeout = cfg["timeout_s"]
        self.dev = ["--device", str(a.device)] if a.device is not None else []
        self.points = []
        self.notes = []
        self.deadline = time.time() + 60 * a.minutes if a.minutes else None
        self.skipped = []
        os.makedirs(self.work, exist_ok=True)
        os.makedirs(self.cache, exist_ok=True)
        # --help-all lists every option (--help leaves out the algorithm
        # switches the curves need); a build from before it has --help only.
        rc = subprocess.run([self.exe, "render", "--help-all"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True)
        if rc.returncode != 0:
            rc = subprocess.run([self.exe, "render", "--help"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                universal_newlines=True)
        self.render_help = rc.stdout

    def expired(self, what):
        """True past --minutes: the point `what` is skipped (and listed)."""
        if self.deadline is None or time.time() < self.deadline:
            return False
        self.skipped.append(what)
        return True

    def scene_path(self, name):
        return os.path.join(ROOT, "samples", name, name + ".gltf")

    def log(self, msg):
        print("bench: " + msg, flush=True)

    def compare(self, test, ref, tag):
        js = os.path.join(self.work, tag + ".cmp.json")
        r = run_point([self.exe, "compare", test, ref, "--json", js, "-q"], os.path.join(self.work, tag + ".cmp.log"),
                      120)
        m = read_json(js) if r["rc"] == 0 else None
        if not m:
            return {"error": "compare: " + tail(r["out"])}
        return {k: m.get(k) for k in ("psnr_db", "ssim", "rmse", "relmse", "mse_display")}

    def add_point(self, scene, renderer, config, params, r, exr, ref, render_s=None, extra=None):
        pt = {"scene": scene, "width": self.width, "renderer": renderer, "config": config, "params": params,
              "wall_s": r["wall_s"], "render_s": render_s, "maxrss_mb": r["maxrss_mb"], "load_1m": loadavg(),
              "ref_noise_psnr_db": ref["noise"].get("psnr_db") if ref.get("noise") else None}
        if r["rc"] != 0 or not os.path.isfile(exr):
            pt["status"] = "failed"
            pt["error"] = "exit %d: %s" % (r["rc"], tail(r["out"]))
        else:
            m = self.compare(exr, ref["exr"], os.path.basename(exr)[:-4])
            pt.update(m)
            pt["status"] = "ok" if "error" not in m else "failed"
            os.unlink(exr)  # the images are not kept, only their numbers
        if extra:
            pt.update(extra)
        self.points.append(pt)
        self.log("%-16s %-12s %-26s %s  %7.2f s  %6s MiB  PSNR %s" % (
            scene, renderer, config, json.dumps(params, separators=(",", ":"))[:40], pt["wall_s"],
            pt["maxrss_mb"], "%.2f" % pt["psnr_db"] if pt.get("psnr_db") is not None else pt.get("error", "-")))
        return pt

    # ---- converged references (cached) -----------------------------------

    def reference(self, scene):
        rs = self.cfg["reference_spp"]
        spp = self.a.ref_spp or rs.get(scene, rs["default"])
        h = hashlib.sha1()
        sdir = os.path.dirname(self.scene_path(scene))
        for fn in sorted(os.listdir(sdir)):
            with open(os.path.join(sdir, fn), "rb") as f:
                h.update(fn.encode() + b"\0" + f.read())
        args = ["--width", str(self.width), "--spp", str(spp), "--seed", "0", "--estimate-noise"]
        # The version without its commit: a rebuild does not invalidate the
        # cache (--refresh-references does); the JSON keeps the full string.
        h.update(" ".join(args).encode() + b"\0" + self.version.split(" (")[0].encode())
        key = "%s_w%d_spp%d_%s" % (scene, self.width, spp, h.hexdigest()[:12])
        exr, js = os.path.join(self.cache, key + ".exr"), os.path.join(self.cache, key + ".json")
        st = read_json(js)
        if os.path.isfile(exr) and st and not self.a.refresh_references:
            self.log("%s: converged reference cached (%s)" % (scene, os.path.relpath(exr, ROOT)))
        else:
            self.log("%s: rendering the converged reference (%d spp, %d px)" % (scene, spp, self.width))
            r = run_point([self.exe, "reference", self.scene_path(scene), "-o", exr, "--json", js, "-q"] + args,
                          os.path.join(self.cache, key + ".log"), 4 * 3600)
            st = read_json(js)
            if r["rc"] != 0 or not st:
                raise RuntimeError("%s: reference failed: %s" % (scene, tail(r["out"])))
            st["render_wall_s"] = r["wall_s"]
            st["photonbridge_version"] = self.version
            st["render_load_1m"] = loadavg()
            with open(js, "w") as f:
                json.dump(st, f, indent=1)
        return {"exr": exr, "key": key, "spp": spp, "mode": st.get("mode"), "time_s": st.get("time_s"),
                "photonbridge_version": st.get("photonbridge_version"), "load_1m": st.get("render_load_1m"),
                "noise": st.get("noise"), "width": st.get("width"), "height": st.get("height")}

    # ---- one function per renderer ----------------------------------------

    def bench_photonbridge(self, scene, ref):
        for curve in self.cfg["photonbridge"]:
            if curve["needs"] and curve["needs"] not in self.render_help:
                self.notes.append("photonbridge curve '%s' skipped: render has no %s" % (curve["label"], curve["needs"]))
                continue
            for p in curve["points"]:
                if self.expired("%s photonbridge %s %s" % (scene, curve["label"], json.dumps(p))):
                    continue
                tag = "%s_pb_%s_%d_%d_%d" % (scene, re.sub(r"\W+", "", curve["label"]), p["photons"], p["iterations"],
                                            p["spp"])
                exr, js = os.path.join(self.work, tag + ".exr"), os.path.join(self.work, tag + ".json")
                cmd = [self.exe, "render", self.scene_path(scene), "-o", exr, "--width", str(self.width),
                       "--spp", str(p["spp"]), "--photons", str(p["photons"]), "--iterations", str(p["iterations"]),
                       "--json", js, "-q"] + p["extra"] + self.dev
                r = run_point(cmd, os.path.join(self.work, tag + ".log"), self.timeout)
                st = read_json(js) or {}
                ph = st.get("photons") or {}
                dm = (st.get("device_memory") or {}).get("buffers_peak_bytes")
                extra = {"passes_ms": st.get("passes_ms"), "device": st.get("device"), "k_pd": ph.get("k_pd"),
                         "t_auto": ph.get("t_auto"), "photons_stored": ph.get("stored"),
                         "gpu_buffers_peak_mb": round(dm / 1048576.0, 1) if isinstance(dm, (int, float)) else None}
                rs = st["wall_ms"] / 1e3 if isinstance(st.get("wall_ms"), (int, float)) else None
                self.add_point(scene, "photonbridge", curve["label"], p, r, exr, ref, rs, extra)

    def bench_reference(self, scene, ref):
        for spp in self.cfg["reference"]:
            if self.expired("%s reference %d spp" % (scene, spp)):
                continue
            tag = "%s_ref_%d" % (scene, spp)
            exr, js = os.path.join(self.work, tag + ".exr"), os.path.join(self.work, tag + ".json")
            # Seed 1: independent of the converged reference's seed 0.
            cmd = [self.exe, "reference", self.scene_path(scene), "-o", exr, "--width", str(self.width),
                   "--spp", str(spp), "--seed", "1", "--json", js, "-q"]
            r = run_point(cmd, os.path.join(self.work, tag + ".log"), self.timeout)
            st = read_json(js) or {}
            self.add_point(scene, "reference", "path tracing" + (" + SPPM" if st.get("mode") not in (None, "pt") else ""),
                           {"spp": spp, "seed": 1, "mode": st.get("mode")}, r, exr, ref, st.get("time_s"))

    def bench_povray(self, scene, ref):
        if not shutil.which("povray"):
            self.notes.append("POV-Ray: not installed")
            return
        pc = self.cfg["povray"]
        for q in pc.get(scene, pc["default"]):
            if self.expired("%s povray %s" % (scene, q)):
                continue
            tag = "%s_pov_%s" % (scene, q)
            pdir = os.path.join(self.work, tag)
            os.makedirs(pdir, exist_ok=True)
            pov, exr = os.path.join(pdir, "scene.pov"), os.path.join(self.work, tag + ".exr")
            e = run_point([self.exe, "export-pov", self.scene_path(scene), "-o", pov, "--width", str(self.width),
                           "--quality", q], os.path.join(self.work, tag + ".export.log"), 300)
            if e["rc"] != 0:
                self.add_point(scene, "povray", "quality presets", {"quality": q}, e, exr, ref)
                continue
            r = run_point(["sh", os.path.join(ROOT, "validation", "run_povray.sh"), pov, exr],
                          os.path.join(self.work, tag + ".log"), self.timeout)
            render_s = None
            try:
                for line in open(exr + ".log"):
                    if line.startswith("wall_s="):
                        render_s = float(line.split("=", 1)[1])
                os.unlink(exr + ".log")
            except (OSError, ValueError):
                pass
            self.add_point(scene, "povray", "quality presets", {"quality": q, "export_s": e["wall_s"]}, r, exr, ref,
                           render_s)
            shutil.rmtree(pdir, ignore_errors=True)

    def bench_cycles(self, scene, ref):
        blender = os.environ.get("BLENDER", "blender")
        if self.a.no_cycles:
            self.notes.append("Cycles: skipped (--no-cycles)")
            return
        if not shutil.which(blender):
            self.notes.append("Cycles: Blender not installed")
            return
        for spp in self.cfg["cycles"]:
            if self.expired("%s cycles %d" % (scene, spp)):
                continue
            tag = "%s_cycles_%d" % (scene, spp)
            exr = os.path.join(self.work, tag + ".exr")
            cmd = ["sh", os.path.join(ROOT, "validation", "run_cycles.sh"), scene, exr, "--width", str(self.width),
                   "--samples", str(spp)]
            r = run_point(cmd, os.path.join(self.work, tag + ".log"), self.timeout)
            st = read_json(exr + ".json") or {}
            for suffix in (".json", ".log"):
                if os.path.exists(exr + suffix):
                    os.unlink(exr + suffix)
            self.add_point(scene, "cycles", "path tracing (CPU)", {"samples": spp}, r, exr, ref, st.get("render_s"))

    # ---- pipeline internals (seed 000) ------------------------------------

    def leaf_sweep(self, scene):
        """Table 1: gather + LBVH time per leaf-size threshold, and T_auto."""
        s = self.cfg["leaf_setup"]
        rows = []
        for leaf in [0] + list(self.cfg["leaf_sizes"]):
            best = None
            for rep in range(s["repeat"]):
                tag = "%s_leaf_%d_%d" % (scene, leaf, rep)
                exr, js = os.path.join(self.work, tag + ".exr"), os.path.join(self.work, tag + ".json")
                cmd = [self.exe, "render", self.scene_path(scene), "-o", exr, "--width", str(s["width"]),
                       "--spp", str(s["spp"]), "--photons", str(s["photons"]), "--iterations",
                       str(s["iterations"]), "--json", js, "-q"] + self.dev
                if leaf:
                    cmd += ["--leaf-size", str(leaf)]
                r = run_point(cmd, os.path.join(self.work, tag + ".log"), self.timeout)
                st = read_json(js)
                if os.path.exists(exr):
                    os.unlink(exr)
                if r["rc"] != 0 or not st:
                    rows.append({"scene": scene, "leaf_size": leaf or "auto", "error": tail(r["out"])})
                    break
                pm = st["passes_ms"]
                row = {"scene": scene, "leaf_size": leaf or "auto", "t_auto": st["photons"]["t_auto"],
                       "leaf_used": st["photons"].get("leaf_size"), "leaves": st["photons"]["lbvh_leaves"],
                       "gather_ms": pm.get("gather"), "lbvh_ms": pm.get("lbvh_build"),
                       "wall_ms": st.get("wall_ms"), "k_pd": st["photons"]["k_pd"]}
                row["query_ms"] = (row["gather_ms"] or 0) + (row["lbvh_ms"] or 0)
                if best is None or row["query_ms"] < best["query_ms"]:
                    best = row
            if best:
                rows.append(best)
                self.log("leaf %-5s %s: gather %.1f ms + LBVH %.1f ms, %d leaves (T_auto %d)" % (
                    best["leaf_size"], scene, best["gather_ms"], best["lbvh_ms"], best["leaves"], best["t_auto"]))
        ok = [r for r in rows if "error" not in r]
        auto = [r for r in ok if r["leaf_size"] == "auto"]
        manual = [r for r in ok if r["leaf_size"] != "auto"]
        summary = {"scene": scene, "setup": s, "rows": rows}
        if auto and manual:
            b = min(manual, key=lambda r: r["query_ms"])
            summary.update({"t_auto": auto[0]["t_auto"], "best_manual_leaf": b["leaf_size"],
                            "best_manual_ms": b["query_ms"], "auto_ms": auto[0]["query_ms"],
                            "auto_fraction_of_best": b["query_ms"] / auto[0]["query_ms"]})
        return summary

    def kpd_histogram(self, scene):
        """Table 2's k_PD and Table 3's radius histogram, default settings."""
        tag = "%s_hist" % scene
        exr, js = os.path.join(self.work, tag + ".exr"), os.path.join(self.work, tag + ".json")
        cmd = [self.exe, "render", self.scene_path(scene), "-o", exr, "--width", str(self.width), "--spp", "4",
               "--iterations", "4", "--radius-histogram", "--json", js, "-q"] + self.dev
        r = run_point(cmd, os.path.join(self.work, tag + ".log"), self.timeout)
        st = read_json(js)
        if os.path.exists(exr):
            os.unlink(exr)
        if r["rc"] != 0 or not st:
            return {"scene": scene, "error": tail(r["out"])}
        ph = st["photons"]
        return {"scene": scene, "settings": "default photons (2^18/map), 4 maps, 4 spp", "k_pd": ph["k_pd"],
                "t_auto": ph["t_auto"], "stored": ph["stored"], "caustic": ph["caustic"],
                "histogram": ph.get("radius_histogram")}

    def lbvh_rates(self):
        exe = os.path.join(os.path.dirname(self.exe), "pb_bench_lbvh")
        if not os.access(exe, os.X_OK):
            self.notes.append("LBVH rates: %s not built" % exe)
            return []
        counts = ["%d" % c for c in self.cfg["lbvh_counts"]]
        r = run_point([exe, "--repeat", "3"] + self.dev + counts, os.path.join(self.work, "lbvh_rates.log"),
                      self.timeout)
        rows = []
        for line in r["out"].splitlines():
            if line.startswith("{"):
                try:
                    rows.append(json.loads(line))
                except ValueError:
                    pass
        for row in rows:
            self.log("LBVH %9d photons: %s" % (row["photons"], "%.2f M photons/s build, %.2f M keys/s sort" % (
                row["build_mphotons_s"], row["sort_mkeys_s"]) if "error" not in row else row["error"][:90]))
        return rows


# ---- summaries -------------------------------------------------------------


def time_to_psnr(pts, target):
    """Seconds at which one curve's PSNR first reaches `target` dB: linear
    in log(time) between the last point below and the first at or above.
    Returns (seconds, bound): bound '<=' when the first point is already
    above (the true time is at most that), None when never reached."""
    pts = sorted((p for p in pts if p.get("psnr_db") is not None), key=lambda p: p["wall_s"])
    prev = None
    for p in pts:
        if p["psnr_db"] >= target:
            if prev is None:
                return p["wall_s"], "<="
            t0, t1 = math.log(prev["wall_s"]), math.log(p["wall_s"])
            f = (target - prev["psnr_db"]) / (p["psnr_db"] - prev["psnr_db"])
            return math.exp(t0 + f * (t1 - t0)), "="
        prev = p
    return None, None


def curves(points):
    out = {}
    for p in points:
        if p.get("status") == "ok":
            out.setdefault((p["scene"], p["renderer"], p["config"]), []).append(p)
    return out


def summarise(points, scenes):
    """Per scene and threshold: each renderer's best time over its curves,
    and photonbridge / best peer."""
    cv = curves(points)
    table = []
    for s in scenes:
        for thr in THRESHOLDS_DB:
            row = {"scene": s, "psnr_db": thr, "renderers": {}}
            for (sc, rn, cf), pts in cv.items():
                if sc != s:
                    continue
                t, bound = time_to_psnr(pts, thr)
                cur = row["renderers"].get(rn)
                if t is not None and (cur is None or t < cur["time_s"]):
                    row["renderers"][rn] = {"time_s": t, "bound": bound, "config": cf}
            pb = row["renderers"].get("photonbridge")
            peers = [(row["renderers"][n]["time_s"], n) for n in PEERS if n in row["renderers"]]
            if pb and peers:
                best = min(peers)
                row["best_peer"] = best[1]
                row["ratio"] = pb["time_s"] / best[0]
                # A time reached at a sweep's first point is an upper bound.
                pb_b, peer_b = pb["bound"] == "<=", row["renderers"][best[1]]["bound"] == "<="
                row["ratio_bound"] = "?" if pb_b and peer_b else ("<=" if pb_b else (">=" if peer_b else "="))
            table.append(row)
    return table


def machine_info():
    info = {"hostname_hash": hashlib.sha1(platform.node().encode()).hexdigest()[:8], "kernel": platform.release(),
            "cores": os.cpu_count(), "python": sys.version.split()[0]}
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                info["cpu"] = line.split(":", 1)[1].strip()
                break
        for line in open("/proc/meminfo"):
            if line.startswith("MemTotal"):
                info["mem_gib"] = round(int(line.split()[1]) / 1048576.0, 1)
    except OSError:
        pass
    return info


def tool_versions(exe):
    def first(cmd, match=None):
        try:
            p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                               timeout=120)
        except (OSError, subprocess.TimeoutExpired):
            return None
        lines = [l.strip() for l in p.stdout.splitlines() if l.strip() and (not match or match in l)]
        return lines[0] if lines else None

    def deb(pkg):
        return first(["dpkg-query", "-W", "-f=${Version}", pkg])

    return {"photonbridge": first([exe, "--version"]),
            "povray": first(["povray", "--version"], "POV-Ray") if shutil.which("povray") else None,
            "blender": first([os.environ.get("BLENDER", "blender"), "--version"], "Blender")
            if shutil.which(os.environ.get("BLENDER", "blender")) else None,
            "mesa-vulkan-drivers": deb("mesa-vulkan-drivers"), "libembree3": deb("libembree3-3"),
            "matplotlib": deb("python3-matplotlib")}


def devices(exe):
    p = subprocess.run([exe, "info", "--devices"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       universal_newlines=True)
    out = []
    for line in p.stdout.splitlines():
        m = re.match(r"\s+(\d+)(\*?)\s+(.*?)\s{2,}(\S+)", line)
        if m:
            out.append({"index": int(m.group(1)), "default": bool(m.group(2)), "name": m.group(3),
                        "type": m.group(4)})
    return out


def slug(name):
    s = re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-")
    if s.startswith("llvmpipe"):
        s = "lavapipe"  # Mesa's CPU Vulkan; its version is in results.json
    return s[:48] or "device"


# ---- outputs ---------------------------------------------------------------

CSV_FIELDS = ["scene", "width", "renderer", "config", "params", "status", "wall_s", "render_s", "maxrss_mb",
              "psnr_db", "ssim", "rmse", "relmse", "ref_noise_psnr_db", "k_pd", "t_auto", "gpu_buffers_peak_mb",
              "load_1m", "error"]


def write_csv(path, points):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, CSV_FIELDS, extrasaction="ignore")
        w.writeheader()
        for p in points:
            row = dict(p)
            row["params"] = json.dumps(p.get("params"), separators=(",", ":"), sort_keys=True)
            w.writerow(row)


STYLE = {"photonbridge": "-o", "reference": "-s", "povray": "-^", "cycles": "-D"}


def plots(res, out):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return ["matplotlib not importable (install python3-matplotlib, run with /usr/bin/python3): no plots"]
    files = []
    cv = curves(res["points"])
    for s in res["scenes"]:
        fig, ax = plt.subplots(1, 2, figsize=(12, 4.6))
        for (sc, rn, cf), pts in sorted(cv.items()):
            if sc != s:
                continue
            pts = sorted(pts, key=lambda p: p["wall_s"])
            t = [p["wall_s"] for p in pts]
            ax[0].plot(t, [p["psnr_db"] for p in pts], STYLE.get(rn, "-x"), label="%s: %s" % (rn, cf), ms=4)
            ax[1].plot(t, [max(p["relmse"], 1e-8) for p in pts], STYLE.get(rn, "-x"), ms=4)
        ref = res["references"].get(s, {})
        noise = (ref.get("noise") or {}).get("psnr_db")
        for thr in THRESHOLDS_DB:
            ax[0].axhline(thr, color="0.8", lw=0.8, zorder=0)
        if noise:
            ax[0].axhline(noise, color="k", ls=":", lw=1, label="converged reference's own noise")
        ax[0].set_xscale("log")
        ax[0].set_xlabel("wall time per image, s (log)")
        ax[0].set_ylabel("PSNR vs converged reference, dB (display)")
        ax[1].set_xscale("log")
        ax[1].set_yscale("log")
        ax[1].set_xlabel("wall time per image, s (log)")
        ax[1].set_ylabel("relMSE (scene-linear, log)")
        for a_ in ax:
            a_.grid(True, which="both", lw=0.3)
        ax[0].legend(fontsize=7, loc="lower right")
        fig.suptitle("%s, %d px wide, %s" % (s, res["width"], res["device"]["name"]), fontsize=10)
        fig.tight_layout()
        for ext in ("svg", "png"):
            fn = "error_vs_time_%s.%s" % (s, ext)
            fig.savefig(os.path.join(out, fn), dpi=110)
            files.append(fn)
        plt.close(fig)
    # Fig. 5: per-pass breakdown of one representative photonbridge point per scene.
    rows = res["internals"]["passes"]
    if rows:
        names = []
        for r in rows:
            for k in r["passes_ms"]:
                if k not in names:
                    names.append(k)
        fig, ax = plt.subplots(figsize=(8.5, 1.0 + 0.5 * len(rows)))
        left = [0.0] * len(rows)
        for k in names:
            v = [r["passes_ms"].get(k, 0.0) or 0.0 for r in rows]
            ax.barh([r["scene"] for r in rows], v, left=left, label=k)
            left = [a + b for a, b in zip(left, v)]
        ax.set_xlabel("GPU ms per image (timestamps, summed over maps and samples)")
        ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
        fig.tight_layout()
        for ext in ("svg", "png"):
            fig.savefig(os.path.join(out, "passes.%s" % ext), dpi=110)
            files.append("passes.%s" % ext)
        plt.close(fig)
    lb = [r for r in res["internals"]["lbvh_rates"] if "error" not in r]
    if lb:
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot([r["photons"] for r in lb], [r["build_mphotons_s"] for r in lb], "-o", label="LBVH build, M photons/s")
        ax.plot([r["photons"] for r in lb], [r["sort_mkeys_s"] for r in lb], "-s", label="radix sort, M keys/s")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("photons")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=8)
        ax.set_title(res["device"]["name"], fontsize=9)
        fig.tight_layout()
        for ext in ("svg", "png"):
            fig.savefig(os.path.join(out, "lbvh_rates.%s" % ext), dpi=110)
            files.append("lbvh_rates.%s" % ext)
        plt.close(fig)
    ls = [x for x in res["internals"]["leaf_sweep"] if x.get("rows")]
    if ls:
        fig, ax = plt.subplots(figsize=(6, 4))
        for x in ls:
            m = [r for r in x["rows"] if "error" not in r and r["leaf_size"] != "auto"]
            ax.plot([r["leaf_size"] for r in m], [r["query_ms"] for r in m], "-o", label=x["scene"])
            if x.get("auto_ms"):
                ax.plot([x["t_auto"]], [x["auto_ms"]], "k*", ms=10)
        ax.set_xscale("log", base=2)
        ax.set_xlabel("leaf-size threshold (star: T_auto)")
        ax.set_ylabel("gather + LBVH build, GPU ms")
        ax.grid(True, which="both", lw=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        for ext in ("svg", "png"):
            fig.savefig(os.path.join(out, "leaf_sweep.%s" % ext), dpi=110)
            files.append("leaf_sweep.%s" % ext)
        plt.close(fig)
    return files


def fmt_t(r):
    if not r:
        return "not reached"
    return "%s%.2f s" % ("&le; " if r["bound"] == "<=" else "", r["time_s"])


def point_photons(p):
    """'emitted / stored, k_PD' of a photonbridge point (emitted: paths per
    map x maps), '-' for the other renderers."""
    if p.get("renderer") != "photonbridge":
        return "-"
    pr = p.get("params") or {}
    em = pr.get("photons", 0) * pr.get("iterations", 0)
    st, kpd = p.get("photons_stored"), p.get("k_pd")
    return "%s / %s, %s" % ("{:,}".format(em) if em else "-", "{:,}".format(st) if isinstance(st, int) else "-",
                            "%.1f" % kpd if isinstance(kpd, (int, float)) else "-")


def pb_point_photons(cv, row):
    """The photons of the photonbridge point that first reached the row's
    PSNR on the curve behind its best time."""
    pb = row["renderers"].get("photonbridge")
    if not pb:
        return "-"
    pts = sorted(cv.get((row["scene"], "photonbridge", pb["config"]), []), key=lambda p: p["wall_s"])
    at = next((p for p in pts if p.get("psnr_db") is not None and p["psnr_db"] >= row["psnr_db"]), None)
    return point_photons(at) if at else "-"


def markdown(res, rel):
    """The report; rel: the results folder relative to the Markdown file."""
    L = []
    m, dev = res["machine"], res["device"]
    L.append("# Speed against error\n")
    L.append("Generated by `bench/run_bench.py` (%s run, `make %s`) on %s. Do not edit: rerun the benchmark.\n"
             % (res["mode"], {"full": "bench", "quick": "bench-quick", "estimators": "bench-estimators"}.get(res["mode"], "bench-quick"), res["finished"]))
    L.append("- Machine: %s, %s cores, %s GiB; Vulkan device **%s** (%s)%s." % (
        m.get("cpu"), m.get("cores"), m.get("mem_gib"), dev["name"], dev.get("type"),
        ", a CPU implementation on the same cores as the CPU renderers" if dev.get("type") == "cpu" else ""))
    L.append("- Load average (1 min) at start / end: %s / %s (%d cores). %s" % (
        res["load_start"], res["load_end"], m.get("cores") or 0, res["load_note"]))
    L.append("- Tools: " + "; ".join("%s: %s" % (k, v) for k, v in res["versions"].items() if v) + ".")
    L.append("- Scenes at %d px wide; every point a separate process timed spawn to exit (start-up, scene "
             "load and EXR write included), peak RSS: %s. Error: `photonbridge compare` against the "
             "converged reference (PSNR/SSIM on the sRGB display image, relMSE scene-linear). On a CPU Vulkan device the "
             "GPU memory is part of the RSS; on a discrete GPU it is not." % (res["width"], res["peak_memory"]))
    L.append("- Results: [`%s/results.json`](%s/results.json), [`results.csv`](%s/results.csv); "
             "plots in the same folder.\n" % (rel, rel, rel))
    L.append("## Time to reach 25, 30 and 35 dB PSNR\n")
    L.append("Best over each renderer's configurations (interpolated in log time between the sweep's points; "
             "&le;: already reached at the first point). Ratio = photonbridge / best peer, within this run "
             "(< 1: photonbridge faster; &le;/&ge;: a bound, because one side reached the level at its cheapest point; "
             "~: both did).\n")
    L.append("| scene | ref. noise | dB | photonbridge | its point: photons emitted / stored, k_PD | reference (CPU) "
             "| POV-Ray | Cycles | photonbridge / best peer |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    cv = curves(res["points"])
    for row in res["summary"]:
        rr = row["renderers"]
        noise = ((res["references"].get(row["scene"]) or {}).get("noise") or {}).get("psnr_db")
        L.append("| %s | %s | %g | %s | %s | %s | %s | %s | %s |" % (
            row["scene"], "%.1f dB" % noise if noise else "-", row["psnr_db"],
            fmt_t(rr.get("photonbridge")), pb_point_photons(cv, row), fmt_t(rr.get("reference")),
            fmt_t(rr.get("povray")), fmt_t(rr.get("cycles")),
            "**%s%.2f** (vs %s)" % ({"=": "", "<=": "&le; ", ">=": "&ge; ", "?": "~"}[row["ratio_bound"]],
                                   row["ratio"], row["best_peer"]) if row.get("ratio") else "-"))
    L.append("\nThe configuration behind each best time is in results.json (`summary`). A PSNR near the "
             "converged reference's own noise PSNR (column 2) is limited by the reference, not by the "
             "renderer.\n")
    L.append("## Best PSNR reached and its cost\n")
    L.append("| scene | renderer | configuration | best PSNR dB | SSIM | at s | photons emitted / stored, k_PD "
             "| peak RSS MiB | GPU buffers MiB |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    for (sc, rn, cf), pts in sorted(curves(res["points"]).items()):
        b = max(pts, key=lambda p: p["psnr_db"])
        L.append("| %s | %s | %s | %.2f | %.3f | %.2f | %s | %s | %s |" % (
            sc, rn, cf, b["psnr_db"], b["ssim"], b["wall_s"], point_photons(b), b["maxrss_mb"],
            b["gpu_buffers_peak_mb"] if b.get("gpu_buffers_peak_mb") is not None else "-"))
    for s in res["scenes"]:
        if "error_vs_time_%s.svg" % s in res["plots"]:
            L.append("\n![%s](%s/error_vs_time_%s.svg)" % (s, rel, s))
    it = res["internals"]
    L.append("\n## Pipeline internals (seed 000)\n")
    if it["passes"]:
        L.append("Per-pass GPU time (Fig. 5), one point per scene (%s):\n" % it["passes"][0]["what"])
        names = []
        for r in it["passes"]:
            names += [k for k in r["passes_ms"] if k not in names]
        L.append("| scene | " + " | ".join(names) + " | process wall ms |")
        L.append("|---|" + "---|" * (len(names) + 1))
        for r in it["passes"]:
            L.append("| %s | %s | %.0f |" % (r["scene"], " | ".join(
                "%.1f" % r["passes_ms"][k] if isinstance(r["passes_ms"].get(k), (int, float)) else "-"
                for k in names), r["wall_ms"]))
        if "passes.svg" in res["plots"]:
            L.append("\n![passes](%s/passes.svg)\n" % rel)
    for x in it["leaf_sweep"]:
        s = x["setup"]
        kp = next((r.get("k_pd") for r in x["rows"] if r.get("k_pd") is not None), None)
        L.append("Leaf-size sweep (Table 1), %s, %d px, %d photons/map, %d maps, %d spp (k_PD %s); gather + LBVH "
                 "build GPU ms (best of %d):\n" % (x["scene"], s["width"], s["photons"], s["iterations"], s["spp"],
                                                   "%.1f" % kp if kp is not None else "-", s["repeat"]))
        L.append("| leaf size | " + " | ".join(str(r["leaf_size"]) for r in x["rows"]) + " |")
        L.append("|---|" + "---|" * len(x["rows"]))
        L.append("| ms | " + " | ".join("%.1f" % r["query_ms"] if "query_ms" in r else "failed" for r in x["rows"])
                 + " |")
        L.append("| leaves | " + " | ".join(str(r.get("leaves", "-")) for r in x["rows"]) + " |")
        if x.get("auto_fraction_of_best"):
            L.append("\nT_auto = %d; best manual threshold %s (%.1f ms); T_auto reaches **%.0f %%** of the best "
                     "manual speed (paper: 97-100 %%).\n" % (x["t_auto"], x["best_manual_leaf"], x["best_manual_ms"],
                                                             100 * x["auto_fraction_of_best"]))
    if "leaf_sweep.svg" in res["plots"]:
        L.append("![leaf sweep](%s/leaf_sweep.svg)\n" % rel)
    hs = [h for h in it["histograms"] if h.get("histogram")]
    if hs:
        L.append("k_PD (photons per gather) and footprint radii (Table 3), %s. Radii in bins of r_max / 20; the "
                 "last column counts footprints at the clamp r_max (18 Delta R by default: Delta = 2 sqrt(pi / paths), R the scene radius):\n"
                 % hs[0]["settings"])
        L.append("| scene | k_PD | T_auto | stored | r_max m | " + " | ".join(
            "<%d%%" % (5 * (i + 1)) for i in range(20)) + " | at r_max |")
        L.append("|---|---|---|---|---|" + "---|" * 21)
        for h in hs:
            c = h["histogram"]["counts"]
            L.append("| %s | %.1f | %d | %d | %.3g | %s |" % (h["scene"], h["k_pd"], h["t_auto"], h["stored"],
                                                             h["histogram"]["r_max_m"],
                                                             " | ".join(str(v) for v in c)))
        L.append("")
    lb = it["lbvh_rates"]
    if lb:
        L.append("LBVH build and radix-sort rates against photon count (bench/lbvh.c, synthetic photons on a "
                 "10 x 10 m floor, about 20 footprints over a point, best of 3, GPU timestamps):\n")
        L.append("| photons | build ms | M photons/s | sort ms | M keys/s | T_auto |")
        L.append("|---|---|---|---|---|---|")
        for r in lb:
            if "error" in r:
                L.append("| %d | failed: %s | | | | |" % (r["photons"], r["error"][:110]))
            else:
                L.append("| %d | %.2f | %.2f | %.2f | %.2f | %d |" % (r["photons"], r["build_ms"], r["build_mphotons_s"],
                                                                   r["sort_ms"], r["sort_mkeys_s"], r["t_auto"]))
        if "lbvh_rates.svg" in res["plots"]:
            L.append("\n![LBVH rates](%s/lbvh_rates.svg)\n" % rel)
    L += tracer_section(res, rel)
    L += estimators_section(res)
    L.append("## Settings\n")
    L.append("Converged references (`photonbridge reference --estimate-noise`, seed 0; the reference sweep uses "
             "seed 1):\n")
    L.append("| scene | size | spp | mode | time s | noise PSNR dB | noise relMSE |")
    L.append("|---|---|---|---|---|---|---|")
    for s, r in sorted(res["references"].items()):
        n = r.get("noise") or {}
        L.append("| %s | %sx%s | %s | %s | %s | %s | %s |" % (s, r.get("width"), r.get("height"), r["spp"], r["mode"],
                                                         "%.1f" % r["time_s"] if r.get("time_s") else "-",
                                                         "%.1f" % n["psnr_db"] if n.get("psnr_db") else "-",
                                                         "%.2g" % n["relmse"] if n.get("relmse") else "-"))
    L.append("\nSweeps: `%s`" % json.dumps(res["config"], separators=(", ", ": ")))
    if res["notes"]:
        L.append("\nNotes:\n")
        L += ["- " + n for n in res["notes"]]
    others = []
    rdir = os.path.join(ROOT, "bench", "results")
    for d in sorted(os.listdir(rdir)) if os.path.isdir(rdir) else []:
        for m_ in ("full", "quick"):
            f = os.path.join(rdir, d, m_, "results.json")
            if os.path.isfile(f) and os.path.abspath(os.path.dirname(f)) != os.path.abspath(res["out_abs"]):
                others.append("bench/results/%s/%s" % (d, m_))
    if others:
        L.append("\nOther result sets (other devices or modes; their own BENCHMARKS.md, never compared with this "
                 "one in absolute time): " + ", ".join("`%s`" % o for o in others) + ".")
    failed = [p for p in res["points"] if p.get("status") != "ok"]
    if failed:
        L.append("\nFailed points (%d):\n" % len(failed))
        L += ["- %s %s %s: %s" % (p["scene"], p["renderer"], json.dumps(p["params"]), p.get("error", "")[:160])
              for p in failed]
    return "\n".join(L) + "\n"


def tracer_section(res, rel_out):
    """The image-space photon tracer beside the BVH tracer (seed
    003): bench/tracer_images.py's last results on this device
    (bench/results/DEVICE/tracer_images/tracer_images.json), with its misses."""
    d = os.path.join(ROOT, "bench", "results", slug(res["device"]["name"]), "tracer_images")
    js = read_json(os.path.join(d, "tracer_images.json"))
    if not js:
        return []
    sys.path.insert(0, HERE)
    import tracer_images
    # Links relative to the Markdown file: rel_out is the results folder
    # relative to it.
    md_dir = os.path.normpath(os.path.join(os.path.abspath(res["out_abs"]), os.path.relpath(".", rel_out)))
    rel = os.path.relpath(d, md_dir)
    runs = js.get("runs", {})
    L = ["## The image-space photon tracer (seed 003) beside the BVH tracer\n",
         "`--tracer images` (k = 8 cube environment maps of 128^2 texels per face, no hierarchy) against "
         "`--tracer bvh`, from `bench/tracer_images.py` on this device (its own runs, not this sweep's: %s; "
         "[`%s/TRACER_IMAGES.md`](%s/TRACER_IMAGES.md) has every table). The miss rate is the share of photon "
         "segments no map confirmed (`photons.image_miss_rate`); the uncovered share the part of the "
         "candidates' view no centre sees (eq. 1)." % (
             "; ".join("%s %s UTC, load %s" % (k, v["date"][:16].replace("T", " "),
                                                "%.1f" % v["load_start"] if v.get("load_start") is not None
                                                else "?")
                       for k, v in sorted(runs.items())) or "date unknown", rel, rel)]
    L += tracer_images.samples_md(js, rel + "/")
    L.append("")
    return L


def estimator_of(cfg_extra):
    """The density estimator a point ran (`--estimator NAME`, with
    ` directional` for --vsch-directional), None without the option."""
    if "--estimator" not in cfg_extra:
        return None
    name = cfg_extra[cfg_extra.index("--estimator") + 1]
    return name + (" directional" if "--vsch-directional" in cfg_extra else "")


def estimators_section(res):
    """The density estimators side by side: per scene, every
    curve that names an estimator, on the same photon maps: its time to
    each PSNR, the ratio to the LBVH gather's at the same level (within this
    run), its best PSNR and the estimator's GPU ms per sample there."""
    cv = curves(res["points"])
    rows = {}
    for (sc, rn, cf), pts in cv.items():
        est = estimator_of(pts[0]["params"].get("extra", [])) if rn == "photonbridge" else None
        if est:
            rows.setdefault(sc, []).append((est, cf, pts))
    if not rows or max(len(v) for v in rows.values()) < 2:
        return []
    L = ["## Density estimators side by side\n",
         "Every curve of this run that picks a density estimator (`render --estimator`), on the same photon maps "
         "(same photons per map, maps and spp; the tracer's seed is the same, so the maps are the same up to the "
         "store order). Time to each PSNR interpolated as above; x lbvh: the ratio to the LBVH gather's time to "
         "the same PSNR in this run (> 1: slower). Estimator ms: the estimate's GPU ms (`gather` in the per-pass "
         "timings: every sample's estimate, plus for lbvh and knn the LBVH build) at the best point.\n"]
    hdr = "| scene | estimator | " + " | ".join("%g dB (x lbvh)" % t for t in THRESHOLDS_DB) + \
          " | best PSNR / SSIM | at s | stored, k_PD | estimator ms |"
    L.append(hdr)
    L.append("|" + "---|" * (hdr.count("|") - 1))
    for sc in res["scenes"]:
        ests = sorted(rows.get(sc, []), key=lambda r: (r[0] != "lbvh", r[0]))
        base = next((r for r in ests if r[0] == "lbvh"), None)
        for est, cf, pts in ests:
            cells = []
            for thr in THRESHOLDS_DB:
                t, b = time_to_psnr(pts, thr)
                if t is None:
                    cells.append("not reached")
                    continue
                c = "%s%.2f s" % ("&le; " if b == "<=" else "", t)
                if base and est != "lbvh":
                    tb, bb = time_to_psnr(base[2], thr)
                    c += " (lbvh not)" if tb is None else " (%s%.2f)" % ("~" if b == "<=" or bb == "<=" else "",
                                                                       t / tb)
                cells.append(c)
            best = max((p for p in pts if p.get("psnr_db") is not None), key=lambda p: p["psnr_db"], default=None)
            if best is None:
                continue
            pm = best.get("passes_ms") or {}
            est_ms = (pm.get("gather") or 0) + (pm.get("estimator_build") or 0)
            L.append("| %s | %s | %s | %.2f / %.3f | %.2f | %s, %s | %s |" % (
                sc, est, " | ".join(cells), best["psnr_db"], best.get("ssim") or 0, best["wall_s"],
                "{:,}".format(best["photons_stored"]) if best.get("photons_stored") is not None else "-",
                "%.1f" % best["k_pd"] if best.get("k_pd") is not None else "-",
                "%.0f" % est_ms if pm else "-"))
    L.append("")
    return L


def note_load(load_start, cores):
    """The load before the run started (the run itself then adds about one
    per core, so the load at the end says little about other work)."""
    if load_start is not None and load_start > 0.5 * cores:
        return ("Other work was running when the run started (load %.2f on %d cores), so times carry extra "
                "noise." % (load_start, cores))
    return "The machine was otherwise quiet when the run started (the load at the end is mostly the run's own)."


def write_reports(res, out, md):
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump({k: v for k, v in res.items() if k != "out_abs"}, f, indent=1)
    write_csv(os.path.join(out, "results.csv"), res["points"])
    with open(os.path.join(out, "BENCHMARKS.md"), "w") as f:
        f.write(markdown(res, "."))
    if md:
        with open(md, "w") as f:
            f.write(markdown(res, os.path.relpath(out, os.path.dirname(os.path.abspath(md)))))


def rebuild(out, md):
    """--rebuild-report: the tables, notes and plots again from DIR/results.json."""
    res = read_json(os.path.join(out, "results.json"))
    if not res:
        print("run_bench: %s: no results.json" % out, file=sys.stderr)
        return 2
    res["out_abs"] = os.path.abspath(out)
    res["load_note"] = note_load(res.get("load_start"), res["machine"].get("cores") or 1)
    res["summary"] = summarise(res["points"], res["scenes"])
    res["plots"] = plots(res, out)
    if res["plots"] and not res["plots"][0].endswith((".svg", ".png")):
        res["notes"].append(res["plots"].pop())
    write_reports(res, out, md or (os.path.join(ROOT, "BENCHMARKS.md") if res["mode"] == "full" else None))
    return 0


def main(argv):
    ap = argparse.ArgumentParser(prog="run_bench.py", description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="a few minutes: 2 scenes, small images, few points "
                    "(= --mode quick)")
    ap.add_argument("--mode", choices=sorted(CONFIGS), default=None, help="full (default), quick or smoke (tests)")
    ap.add_argument("--keep-work", action="store_true", help="keep the per-point logs and JSON (DIR/work)")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "photonbridge"))
    ap.add_argument("--device", type=int, help="Vulkan device index for photonbridge (info --devices)")
    ap.add_argument("--scenes", help="comma-separated sample names (default: the mode's list)")
    ap.add_argument("--width", type=int, default=0)
    ap.add_argument("--ref-spp", type=int, default=0, help="converged reference spp (default: the mode's)")
    ap.add_argument("--out", help="results folder (default bench/results/DEVICE/MODE)")
    ap.add_argument("--cache", default=os.path.join(HERE, "cache"))
    ap.add_argument("--markdown", help="also write the report here (default: BENCHMARKS.md for a full run)")
    ap.add_argument("--no-cycles", action="store_true")
    ap.add_argument("--refresh-references", action="store_true", help="render the converged references again")
    ap.add_argument("--references-only", action="store_true", help="only render (or find) the cached converged "
                    "references, e.g. ahead of a timed run")
    ap.add_argument("--no-internals", action="store_true")
    ap.add_argument("--note", action="append", default=[], help="a line for the report's notes")
    ap.add_argument("--minutes", type=float, default=0, help="skip (and list) the renderer sweeps' points that "
                    "would start after this many minutes (0: no limit); the internals always run")
    ap.add_argument("--rebuild-report", metavar="DIR", help="only rewrite DIR's tables, plots and BENCHMARKS.md "
                    "from its results.json (after a change to the report code)")
    a = ap.parse_args(argv)
    if a.rebuild_report:
        return rebuild(a.rebuild_report, a.markdown)
    mode = a.mode or ("quick" if a.quick else "full")
    cfg = CONFIGS[mode]
    if not os.access(a.exe, os.X_OK):
        print("run_bench: %s: no photonbridge executable (build first, or --exe)" % a.exe, file=sys.stderr)
        return 2
    devs = devices(os.path.abspath(a.exe))
    dev = next((d for d in devs if (d["index"] == a.device if a.device is not None else d["default"])), None)
    if not dev:
        print("run_bench: no Vulkan device%s (photonbridge info --devices)" %
              (" %d" % a.device if a.device is not None else ""), file=sys.stderr)
        return 2
    if not a.out:
        a.out = os.path.join(HERE, "results", slug(dev["name"]), mode)
    scenes = a.scenes.split(",") if a.scenes else cfg["scenes"]
    for s in scenes:
        if not os.path.isfile(os.path.join(ROOT, "samples", s, s + ".gltf")):
            print("run_bench: %s: no such sample" % s, file=sys.stderr)
            return 2
    b = Bench(a, cfg)
    build_peak_helper(b.cache)
    b.version = (subprocess.run([b.exe, "--version"], stdout=subprocess.PIPE, universal_newlines=True).stdout
                 .strip())
    t_start = time.time()
    load_start = loadavg()
    b.log("%s run, device %d: %s, %d px, scenes %s -> %s" % (mode, dev["index"], dev["name"], b.width,
                                                            ",".join(scenes), os.path.relpath(b.out, ROOT)))
    refs = {}
    for s in scenes:  # references first: they are cached, and not timed
        refs[s] = b.reference(s)
    if a.references_only:
        return 0
    for s in scenes:
        b.bench_photonbridge(s, refs[s])
        b.bench_reference(s, refs[s])
        b.bench_povray(s, refs[s])
        b.bench_cycles(s, refs[s])
    internals = {"passes": [], "leaf_sweep": [], "histograms": [], "lbvh_rates": []}
    # Fig. 5: the photonbridge point of the first curve with 4 maps, per scene.
    first = cfg["photonbridge"][0]["label"]
    for s in scenes:
        cand = [p for p in b.points if p["scene"] == s and p["renderer"] == "photonbridge" and p["config"] == first
                and p.get("passes_ms")]
        if cand:
            four = [p for p in cand if p["params"]["iterations"] == 4]
            p = four[0] if four else max(cand, key=lambda p: p["params"]["iterations"])
            pm = {k: v for k, v in p["passes_ms"].items() if k not in ("gpu_total", "upload", "bvh_build")}
            internals["passes"].append({"scene": s, "what": "%s, %d maps, %d spp, %d px" % (
                                            first, p["params"]["iterations"], p["params"]["spp"], b.width),
                                        "params": p["params"], "passes_ms": pm, "wall_ms": 1e3 * p["wall_s"]})
    if not a.no_internals:
        for s in cfg["leaf_scenes"]:
            if s in scenes:
                internals["leaf_sweep"].append(b.leaf_sweep(s))
        for s in scenes:
            internals["histograms"].append(b.kpd_histogram(s))
        internals["lbvh_rates"] = b.lbvh_rates()
    load_end = loadavg()
    load_note = note_load(load_start, os.cpu_count() or 1)
    res = {"mode": mode, "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(t_start)),
           "finished": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "duration_s": round(time.time() - t_start),
           "machine": machine_info(), "device": dev, "devices": devs, "versions": tool_versions(b.exe),
           "load_start": load_start, "load_end": load_end, "load_note": load_note, "width": b.width,
           "scenes": scenes, "config": {k: v for k, v in cfg.items()}, "references": refs, "points": b.points,
           "internals": internals, "notes": b.notes + a.note + (
               ["stopped by --minutes %g: %d points skipped (%s)" % (a.minutes, len(b.skipped), "; ".join(b.skipped))]
               if b.skipped else []), "skipped": b.skipped, "peak_memory": PEAK["how"], "out": os.path.relpath(b.out, ROOT)}
    res["summary"] = summarise(b.points, scenes)
    res["out_abs"] = b.out
    res["plots"] = plots(res, b.out)
    if res["plots"] and not res["plots"][0].endswith((".svg", ".png")):
        res["notes"].append(res["plots"].pop())
    if not a.keep_work:
        shutil.rmtree(b.work, ignore_errors=True)
    md = a.markdown or (os.path.join(ROOT, "BENCHMARKS.md") if mode == "full" else None)
    write_reports(res, b.out, md)
    b.log("done in %d s: %s%s" % (res["duration_s"], os.path.relpath(os.path.join(b.out, "BENCHMARKS.md"), ROOT),
                                  (" and " + os.path.relpath(md, ROOT)) if md else ""))
    for row in res["summary"]:
        if row.get("ratio"):
            b.log("%s %g dB: photonbridge / best peer (%s) %s %.2f" % (
                row["scene"], row["psnr_db"], row["best_peer"], row["ratio_bound"], row["ratio"]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
