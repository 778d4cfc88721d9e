#!/usr/bin/env python3
"""Seed 004 Table 2 on our samples: the view-sample cluster hierarchy
(`render --estimator vsch`, cluster-trivial and `--vsch-directional`) over
photon count and photon radius, SSIM and PSNR against an Embree reference,
with the estimator's time, beside the LBVH gather (`--estimator lbvh`) at
the same photon counts (the paper's third column is Mara et al.'s tiled
splatting; ours is the gather the product ships).

  python3 bench/vsch_table2.py [--exe build/photonbridge] [--width 64]
      [--rows 16384:0.2,65536:0.1,262144:0.05] [--spp 4] [--ref-spp 512]
      [--scenes samples/cornell_box/cornell_box.gltf] [--out DIR]

Each row is (photon paths per map, radius in metres; radius 0: each
photon's own footprint radius, the estimator's default). One photon map per
sample pass (--iterations = --spp), so the hierarchy, the splat and the
estimate run spp times; the time is the frame's estimator time
(passes_ms.gather: GPU timestamps around the estimator's record, all
samples). PSNR and SSIM from `photonbridge compare` (display image, the
shared view; SSIM in %, as the paper's table).

--ablation PATHS:RADIUS also renders that row with seed 004 Figure 9's
optimisations turned off one at a time (PB_VSCH_ABLATE=trivial: no
cluster-trivial acceptance, every enclosed node gets a list entry;
=cone: no normal-cone rejection; =trivial,cone: neither).

Writes VSCH_TABLE2.md and vsch_table2.json to --out (default
bench/results/lavapipe/vsch_table2; images under its ignored work/)."""
import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import time


def run(cmd):
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (p.returncode, " ".join(cmd), p.stderr[-2000:]))
    return time.time() - t0, p.stdout + p.stderr


def compare(exe, a, b, work):
    js = a[:-4] + "_cmp.json"
    run([exe, "compare", a, b, "--json", js, "-q"])
    j = json.load(open(js))
    return j["psnr_db"], j["ssim"]


