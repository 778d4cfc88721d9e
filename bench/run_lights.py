#!/usr/bin/env python3
"""Soft lights and the world against Cycles 3.4: speed and error on the two
scenes of bench/scenes/lights (exporters/blender/light_scenes.py --bench):

  studio_area  a floor curving into a back wall (a photographer's cove), a
               sphere, a box and a prism, lit by a 1.2 x 0.8 m softbox (60 W)
               and a 1.5 m disc fill (15 W, spread 100 degrees), no world;
  world_only   the same props on an open floor, lit by a uniform world
               (0.8, 0.9, 1.0) alone.

Principled materials (Blender's default Principled BSDF on the floor, a
rough metal sphere, a glossy plastic box, a default prism: the
PHOTONBRIDGE_blender extension, rendered as they are by Cycles), 128 x 96,
Cycles' box filter. The Cycles render (cycles.json: 2048 spp) is the
reference; cycles.json holds its own noise (a second seed).
Swept: the photonbridge reference over spp, the GPU pipeline over photon
maps and spp (its own defaults first, the Blender render engine's
last); each point a separate process,
timed spawn to exit; PSNR and SSIM on the display image, mean difference on
scene-linear RGB (tests/lights_cycles.py's measures). Then what the lights
cost the GPU: per-pass times (GPU timestamps) of each scene against the same
scene with point lights of the same powers at the area lights' centres
(studio_area) or with a sun instead of the world (world_only).

    python3 bench/run_lights.py [--exe build/photonbridge] [--device N] [--quick]
                                [--out DIR] [--only reference,gpu,cost] [--repeat N]

Writes DIR/results.json and DIR/LIGHTS.md (DIR: bench/results/DEVICE/lights);
--only re-measures those parts into DIR's results.json and says when.
"""
import argparse
import json
import os
import platform
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SCENES = ("studio_area", "world_only")
REF_SPP = {"full": [64, 256, 1024, 4096], "quick": [64, 256]}
# (label, `render` options): its own defaults (1 spp, one map of 2^18
# paths), photon maps x spp, and the Blender render engine's defaults
# (exporters/blender/photonbridge/settings.py: 2^18 paths, 16 maps, 16 spp,
# progressive), which the lights' 30 dB goal names.
ENGINE_DEFAULTS = ("render engine defaults (2^18 x 16 maps, 16 spp, progressive)",
                   ["--photons", str(1 << 18), "--iterations", "16", "--spp", "16", "--progressive"])


def gpu_point(photons, maps, spp):
    return ("2^%d x %d maps, %d spp" % (photons.bit_length() - 1, maps, spp),
            ["--photons", str(photons), "--iterations", str(maps), "--spp", str(spp)])


PARTS = ("reference", "gpu", "cost")
GPU_POINTS = {"full": [("render defaults (1 spp, 2^18 x 1 map)", []), gpu_point(1 << 16, 4, 16),
                       gpu_point(1 << 16, 8, 64), gpu_point(1 << 17, 16, 256), ENGINE_DEFAULTS],
              "quick": [("render defaults (1 spp, 2^18 x 1 map)", []), gpu_point(1 << 16, 4, 16)]}


def run(cmd):
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True)
    return p.returncode, time.monotonic() - t0, p.stdout, p.stderr


def probe_means(probe, path):
    rc, _, out, err = run([probe, path])
    if rc:
        raise RuntimeError("exr_probe %s: %s" % (path, err.strip()))
    ch = json.loads(out)["channels"]
    return [sum(ch[c]) / len(ch[c]) for c in ("R", "G", "B")]


def compare(exe, probe, test, ref):
    rc, _, out, err = run([exe, "compare", test, ref, "--json", "-", "-q"])
    if rc:
        raise RuntimeError("compare: %s" % err.strip())
    m = json.loads(out)
    mt, mr = probe_means(probe, test), probe_means(probe, ref)
    m["mean_diff"] = max((a / b - 1 for a, b in zip(mt, mr)), key=abs)
    return m


def variant(src, kind, out):
    """studio_area with point lights of the same powers (kind 'point'), or
    world_only with a sun of the world's irradiance on the floor instead
    (kind 'sun'): the cost of the feature, by the difference of times."""
    with open(src) as f:
        d = json.load(f)
    folder = os.path.dirname(src)
    for b in d["buffers"]:
        b["uri"] = os.path.join(folder, b["uri"])
    if kind == "point":
        for n in d["nodes"]:
            e = n.get("extensions", {}).get("PHOTONBRIDGE_blender", {}).get("light")
            if e and e["type"] == "AREA":
                e.update(type="POINT", radius=0.0)
    else:
        root = d["extensions"]["PHOTONBRIDGE_blender"]
        w = root.pop("world")
        e_floor = sum(w["color"]) / 3 * w["strength"] * 3.14159265
        d["nodes"].append({"name": "Sun", "rotation": [-0.5, 0.0, 0.0, 0.8660254],
                           "extensions": {"PHOTONBRIDGE_blender": {"light": {"type": "SUN", "strength": e_floor,
                                                                             "angle": 0.0}}}})
        d["scenes"][d.get("scene", 0)]["nodes"].append(len(d["nodes"]) - 1)
    with open(out, "w") as f:
        json.dump(d, f)


