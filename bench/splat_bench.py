#!/usr/bin/env python3
"""Screen-space splatting (seed 001 24.3, `render --estimator splat`) next to
the LBVH gather: the same scenes, photon budget, samples and seed through
both estimators, each against the reference (cached), with the estimators'
GPU times.

usage: splat_bench.py PHOTONBRIDGE OUTDIR [--scenes a,b] [--width N] [--spp N]
                      [--photons N] [--iterations N] [--ref-spp N]
                      [--estimators lbvh,splat] [--extra "ARGS"]
Prints one markdown table (bench/README.md, "Screen-space splatting")."""
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def main():
    a = sys.argv[1:]
    if len(a) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    exe, out = os.path.abspath(a[0]), os.path.abspath(a[1])
    opt = {"scenes": "cornell_box,spot_room", "width": "128", "spp": "16", "photons": "262144", "iterations": "4",
           "ref-spp": "1024", "estimators": "lbvh,splat", "extra": ""}
    rest = a[2:]
    while rest:
        k = rest.pop(0)
        if not k.startswith("--") or k[2:] not in opt or not rest:
            print("splat_bench.py: bad argument %s" % k, file=sys.stderr)
            return 2
        opt[k[2:]] = rest.pop(0)
    os.makedirs(out, exist_ok=True)
    rows = []
    for scene in opt["scenes"].split(","):
        path = os.path.join(ROOT, "samples", scene, scene + ".gltf")
        ref = os.path.join(out, "ref_%s_%s_%s.exr" % (scene, opt["width"], opt["ref-spp"]))
        if not os.path.exists(ref):
            subprocess.run([exe, "reference", path, "-o", ref, "--width", opt["width"], "--spp", opt["ref-spp"],
                            "--seed", "9", "-q"], check=True)
        for est in opt["estimators"].split(","):
            base = os.path.join(out, "%s_%s" % (scene, est))
            cmd = [exe, "render", path, "-o", base + ".exr", "--json", base + ".json", "--width", opt["width"],
                   "--spp", opt["spp"], "--photons", opt["photons"], "--iterations", opt["iterations"],
                   "--seed", "5", "--estimator", est, "-q"] + opt["extra"].split()
            t0 = time.time()
            p = subprocess.run(cmd, capture_output=True, text=True)
            wall = time.time() - t0
            if p.returncode != 0:
                print("%s %s: exit %d: %s" % (scene, est, p.returncode, p.stderr.strip()), file=sys.stderr)
                return 1
            js = json.load(open(base + ".json"))
            c = subprocess.run([exe, "compare", base + ".exr", ref, "--json", "-"], capture_output=True, text=True)
            m = json.loads(c.stdout)
            pm = js.get("passes_ms", {})
            rows.append((scene, est, m.get("psnr_db"), m.get("relmse"), m.get("ssim"), pm.get("gather"),
                         pm.get("lbvh_build"), pm.get("gpu_total"), wall))
    print("| scene | estimator | PSNR dB | relMSE | SSIM | estimate ms (all samples) | build ms | GPU total ms | wall s |")
    print("|---|---|---|---|---|---|---|---|---|")

    def f(v, fmt):
        return fmt % v if isinstance(v, (int, float)) else "-"

    for r in rows:
        print("| %s | %s | %s | %s | %s | %s | %s | %s | %.1f |" % (r[0], r[1], f(r[2], "%.2f"), f(r[3], "%.4f"),
                                                               f(r[4], "%.4f"), f(r[5], "%.1f"), f(r[6], "%.1f"),
                                                               f(r[7], "%.1f"), r[8]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