def estimator_ms(j):
    pm = j.get("passes_ms", {})
    for k in ("estimate", "gather"):
        if pm.get(k) is not None:
            return pm[k]
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--exe", default="build/photonbridge")
    ap.add_argument("--width", type=int, default=64)
    ap.add_argument("--rows", default="16384:0.2,16384:0,65536:0.1,65536:0,262144:0.05,262144:0")
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--ref-spp", type=int, default=512)
    ap.add_argument("--scenes", default="samples/cornell_box/cornell_box.gltf")
    ap.add_argument("--out", default="bench/results/lavapipe/vsch_table2")
    ap.add_argument("--ablation", default="65536:0")
    a = ap.parse_args()
    work = os.path.join(a.out, "work")
    os.makedirs(work, exist_ok=True)
    rows = []
    for scene in a.scenes.split(","):
        name = os.path.splitext(os.path.basename(scene))[0]
        ref = os.path.join(work, "%s_ref_%d_%d.exr" % (name, a.width, a.ref_spp))
        if not os.path.exists(ref):
            run([a.exe, "reference", scene, "-o", ref, "--width", str(a.width), "--spp", str(a.ref_spp), "-q"])
        for spec in a.rows.split(","):
            photons, radius = spec.split(":")
            photons, radius = int(photons), float(radius)
            row = {"scene": name, "photons": photons, "radius": radius}
            variants = [("cluster", ["--estimator", "vsch"]),
                        ("directional", ["--estimator", "vsch", "--vsch-directional"])]
            if radius == 0:
                variants.append(("lbvh", ["--estimator", "lbvh"]))
            for vname, extra in variants:
                tag = "%s_%s_%d_%g" % (name, vname, photons, radius)
                exr = os.path.join(work, tag + ".exr")
                js = os.path.join(work, tag + ".json")
                cmd = [a.exe, "render", scene, "-o", exr, "--json", js, "--width", str(a.width), "--photons",
                       str(photons), "--spp", str(a.spp), "--iterations", str(a.spp), "--seed", "3", "-q"] + extra
                if vname != "lbvh" and radius > 0:
                    cmd += ["--vsch-radius", str(radius)]
                wall, _ = run(cmd)
                j = json.load(open(js))
                psnr, ssim = compare(a.exe, exr, ref, work)
                est = j.get("estimator", {})
                row[vname] = {"psnr": psnr, "ssim": ssim, "ms": estimator_ms(j), "wall_s": wall,
                              "stats": {k: v for k, v in est.items() if k != "name"}}
            rows.append(row)
            print(json.dumps(row), flush=True)
    abl = []
    if a.ablation:
        photons, radius = a.ablation.split(":")
        scene = a.scenes.split(",")[0]
        name = os.path.splitext(os.path.basename(scene))[0]
        ref = os.path.join(work, "%s_ref_%d_%d.exr" % (name, a.width, a.ref_spp))
        for off in ["", "trivial", "cone", "trivial,cone"]:
            tag = "%s_ablate_%s_%s_%s" % (name, off.replace(",", "+") or "none", photons, radius)
            exr = os.path.join(work, tag + ".exr")
            js = os.path.join(work, tag + ".json")
            cmd = [a.exe, "render", scene, "-o", exr, "--json", js, "--width", str(a.width), "--photons", photons,
                   "--spp", str(a.spp), "--iterations", str(a.spp), "--seed", "3", "-q", "--estimator", "vsch"]
            if float(radius) > 0:
                cmd += ["--vsch-radius", radius]
            env = dict(os.environ, PB_VSCH_ABLATE=off)
            t0 = time.time()
            p = subprocess.run(cmd, capture_output=True, text=True, env=env)
            if p.returncode != 0:
                sys.exit("failed: %s\n%s" % (" ".join(cmd), p.stderr[-2000:]))
            j = json.load(open(js))
            psnr, ssim = compare(a.exe, exr, ref, work)
            abl.append({"off": off or "none", "ms": estimator_ms(j), "wall_s": time.time() - t0, "psnr": psnr,
                        "ssim": ssim, "stats": {k: v for k, v in j.get("estimator", {}).items() if k != "name"}})
            print(json.dumps(abl[-1]), flush=True)
    load = open("/proc/loadavg").read().split()[:3] if os.path.exists("/proc/loadavg") else []
    dev = subprocess.run([a.exe, "info", "--devices"], capture_output=True, text=True).stdout.strip()
    meta = {"date": datetime.datetime.utcnow().isoformat() + "Z", "machine": platform.node(), "cpus": os.cpu_count(),
            "load": load, "devices": dev, "width": a.width, "spp": a.spp, "ref_spp": a.ref_spp}
    json.dump({"meta": meta, "rows": rows, "ablation": abl}, open(os.path.join(a.out, "vsch_table2.json"), "w"), indent=1)
    with open(os.path.join(a.out, "VSCH_TABLE2.md"), "w") as f:
        f.write("# Seed 004 Table 2: vsch cluster-trivial and directional (and the LBVH gather)\n\n")
        f.write("%s, %d CPUs, load %s, %s\n\n" % (meta["date"], meta["cpus"], " ".join(load), dev))
        f.write("%d px wide, %d spp = %d photon maps, reference %d spp; radius 0: each photon's footprint radius\n\n"
                % (a.width, a.spp, a.spp, a.ref_spp))
        f.write("| scene | paths/map | radius m | cluster SSIM % | PSNR dB | ms | directional SSIM % | PSNR dB | ms "
                "| LBVH SSIM % | PSNR dB | ms |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            cells = []
            for v in ("cluster", "directional", "lbvh"):
                x = r.get(v)
                if x:
                    cells.append("%.1f | %.2f | %s" % (100 * x["ssim"], x["psnr"],
                                                        "%.0f" % x["ms"] if x["ms"] is not None else "-"))
                else:
                    cells.append("- | - | -")
            f.write("| %s | %d | %s | %s |\n" % (r["scene"], r["photons"], r["radius"] or "footprint",
                                                 " | ".join(cells)))
        if abl:
            f.write("\nSeed 004 Figure 9's optimisations off (%s, radius %s):\n\n" % (a.ablation.split(":")[0],
                                                                                  a.ablation.split(":")[1]))
            f.write("| off | estimator ms | PSNR dB | SSIM % | list pairs | trivial accepts | cone rejects |\n"
                    "|---|---|---|---|---|---|---|\n")
            for x in abl:
                st = x["stats"]
                f.write("| %s | %s | %.2f | %.1f | %s | %s | %s |\n" % (
                    x["off"], "%.0f" % x["ms"] if x["ms"] is not None else "-", x["psnr"], 100 * x["ssim"],
                    st.get("list_pairs", "-"), st.get("trivial_accepts", "-"), st.get("cone_rejects", "-")))


if __name__ == "__main__":
    main()
