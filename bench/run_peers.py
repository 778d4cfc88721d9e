#!/usr/bin/env python3
"""Speed against error, the peers: LuxCoreRender, Mitsuba 3 and Cycles 4.5
beside photonbridge's Embree reference (and its GPU pipeline), one run.

    python3 bench/run_peers.py [--mode full|tiny] [--scenes a,b] [--renderers r,s] [--width W]
                               [--threads N] [--out DIR] [--markdown FILE] [--minutes M]
                               [--no-photonbridge]

For each scene at one resolution every renderer below renders a sweep of
points (each its own child process, timed from spawn to exit, as
bench/run_bench.py times its renderers), and each image is compared with
one converged Embree reference (run_bench.py's, cached under bench/cache/):
PSNR and SSIM on the display image (`photonbridge compare`, the shared OCIO
view) and HDR-FLIP on the scene-linear image (validation/flip_mean.py, NVIDIA FLIP
1.7 in tools/flip). Renderers:

  reference     photonbridge's Embree path tracer (+ SPPM on caustic scenes),
                spp sweep, seed 1 (the converged reference has seed 0)
  photonbridge  the GPU pipeline (Vulkan device 0), one photon budget
                (skipped with --no-photonbridge)
  luxcore-photongi  LuxCore 2.11 PATHCPU + PhotonGI indirect and caustic
                caches (validation/peer_render.py --engine photongi)
  luxcore-bidirvm   LuxCore 2.11 BIDIRVMCPU (vertex connection and merging)
  mitsuba       Mitsuba 3 `path` integrator, scalar_rgb
  cycles        Cycles 4.5 (bpy 4.5, tools/bpy45) on the glTF through Blender's
                importer with glTF's materials rebuilt (validation/cycles_gltf.py)

LuxCore and Mitsuba render `photonbridge export-peer`'s dump of the scene
(written once per scene, not timed). Every renderer gets --threads worker
threads (default 1: the machine is shared): `reference --threads`,
LuxCore native.threads.count, Cycles' fixed thread count, lavapipe's
LP_NUM_THREADS; Mitsuba's Dr.Jit pool cannot run with fewer than two
workers here (peer_render.py), so its process is pinned to --threads CPUs
with sched_setaffinity instead.

Writes DIR/results.json (every point with settings and timings, versions,
machine, load) and DIR/PEERS.md (the tables); --markdown FILE writes the
tables there too. DIR defaults to bench/results/lavapipe/peers (or
peers_tiny). Times to 25/30/35 dB are interpolated in log time between the
two points around the threshold (run_bench.time_to_psnr), never
extrapolated past a sweep's last point; the ratio is the peer's time over
the Embree reference's, both from this run.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import run_bench as rb  # noqa: E402

THRESHOLDS_DB = rb.THRESHOLDS_DB
FLIP_THRESHOLDS = (0.2, 0.1)
TOOLS = os.path.join(ROOT, "tools")
PY = {"luxcore": os.path.join(TOOLS, "luxcore", "bin", "python"),
      "mitsuba": os.path.join(TOOLS, "mitsuba3", "bin", "python"),
      "flip": os.path.join(TOOLS, "flip", "bin", "python"),
      "bpy45": os.path.join(TOOLS, "bpy45", "bin", "python")}
RENDERERS = ("reference", "photonbridge", "luxcore-photongi", "luxcore-bidirvm", "mitsuba", "cycles")

MODES = {
    "full": {
        "width": 128,
        "scenes": ["cornell_box", "cornell_caustics", "spot_room", "ring"],
        "reference_spp": {"cornell_box": 4096, "default": 2048},
        "reference": [4, 16, 64, 256, 1024],
        "photonbridge": [(1 << 16, 1, 4), (1 << 16, 4, 8)],
        # PhotonGI: photon.maxcount, indirect.haltthreshold, caustic.maxsize.
        "photongi": {"photons": 2000000, "halt": 0.05, "indirect_maxsize": 0, "caustic": 100000,
                     "spp": [4, 32]},
        "bidirvm": {"light_paths": 16384, "spp": [1, 4]},
        "mitsuba": [4, 16, 64, 256],
        "cycles": [4, 16, 64, 256],
        "timeout_s": 300,
    },
    # The ctest's configuration (tests/peers.cmake, bench_peers_tiny): one
    # scene, 32 px, a few samples; structure only, no timing claims.
    "tiny": {
        "width": 32,
        "scenes": ["cornell_box"],
        "reference_spp": {"default": 256},
        "reference": [4, 32],
        "photonbridge": [],
        "photongi": {"photons": 100000, "halt": 0.15, "indirect_maxsize": 20000, "caustic": 20000, "spp": [4]},
        "bidirvm": {"light_paths": 1024, "spp": [4]},
        "mitsuba": [4, 64],
        "cycles": [4],
        "timeout_s": 120,
    },
}


class PeerBench(rb.Bench):
    def __init__(self, a, cfg):
        cfg = dict(cfg)
        cfg["reference"] = cfg["reference"]
        super().__init__(a, cfg)
        self.threads = a.threads
        self.flip_ok = os.access(PY["flip"], os.X_OK)
        if not self.flip_ok:
            self.notes.append("FLIP: tools/flip missing (scripts/install-deps.sh): no FLIP column")
        try:
            cpus = sorted(os.sched_getaffinity(0))
        except AttributeError:
            cpus = list(range(os.cpu_count() or 1))
        self.pin = cpus[:max(1, self.threads)]

    def compare(self, test, ref, tag):
        m = super().compare(test, ref, tag)
        if self.flip_ok and "error" not in m:
            r = rb.run_point([PY["flip"], os.path.join(os.path.dirname(HERE), "validation", "flip_mean.py"), ref, test],
                             os.path.join(self.work, tag + ".flip.log"), 120)
            try:
                line = [l for l in r["out"].splitlines() if l.startswith("{")][-1]
                res = json.loads(line)["results"][0]
                m["flip_hdr"] = res.get("hdr_flip_mean")
                m["flip_nonfinite"] = res.get("nonfinite")
                if "error" in res:
                    m["flip_error"] = res["error"]
            except (IndexError, ValueError, KeyError):
                m["flip_error"] = rb.tail(r["out"])
        return m

    def env(self, **kw):
        e = dict(os.environ)
        e["PATH"] = ":".join(p for p in e.get("PATH", "").split(":") if "pyenv" not in p)
        e.update({k: str(v) for k, v in kw.items()})
        return e

    # ---- the Embree reference and the GPU pipeline -----------------------

    def bench_reference(self, scene, ref):
        for spp in self.cfg["reference"]:
            if self.expired("%s reference %d spp" % (scene, spp)):
                continue
            tag = "%s_ref_%d" % (scene, spp)
            exr, js = os.path.join(self.work, tag + ".exr"), os.path.join(self.work, tag + ".json")
            cmd = [self.exe, "reference", self.scene_path(scene), "-o", exr, "--width", str(self.width),
                   "--spp", str(spp), "--seed", "1", "--threads", str(self.threads), "--json", js, "-q"]
            r = rb.run_point(cmd, os.path.join(self.work, tag + ".log"), self.timeout)
            st = rb.read_json(js) or {}
            self.add_point(scene, "reference", "Embree path tracing" + (
                " + SPPM" if st.get("mode") not in (None, "pt") else ""),
                {"spp": spp, "seed": 1, "mode": st.get("mode"), "threads": self.threads}, r, exr, ref,
                st.get("time_s"))

    def bench_gpu(self, scene, ref):
        for photons, maps, spp in self.cfg["photonbridge"]:
            if self.expired("%s photonbridge %d %d %d" % (scene, photons, maps, spp)):
                continue
            tag = "%s_pb_%d_%d_%d" % (scene, photons, maps, spp)
            exr, js = os.path.join(self.work, tag + ".exr"), os.path.join(self.work, tag + ".json")
            cmd = [self.exe, "render", self.scene_path(scene), "-o", exr, "--width", str(self.width),
                   "--spp", str(spp), "--photons", str(photons), "--iterations", str(maps), "--json", js,
                   "-q"] + self.dev
            r = rb.run_point(cmd, os.path.join(self.work, tag + ".log"), self.timeout,
                             env=self.env(LP_NUM_THREADS=self.threads))
            st = rb.read_json(js) or {}
            ph = st.get("photons") or {}
            rs = st["wall_ms"] / 1e3 if isinstance(st.get("wall_ms"), (int, float)) else None
            self.add_point(scene, "photonbridge", "GPU photon mapping (lavapipe LP_NUM_THREADS=%d)" % self.threads,
                           {"photons": photons, "iterations": maps, "spp": spp}, r, exr, ref, rs,
                           {"photons_stored": ph.get("stored"), "k_pd": ph.get("k_pd"), "device": st.get("device")})

    # ---- the peers -------------------------------------------------------

    def dump(self, scene, fmt):
        d = os.path.join(self.work, "%s_%s_dump" % (scene, fmt))
        if not os.path.isfile(os.path.join(d, "scene.xml" if fmt == "mitsuba" else "render.cfg")):
            r = rb.run_point([self.exe, "export-peer", self.scene_path(scene), "--format", fmt, "-o", d,
                              "--width", str(self.width)], os.path.join(self.work, "%s_%s_dump.log" % (scene, fmt)),
                             120)
            if r["rc"] != 0:
                return None, r["out"]
            notes = [l[6:].strip() for l in r["out"].splitlines() if l.startswith("note:")]
            self.dump_notes.setdefault(scene, {})[fmt] = notes
        return d, None

    def peer_point(self, scene, renderer, config, params, cmd, exr, ref, env=None):
        tag = os.path.basename(exr)[:-4]
        r = rb.run_point(cmd, os.path.join(self.work, tag + ".log"), self.timeout, env=env)
        st = rb.read_json(exr + ".json") or {}
        if os.path.exists(exr + ".json"):
            os.unlink(exr + ".json")
        extra = {k: st.get(k) for k in ("version", "engine", "spp_reached", "photongi", "build_s", "variant",
                                         "drjit", "blender", "samples") if st.get(k) is not None}
        rs = st.get("render_s")
        return self.add_point(scene, renderer, config, params, r, exr, ref, rs, extra)

    def bench_luxcore(self, scene, ref, which=("photongi", "bidirvm")):
        if not os.access(PY["luxcore"], os.X_OK):
            self.notes.append("LuxCore: tools/luxcore missing (scripts/install-deps.sh)")
            return
        d, err = self.dump(scene, "luxcore")
        if not d:
            self.notes.append("LuxCore: %s: export-peer failed: %s" % (scene, rb.tail(err)))
            return
        pg = self.cfg["photongi"]
        for spp in (pg["spp"] if "photongi" in which else []):
            if self.expired("%s luxcore-photongi %d" % (scene, spp)):
                continue
            exr = os.path.join(self.work, "%s_lxpgi_%d.exr" % (scene, spp))
            cmd = [PY["luxcore"], os.path.join(ROOT, "validation", "peer_render.py"), "luxcore", d, exr,
                   "--engine", "photongi", "--spp", str(spp), "--threads", str(self.threads), "--seed", "1",
                   "--photons", str(pg["photons"]), "--pgi-halt", str(pg["halt"]),
                   "--indirect-maxsize", str(pg["indirect_maxsize"]),
                   "--caustic-photons", str(pg["caustic"])]
            self.peer_point(scene, "luxcore-photongi", "PATHCPU + PhotonGI (indirect + caustic)",
                            {"spp": spp, "photon_maxcount": pg["photons"], "indirect_haltthreshold": pg["halt"],
                             "indirect_maxsize": pg["indirect_maxsize"], "caustic_maxsize": pg["caustic"],
                             "threads": self.threads}, cmd, exr, ref,
                            self.env())
        vc = self.cfg["bidirvm"]
        for spp in (vc["spp"] if "bidirvm" in which else []):
            if self.expired("%s luxcore-bidirvm %d" % (scene, spp)):
                continue
            exr = os.path.join(self.work, "%s_lxvcm_%d.exr" % (scene, spp))
            cmd = [PY["luxcore"], os.path.join(ROOT, "validation", "peer_render.py"), "luxcore", d, exr,
                   "--engine", "bidirvm", "--spp", str(spp), "--threads", str(self.threads), "--seed", "1",
                   "--light-paths", str(vc["light_paths"])]
            self.peer_point(scene, "luxcore-bidirvm", "BIDIRVMCPU (VCM)",
                            {"spp": spp, "light_paths_per_pass": vc["light_paths"], "threads": self.threads}, cmd,
                            exr, ref, self.env())

    def bench_mitsuba(self, scene, ref):
        if not os.access(PY["mitsuba"], os.X_OK):
            self.notes.append("Mitsuba 3: tools/mitsuba3 missing (scripts/install-deps.sh)")
            return
        d, err = self.dump(scene, "mitsuba")
        if not d:
            self.notes.append("Mitsuba 3: %s: export-peer failed: %s" % (scene, rb.tail(err)))
            return
        for spp in self.cfg["mitsuba"]:
            if self.expired("%s mitsuba %d" % (scene, spp)):
                continue
            exr = os.path.join(self.work, "%s_mi_%d.exr" % (scene, spp))
            cmd = ["taskset", "-c", ",".join(map(str, self.pin)), PY["mitsuba"],
                   os.path.join(ROOT, "validation", "peer_render.py"), "mitsuba", d, exr, "--spp", str(spp),
                   "--threads", str(self.threads), "--seed", "1", "--variant", "scalar_rgb"]
            if not shutil.which("taskset"):
                cmd = cmd[3:]
            self.peer_point(scene, "mitsuba", "path (scalar_rgb, pinned to %d CPU)" % len(self.pin),
                            {"spp": spp, "cpus": len(self.pin)}, cmd, exr, ref, self.env())

    def bench_cycles45(self, scene, ref):
        if self.a.no_cycles:
            self.notes.append("Cycles: skipped (--no-cycles)")
            return
        if not os.access(PY["bpy45"], os.X_OK):
            self.notes.append("Cycles 4.5: tools/bpy45 missing (scripts/install-deps.sh)")
            return
        info = os.path.join(self.work, scene + "_info.json")
        if not os.path.isfile(info):
            rb.run_point([self.exe, "info", self.scene_path(scene), "--json", info],
                         os.path.join(self.work, scene + "_info.log"), 60)
        for spp in self.cfg["cycles"]:
            if self.expired("%s cycles %d" % (scene, spp)):
                continue
            exr = os.path.join(self.work, "%s_cy_%d.exr" % (scene, spp))
            cmd = [PY["bpy45"], os.path.join(ROOT, "tests", "blender", "bpy_blender.py"), "-b", "--factory-startup",
                   "--python-exit-code", "1", "-P", os.path.join(ROOT, "validation", "run_cycles.py"), "--",
                   "--gltf", self.scene_path(scene), "--info", info, "--out", exr, "--width", str(self.width),
                   "--samples", str(spp), "--threads", str(self.threads), "--seed", "1"]
            self.peer_point(scene, "cycles", "Cycles 4.5 path tracing (CPU, glTF importer)",
                            {"samples": spp, "threads": self.threads}, cmd, exr, ref, self.env())


# ---- summaries -------------------------------------------------------------

def time_to_flip(pts, target):
    """As run_bench.time_to_psnr, for FLIP falling to `target` or below."""
    pts = sorted((p for p in pts if p.get("flip_hdr") is not None), key=lambda p: p["wall_s"])
    prev = None
    for p in pts:
        if p["flip_hdr"] <= target:
            if prev is None:
                return p["wall_s"], "<="
            t0, t1 = math.log(prev["wall_s"]), math.log(p["wall_s"])
            f = (prev["flip_hdr"] - target) / (prev["flip_hdr"] - p["flip_hdr"])
            return math.exp(t0 + f * (t1 - t0)), "="
        prev = p
    return None, None


def summarise(points, scenes):
    rows = []
    for s in scenes:
        per = {}
        for p in points:
            if p["scene"] == s and p.get("status") == "ok":
                per.setdefault(p["renderer"], []).append(p)
        ref_t = {thr: rb.time_to_psnr(per.get("reference", []), thr) for thr in THRESHOLDS_DB}
        for rn in RENDERERS:
            pts = per.get(rn)
            if not pts:
                continue
            last = max(pts, key=lambda p: p["wall_s"])
            row = {"scene": s, "renderer": rn, "config": last["config"], "points": len(pts),
                   "last": {"wall_s": last["wall_s"], "params": last["params"], "psnr_db": last.get("psnr_db"),
                            "flip_hdr": last.get("flip_hdr"), "ssim": last.get("ssim")},
                   "best_psnr_db": max(p["psnr_db"] for p in pts if p.get("psnr_db") is not None),
                   "best_flip_hdr": min((p["flip_hdr"] for p in pts if p.get("flip_hdr") is not None), default=None),
                   "psnr": {}, "flip": {}}
            for thr in THRESHOLDS_DB:
                t, bound = rb.time_to_psnr(pts, thr)
                rt, rbound = ref_t[thr]
                e = {"time_s": t, "bound": bound}
                if t is not None and rt is not None:
                    e["ratio_to_reference"] = t / rt
                    e["ratio_bound"] = "?" if bound == "<=" and rbound == "<=" else (
                        "<=" if bound == "<=" else (">=" if rbound == "<=" else "="))
                row["psnr"]["%g" % thr] = e
            for thr in FLIP_THRESHOLDS:
                t, bound = time_to_flip(pts, thr)
                row["flip"]["%g" % thr] = {"time_s": t, "bound": bound}
            rows.append(row)
    return rows


def versions(exe):
    def out(cmd):
        try:
            p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, universal_newlines=True,
                               timeout=120)
            return p.stdout.strip().splitlines()[-1] if p.stdout.strip() else None
        except (OSError, subprocess.TimeoutExpired, IndexError):
            return None

    meta = "import importlib.metadata as m; print(' '.join(p + ' ' + m.version(p) for p in %r))"
    v = {"photonbridge": out([exe, "--version"]),
         "mesa-vulkan-drivers": out(["dpkg-query", "-W", "-f=${Version}", "mesa-vulkan-drivers"]),
         "libembree3": out(["dpkg-query", "-W", "-f=${Version}", "libembree3-3"])}
    for key, venv, pkgs in (("luxcore", "luxcore", ["pyluxcore"]), ("mitsuba", "mitsuba", ["mitsuba", "drjit"]),
                            ("flip", "flip", ["flip-evaluator"]), ("bpy", "bpy45", ["bpy"])):
        if os.access(PY[venv], os.X_OK):
            v[key] = out([PY[venv], "-c", meta % pkgs])
    return v


def fmt_t(e):
    if not e or e.get("time_s") is None:
        return "not reached"
    return ("<= " if e.get("bound") == "<=" else "") + "%.1f s" % e["time_s"]


def fmt_ratio(e):
    if not e or e.get("ratio_to_reference") is None:
        return ""
    b = e.get("ratio_bound", "=")
    return " (%s%.2fx)" % ("" if b == "=" else b + " ", e["ratio_to_reference"])


def markdown(res):
    L = []
    m = res["machine"]
    L.append("## Peers: time to PSNR and FLIP (bench/run_peers.py, mode %s)" % res["mode"])
    L.append("")
    L.append("Run %s to %s (%d s); machine: %s, %s cores, %s GiB; load average %s at the start, %s at the end. "
             "Width %d px; every renderer with %d worker thread(s) (Mitsuba: pinned to %d CPU). "
             "photonbridge device: %s." % (
                 res["started"], res["finished"], res["duration_s"], m.get("cpu"), m.get("cores"), m.get("mem_gib"),
                 res["load_start"], res["load_end"], res["width"], res["threads"], res["threads"],
                 res["device"]["name"] if res.get("device") else "-"))
    L.append("")
    L.append("Versions: " + "; ".join("%s %s" % (k, v) for k, v in sorted(res["versions"].items()) if v) + ".")
    L.append("")
    L.append("PSNR: display image (sRGB / Standard view of `photonbridge compare`); FLIP: HDR-FLIP mean (NVIDIA "
             "FLIP 1.7, scene-linear, exposures from the reference); times: wall seconds from spawn to exit "
             "(interpreter start, scene load and, for PhotonGI, the cache's photon tracing included), "
             "interpolated in log time between sweep points, '<=' = reached at the first point; "
             "(Nx) = time over the Embree reference's time to the same PSNR, same run.")
    L.append("")
    for s in res["scenes"]:
        ref = res["references"][s]
        noise = (ref.get("noise") or {}).get("psnr_db")
        L.append("**%s**, %dx%s px; converged reference %d spp (%s), its noise PSNR %s dB" % (
            s, res["width"], ref.get("height"), ref["spp"], ref.get("mode"), "%.1f" % noise if noise else "-"))
        L.append("")
        L.append("| renderer | 25 dB | 30 dB | 35 dB | FLIP <= 0.2 | FLIP <= 0.1 | longest point | its PSNR dB | its FLIP |")
        L.append("|---|---|---|---|---|---|---|---|---|")
        for row in res["summary"]:
            if row["scene"] != s:
                continue
            ps = row["psnr"]
            lp = row["last"]
            L.append("| %s | %s | %s | %s | %s | %s | %s, %.1f s | %s | %s |" % (
                row["renderer"], fmt_t(ps["25"]) + fmt_ratio(ps["25"]), fmt_t(ps["30"]) + fmt_ratio(ps["30"]),
                fmt_t(ps["35"]) + fmt_ratio(ps["35"]), fmt_t(row["flip"]["0.2"]), fmt_t(row["flip"]["0.1"]),
                json.dumps(lp["params"], separators=(",", ":")), lp["wall_s"],
                "%.2f" % lp["psnr_db"] if lp.get("psnr_db") is not None else "-",
                "%.4f" % lp["flip_hdr"] if lp.get("flip_hdr") is not None else "-"))
        L.append("")
    L.append("Every point:")
    L.append("")
    L.append("| scene | renderer | settings | wall s | render s | PSNR dB | SSIM | HDR-FLIP | status |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    for p in res["points"]:
        settings = dict(p["params"])
        if p.get("spp_reached") is not None and p["spp_reached"] != settings.get("spp"):
            settings["spp_reached"] = p["spp_reached"]
        if (p.get("photongi") or {}).get("photons_traced"):
            settings["photons_traced"] = int(p["photongi"]["photons_traced"])
        L.append("| %s | %s | %s | %.2f | %s | %s | %s | %s | %s |" % (
            p["scene"], p["renderer"], json.dumps(settings, separators=(",", ":")).replace("|", "/"), p["wall_s"],
            "%.2f" % p["render_s"] if isinstance(p.get("render_s"), (int, float)) else "-",
            "%.2f" % p["psnr_db"] if p.get("psnr_db") is not None else "-",
            "%.4f" % p["ssim"] if p.get("ssim") is not None else "-",
            "%.4f" % p["flip_hdr"] if p.get("flip_hdr") is not None else "-",
            p["status"] if p["status"] == "ok" else "failed: " + p.get("error", "")[:120]))
    L.append("")
    if res["notes"]:
        L.append("Notes:")
        L.append("")
        L += ["- " + n for n in res["notes"]]
        L.append("")
    if res.get("dump_notes"):
        L.append("What the dump approximates (export-peer's notes):")
        L.append("")
        for s, d in sorted(res["dump_notes"].items()):
            for fmt, notes in sorted(d.items()):
                for n in notes:
                    L.append("- %s, %s: %s" % (s, fmt, n))
        L.append("")
    return "\n".join(L)


def main(argv):
    ap = argparse.ArgumentParser(prog="run_peers.py", description=__doc__.split("\n")[0])
    ap.add_argument("--mode", choices=sorted(MODES), default="full")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "photonbridge"))
    ap.add_argument("--device", type=int, help="Vulkan device index for photonbridge")
    ap.add_argument("--scenes")
    ap.add_argument("--width", type=int, default=0)
    ap.add_argument("--threads", type=int, default=1, help="worker threads of every renderer (default 1)")
    ap.add_argument("--ref-spp", type=int, default=0)
    ap.add_argument("--out")
    ap.add_argument("--cache", default=os.path.join(HERE, "cache"))
    ap.add_argument("--markdown", help="also write the tables here")
    ap.add_argument("--renderers", help="comma-separated subset of %s (the reference always runs)" %
                    ",".join(RENDERERS))
    ap.add_argument("--no-cycles", action="store_true")
    ap.add_argument("--no-photonbridge", action="store_true", help="leave out the GPU pipeline's points")
    ap.add_argument("--minutes", type=float, default=0, help="skip (and list) points that would start after this "
                    "many minutes")
    ap.add_argument("--refresh-references", action="store_true")
    ap.add_argument("--keep-work", action="store_true")
    ap.add_argument("--note", action="append", default=[])
    a = ap.parse_args(argv)
    cfg = dict(MODES[a.mode])
    if not os.access(a.exe, os.X_OK):
        print("run_peers: %s: no photonbridge executable" % a.exe, file=sys.stderr)
        return 2
    if not a.out:
        a.out = os.path.join(HERE, "results", "lavapipe", "peers" if a.mode == "full" else "peers_" + a.mode)
    scenes = a.scenes.split(",") if a.scenes else cfg["scenes"]
    cfg["timeout_s"] = cfg["timeout_s"]
    b = PeerBench(a, cfg)
    b.dump_notes = {}
    rb.build_peak_helper(b.cache)
    b.version = subprocess.run([b.exe, "--version"], stdout=subprocess.PIPE, universal_newlines=True).stdout.strip()
    devs = rb.devices(b.exe) if not a.no_photonbridge and cfg["photonbridge"] else []
    dev = next((d for d in devs if (d["index"] == a.device if a.device is not None else d["default"])), None)
    t_start = time.time()
    load_start = rb.loadavg()
    b.log("%s run, %d px, %d thread(s), scenes %s -> %s" % (a.mode, b.width, a.threads, ",".join(scenes),
                                                            os.path.relpath(b.out, ROOT)))
    refs = {s: b.reference(s) for s in scenes}
    want = set(a.renderers.split(",")) if a.renderers else set(RENDERERS)
    want.add("reference")  # the ratios' denominator, always in the run
    for s in scenes:  # the dearest curves last, so that --minutes cuts them first
        b.bench_reference(s, refs[s])
        if "mitsuba" in want:
            b.bench_mitsuba(s, refs[s])
        if "cycles" in want:
            b.bench_cycles45(s, refs[s])
        if "luxcore-bidirvm" in want:
            b.bench_luxcore(s, refs[s], ("bidirvm",))
        if dev and not a.no_photonbridge and "photonbridge" in want:
            b.bench_gpu(s, refs[s])
        if "luxcore-photongi" in want:
            b.bench_luxcore(s, refs[s], ("photongi",))
    res = {"mode": a.mode, "started": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime(t_start)),
           "finished": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "duration_s": round(time.time() - t_start),
           "machine": rb.machine_info(), "device": dev, "versions": versions(b.exe), "load_start": load_start,
           "load_end": rb.loadavg(), "width": b.width, "threads": a.threads, "scenes": scenes,
           "config": cfg, "references": refs, "points": b.points, "dump_notes": b.dump_notes,
           "flip": "HDR-FLIP mean (flip-evaluator, scene-linear RGB, exposures from the reference)",
           "notes": b.notes + a.note + (["stopped by --minutes %g: skipped %s" % (a.minutes, "; ".join(b.skipped))]
                                        if b.skipped else []), "skipped": b.skipped}
    res["summary"] = summarise(b.points, scenes)
    os.makedirs(b.out, exist_ok=True)
    with open(os.path.join(b.out, "results.json"), "w") as f:
        json.dump(res, f, indent=1)
    md = markdown(res)
    with open(os.path.join(b.out, "PEERS.md"), "w") as f:
        f.write(md + "\n")
    if a.markdown:
        with open(a.markdown, "w") as f:
            f.write(md + "\n")
    if not a.keep_work:
        shutil.rmtree(b.work, ignore_errors=True)
    b.log("done in %d s: %s" % (res["duration_s"], os.path.relpath(os.path.join(b.out, "PEERS.md"), ROOT)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
