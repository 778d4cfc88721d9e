#!/usr/bin/env python3
"""Blender's Principled BSDF against Cycles 3.4: speed and error on the studio
scenes of tests/data/principled (exporters/blender/make_principled_tests.py:
floor, wall, two spheres and a box, all Blender's default Principled BSDF,
one 150 W point light, 128 x 96), with the GGX distribution (Blender's
default) and with Multiscatter GGX.

    python3 bench/principled_studio.py [--exe build/photonbridge] [--out DIR]
                                       [--quick] [--device N]

For each scene it renders, each in its own process timed from spawn to exit
(wall seconds: start-up, pipeline compilation, scene load and the EXR
included):
  - photonbridge (GPU) over photon budgets / maps / spp, with glossy eye
    paths (the default: a Blender surface's glossy closures are followed by
    the eye path, its diffuse ones shaded by the photon map) and without
    them (--max-specular-depth 0: every closure shaded at the first hit, by
    direct light and the photon map, whose photons are stored on every
    surface with a non-delta closure either way);
  - the reference path tracer over spp (--max-bounces 64, as Cycles);
and compares every picture with the committed Cycles render (8192 samples,
64 bounces): PSNR and SSIM on the display image, relMSE, and the mean
difference. Writes DIR/results.json and DIR/PRINCIPLED.md (default
bench/results/DEVICE-SLUG/principled)."""
import argparse
import json
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DATA = os.path.join(ROOT, "tests", "data", "principled")
SCENES = ["studio", "studio_multi"]

# photons per map, maps, spp
GPU_POINTS = {"full": [(1 << 16, 1, 4), (1 << 16, 4, 16), (1 << 17, 8, 32), (1 << 18, 16, 64)],
              "quick": [(1 << 16, 1, 4), (1 << 16, 4, 16)]}
REF_SPP = {"full": [64, 256, 1024, 4096], "quick": [64, 256]}


def run(cmd):
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    dt = time.time() - t0
    if p.returncode:
        raise RuntimeError("%s exited %d: %s" % (" ".join(cmd), p.returncode, p.stderr.strip()[-400:]))
    return dt


def compare(exe, test, ref, work):
    js = os.path.join(work, "cmp.json")
    run([exe, "compare", test, ref, "--json", js, "-q"])
    c = json.load(open(js))
    return c


def mean_exr(probe, path):
    p = subprocess.run([probe, path], capture_output=True, text=True)
    if p.returncode:
        raise RuntimeError(p.stderr)
    ch = json.loads(p.stdout)["channels"]
    vals = ch["R"] + ch["G"] + ch["B"]
    return sum(vals) / len(vals)


def slug(name):
    return re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-")


def main(argv):
    ap = argparse.ArgumentParser(prog="principled_studio.py")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "photonbridge"))
    ap.add_argument("--probe", default=os.path.join(ROOT, "build", "tests", "exr_probe"))
    ap.add_argument("--out")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--device", type=int)
    args = ap.parse_args(argv)
    mode = "quick" if args.quick else "full"
    dev = subprocess.run([args.exe, "info", "--devices"], capture_output=True, text=True).stdout
    m = re.search(r"^\s+%d\*?\s+(.+?)\s{2,}" % (args.device or 0), dev, re.M)
    device = m.group(1).strip() if m else "unknown"
    out = args.out or os.path.join(HERE, "results", slug(device.split("(")[0]), "principled")
    os.makedirs(out, exist_ok=True)
    work = os.path.join(out, "work")
    os.makedirs(work, exist_ok=True)
    cyc = json.load(open(os.path.join(DATA, "cycles.json")))
    results = {"device": device, "mode": mode, "machine": os.uname().nodename, "cpus": os.cpu_count(),
               "load_before": os.getloadavg()[0], "scenes": {}}
    for scene in SCENES:
        gltf = os.path.join(DATA, scene, scene + ".gltf")
        ref = os.path.join(DATA, scene, "cycles.exr")
        w = str(cyc[scene]["width"])
        m_cycles = mean_exr(args.probe, ref)
        rows = []

        def point(label, cmd, settings):
            exr = os.path.join(work, "%s_%s.exr" % (scene, slug(label + "_" + "_".join(map(str, settings.values())))))
            js = exr[:-4] + ".json"
            dt = run(cmd + ["-o", exr, "--width", w, "--json", js, "-q"])
            c = compare(args.exe, exr, ref, work)
            stats = json.load(open(js))
            mm = mean_exr(args.probe, exr)
            row = dict(settings, label=label, wall_s=round(dt, 2), psnr_db=c["psnr_db"], ssim=c["ssim"],
                       relmse=c["relmse"], mean_diff=round(mm / m_cycles - 1.0, 5))
            if "passes_ms" in stats:
                row["gpu_ms"] = round(stats["passes_ms"].get("gpu_total", 0.0), 1)
                row["photons_stored"] = stats.get("photons", {}).get("stored")
            rows.append(row)
            print("%-14s %-28s %s: %6.2f dB, mean %+.2f %%, %.1f s" % (
                scene, label, settings, row["psnr_db"] or 0, 100 * row["mean_diff"], dt), flush=True)

        dev_opt = ["--device", str(args.device)] if args.device is not None else []
        for photons, maps, spp in GPU_POINTS[mode]:
            base = [args.exe, "render", gltf, "--photons", str(photons), "--iterations", str(maps), "--spp", str(spp)]
            s = {"photons": photons, "maps": maps, "spp": spp}
            point("GPU, glossy eye paths", base + dev_opt, s)
            point("GPU, gather at first hit", base + dev_opt + ["--max-specular-depth", "0"], s)
        for spp in REF_SPP[mode]:
            point("reference", [args.exe, "reference", gltf, "--spp", str(spp), "--max-bounces", "64"], {"spp": spp})
        results["scenes"][scene] = {"cycles": cyc[scene], "points": rows}
    results["load_after"] = os.getloadavg()[0]
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)
    with open(os.path.join(out, "PRINCIPLED.md"), "w") as f:
        f.write("# Principled studio against Cycles 3.4 (%s, %s)\n\n" % (device, mode))
        f.write("Error against Cycles' %d-sample render (its own noise %.1f dB); wall seconds per render.\n\n" % (
            cyc["studio"]["samples"], cyc["studio"]["noise_psnr_db"]))
        for scene in SCENES:
            f.write("## %s\n\n| renderer | photons/map | maps | spp | wall | PSNR | SSIM | mean |\n"
                    "|---|---:|---:|---:|---:|---:|---:|---:|\n" % scene)
            for r in results["scenes"][scene]["points"]:
                f.write("| %s | %s | %s | %s | %.1f s | %.2f dB | %.4f | %+.2f %% |\n" % (
                    r["label"], r.get("photons", "-"), r.get("maps", "-"), r["spp"], r["wall_s"], r["psnr_db"] or 0,
                    r["ssim"], 100 * r["mean_diff"]))
            f.write("\n")
    print("wrote", out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