def main(argv):
    ap = argparse.ArgumentParser(prog="run_lights.py")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "photonbridge"))
    ap.add_argument("--probe", default=os.path.join(ROOT, "build", "tests", "exr_probe"))
    ap.add_argument("--device", default=None)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default=None)
    ap.add_argument("--only", default=None,
                    help="re-measure only these parts (comma-separated: reference, gpu, cost) into the "
                         "results.json already in the output folder, keeping the others")
    ap.add_argument("--repeat", type=int, default=3, help="cost runs per variant (the fastest of each pass is kept)")
    a = ap.parse_args(argv)
    parts = set(a.only.split(",")) if a.only else set(PARTS)
    if not parts <= set(PARTS):
        ap.error("--only: parts are %s" % ", ".join(PARTS))
    mode = "quick" if a.quick else "full"
    dev = ["--device", a.device] if a.device is not None else []
    rc, _, out, _ = run([a.exe, "info", "--devices"] + dev)
    # "  0* llvmpipe (LLVM 15.0.6, 256 bits)     cpu ...": the device used
    # (--device N, else the one marked *).
    rows = re.findall(r"^\s*(\d+)(\*?)\s+(\S.*?)\s{2,}", out, re.M)
    pick = [r for r in rows if (a.device is not None and r[0] == str(a.device)) or (a.device is None and r[1])]
    device = pick[0][2] if pick else "unknown"
    slug = re.sub(r"[^a-z0-9]+", "-", device.lower()).strip("-").split("-llvm")[0] or "device"
    if "llvmpipe" in slug:
        slug = "lavapipe"
    outdir = a.out or os.path.join(ROOT, "bench", "results", slug, "lights" + ("-quick" if a.quick else ""))
    os.makedirs(outdir, exist_ok=True)
    work = tempfile.mkdtemp(prefix="pb_lights_")
    res = {"date": time.strftime("%Y-%m-%d"), "machine": "%s, %d cores" % (platform.processor() or platform.machine(),
                                                                          os.cpu_count()),
           "device": device, "mode": mode, "load": os.getloadavg()[0], "scenes": {}}
    if a.only:
        with open(os.path.join(outdir, "results.json")) as f:
            res = json.load(f)
        for part in parts:
            res.setdefault("remeasured", {})[part] = {"date": time.strftime("%Y-%m-%d"), "load": os.getloadavg()[0]}
    for name in SCENES:
        folder = os.path.join(ROOT, "bench", "scenes", "lights", name)
        gltf, cyc = os.path.join(folder, name + ".gltf"), os.path.join(folder, "cycles.exr")
        with open(os.path.join(folder, "cycles.json")) as f:
            cj = json.load(f)
        # Cycles' own noise on the display image: seeds 1 and 2 differ by
        # twice one render's variance, so its PSNR is theirs + 3.01 dB.
        m2 = compare(a.exe, a.probe, os.path.join(folder, "cycles_seed2.exr"), cyc)
        cj["noise_psnr_db"] = m2["psnr_db"] + 3.0103
        width = "128"
        sc = res["scenes"].setdefault(name, {})
        sc["cycles"] = cj
        for part in parts:
            sc[part] = {} if part == "cost" else []
        for spp in (REF_SPP[mode] if "reference" in parts else []):
            exr, js = os.path.join(work, "ref.exr"), os.path.join(work, "ref.json")
            cmd = [a.exe, "reference", gltf, "-o", exr, "--width", width, "--spp", str(spp), "--json", js, "-q"]
            if spp == REF_SPP[mode][-1]:
                cmd.append("--estimate-noise")
            rc, wall, _, err = run(cmd)
            if rc:
                raise RuntimeError(err)
            m = compare(a.exe, a.probe, exr, cyc)
            with open(js) as f:
                st = json.load(f)
            pt = {"spp": spp, "wall_s": round(wall, 2), "psnr_db": m["psnr_db"], "ssim": m["ssim"],
                  "relmse": m["relmse"], "mean_diff": m["mean_diff"], "noise": st.get("noise")}
            sc["reference"].append(pt)
            print("%s reference %5d spp: %6.1f s  PSNR %.2f dB  SSIM %.4f  mean %+.3f %%" % (
                name, spp, wall, m["psnr_db"], m["ssim"], 100 * m["mean_diff"]), flush=True)
        for label, opts in (GPU_POINTS[mode] if "gpu" in parts else []):
            exr, js = os.path.join(work, "gpu.exr"), os.path.join(work, "gpu.json")
            cmd = [a.exe, "render", gltf, "-o", exr, "--width", width, "--json", js, "-q"] + dev + opts
            rc, wall, _, err = run(cmd)
            if rc:
                raise RuntimeError(err)
            m = compare(a.exe, a.probe, exr, cyc)
            with open(js) as f:
                st = json.load(f)
            # GPU time: the timestamps of every pass, photon maps included.
            gpu_ms = sum(st["passes_ms"][k] for k in ("gbuffer", "direct", "photon_trace", "lbvh_build", "gather",
                                                       "filter"))
            pt = {"settings": label,
                  "wall_s": round(wall, 2), "gpu_ms": round(gpu_ms, 1), "psnr_db": m["psnr_db"],
                  "ssim": m["ssim"], "relmse": m["relmse"], "mean_diff": m["mean_diff"],
                  "photons": st.get("photons", {}).get("emitted"), "stored": st.get("photons", {}).get("stored")}
            sc["gpu"].append(pt)
            print("%s gpu %-24s: %6.1f s (GPU %.0f ms)  PSNR %.2f dB  SSIM %.4f  mean %+.3f %%" % (
                name, pt["settings"], wall, pt["gpu_ms"], m["psnr_db"], m["ssim"], 100 * m["mean_diff"]), flush=True)
        # Cost: the same settings on the scene and on its variant, GPU passes.
        var = os.path.join(work, name + "_variant.gltf")
        variant(gltf, "point" if name == "studio_area" else "sun", var)
        for label, path in ((("as is", gltf), ("point lights" if name == "studio_area" else "sun instead", var))
                            if "cost" in parts else ()):
            js = os.path.join(work, "cost.json")
            cmd = [a.exe, "render", path, "-o", os.path.join(work, "cost.exr"), "--width", width, "--spp", "16",
                   "--iterations", "4", "--photons", str(1 << 16), "--json", js, "-q",
                   "--allow-external-files"] + dev  # the variant's buffer is the scene's, by absolute path
            pm = None
            for _ in range(max(1, a.repeat)):  # other work on a shared machine only slows a pass down
                rc, wall, _, err = run(cmd)
                if rc:
                    raise RuntimeError(err)
                with open(js) as f:
                    st = json.load(f)
                pm = st["passes_ms"] if pm is None else {k: min(v, st["passes_ms"][k]) for k, v in pm.items()}
            sc["cost"][label] = {"passes_ms": pm, "repeat": a.repeat, "stored": st["photons"]["stored"],
                                 "pipeline": st["pipeline"]}
            print("%s cost, %-12s: gbuffer %.1f direct %.1f photon trace %.1f LBVH %.1f gather %.1f ms (GPU)" % (
                name, label, pm["gbuffer"], pm["direct"], pm["photon_trace"], pm["lbvh_build"], pm["gather"]),
                flush=True)
    with open(os.path.join(outdir, "results.json"), "w") as f:
        json.dump(res, f, indent=1)
    lines = ["# Soft lights and the world against Cycles 3.4 (bench/run_lights.py)", "",
             "%s, %s, device %s, load %.1f; 128 x 96; the reference is Cycles 3.4 at %d spp (its own noise: "
             "PSNR %s)." % (res["date"], res["machine"], device, res["load"],
                            res["scenes"][SCENES[0]]["cycles"]["samples"], ", ".join(
                                "%s %.1f dB" % (n, res["scenes"][n]["cycles"].get("noise_psnr_db", float("nan")))
                                for n in SCENES))]
    for part, when in sorted(res.get("remeasured", {}).items()):
        lines.append("Re-measured on %s at load %.1f: %s." % (when["date"], when["load"], part))
    lines += ["", "Wall: spawn to exit; GPU: the timestamps of every pass (photon maps included).", "",
              "| scene | renderer | settings | wall s | GPU s | PSNR dB | SSIM | mean |",
              "|---|---|---|---:|---:|---:|---:|---:|"]
    for name in SCENES:
        sc = res["scenes"][name]
        for p in sc["reference"]:
            lines.append("| %s | reference | %d spp | %.1f | | %.2f | %.4f | %+.3f %% |" % (
                name, p["spp"], p["wall_s"], p["psnr_db"], p["ssim"], 100 * p["mean_diff"]))
        for p in sc["gpu"]:
            lines.append("| %s | GPU | %s | %.1f | %.1f | %.2f | %.4f | %+.3f %% |" % (
                name, p["settings"], p["wall_s"], p["gpu_ms"] / 1e3, p["psnr_db"], p["ssim"], 100 * p["mean_diff"]))
    repeat = next(iter(res["scenes"][SCENES[0]]["cost"].values()), {}).get("repeat", 1)
    lines += ["", "What the lights cost the GPU (16 spp, 4 maps of 2^16 photon paths; GPU timestamps, ms, the "
              "fastest of %d runs):" % repeat, "",
              "| scene | lights | G-buffer | direct | photon trace | LBVH | gather | photons stored |",
              "|---|---|---:|---:|---:|---:|---:|---:|"]
    for name in SCENES:
        for label, c in res["scenes"][name]["cost"].items():
            pm = c["passes_ms"]
            lines.append("| %s | %s | %.1f | %.1f | %.1f | %.1f | %.1f | %d |" % (
                name, label, pm["gbuffer"], pm["direct"], pm["photon_trace"], pm["lbvh_build"], pm["gather"],
                c["stored"]))
    with open(os.path.join(outdir, "LIGHTS.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote %s" % os.path.join(outdir, "LIGHTS.md"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
