#!/usr/bin/env python3
"""The noise threshold's honesty: the render's own noise estimate against its
true error.

    python3 bench/noise_threshold.py [--exe build/photonbridge] [--scenes a,b]
        [--width W] [--thresholds 0.04,0.02] [--ref-spp N] [--seeds 1,2]
        [--out DIR]

For each scene (samples/NAME/NAME.gltf, or a path) a converged Embree
reference at W x W (`photonbridge reference --spp N --estimate-noise`, cached
in DIR) and, per threshold and seed, `photonbridge render --noise-threshold
T`. Its --json gives the estimate (render/frame/noise.h: RMS noise of the display
image from two groups of independent photon maps) and what stopped it; the
true error is `compare`'s display PSNR against the reference through the
built-in config's sRGB Standard view (the display the estimate is measured
on), e = 10^(-PSNR / 20), with the reference's own noise (from its two
halves) taken out: e_true^2 = e^2 - e_ref^2. The ratio estimate / e_true is 1 for an
estimate that sees the whole error; below 1 the render is biased beyond its
noise (the footprints' blur), above 1 the estimate is pessimistic.

Writes DIR/results.json and DIR/NOISE.md (a table). DIR defaults to
bench/results/lavapipe/noise.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def scene_path(name):
    if os.path.exists(name):
        return name
    return os.path.join(ROOT, "samples", name, name + ".gltf")


def run(cmd):
    t0 = time.time()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit("noise_threshold: %s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr.strip()[-400:]))
    return time.time() - t0


def compare(exe, test, ref):
    p = subprocess.run([exe, "compare", test, ref, "--ocio-config", "built-in", "--view", "Standard", "--json", "-"],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit("noise_threshold: compare failed: " + p.stderr.strip())
    return json.loads(p.stdout)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "photonbridge"))
    ap.add_argument("--scenes", default="cornell_box,cornell_caustics,spot_room,ring")
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--thresholds", default="0.04,0.02")
    ap.add_argument("--ref-spp", type=int, default=2048)
    ap.add_argument("--seeds", default="1")
    ap.add_argument("--extra", default="", help="more render options, space-separated")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "lavapipe", "noise"))
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for name in a.scenes.split(","):
        sp = scene_path(name)
        base = os.path.splitext(os.path.basename(sp))[0]
        size = ["--width", str(a.width), "--height", str(a.width)]
        ref = os.path.join(a.out, "%s_ref_%d_%d.exr" % (base, a.width, a.ref_spp))
        refj = ref[:-4] + ".json"
        if not os.path.exists(ref):
            run([a.exe, "reference", sp, "-o", ref, "--spp", str(a.ref_spp), "--estimate-noise", "--json", refj,
                 "-q"] + size)
        ref_noise = json.load(open(refj)).get("noise", {})
        for t in a.thresholds.split(","):
            for seed in a.seeds.split(","):
                out = os.path.join(a.out, "%s_t%s_s%s.exr" % (base, t, seed))
                js = out[:-4] + ".json"
                wall = run([a.exe, "render", sp, "-o", out, "--noise-threshold", t, "--seed", seed, "--json", js,
                            "-q"] + size + a.extra.split())
                j = json.load(open(js))
                m = compare(a.exe, out, ref)
                e_meas = 10 ** (-m["psnr_db"] / 20)
                # The reference's own noise is independent of the render's:
                # e_meas^2 = e_true^2 + e_ref^2, so it is taken out (the
                # reference's noise from its two halves, noise.psnr_db).
                e_ref = 10 ** (-ref_noise["psnr_db"] / 20) if ref_noise and ref_noise.get("psnr_db") else 0.0
                e_true = math.sqrt(max(e_meas * e_meas - e_ref * e_ref, 1e-12))
                est = j["noise"]["estimate"]
                row = {"scene": base, "threshold": float(t), "seed": int(seed), "width": a.width,
                       "maps": j["photons"]["iterations"], "photons_emitted": j["photons"]["emitted"],
                       "photons_stored": j["photons"]["stored"], "stop": j["stop"], "estimate": est,
                       "psnr_estimate": j["noise"]["psnr_estimate"], "psnr_measured": m["psnr_db"],
                       "psnr_true": -20 * math.log10(e_true), "e_true": e_true,
                       "ratio": est / e_true if est else None, "wall_s": wall,
                       "reference_spp": a.ref_spp, "reference_noise_psnr": (ref_noise or {}).get("psnr_db")}
                rows.append(row)
                print("%-18s T %-6s seed %s: %3d maps, estimate %.1f dB, true %.1f dB, ratio %.2f, %s, %.1f s" %
                      (base, t, seed, row["maps"], row["psnr_estimate"] or 0, row["psnr_true"], row["ratio"] or 0,
                       j["stop"], wall), flush=True)
    with open(os.path.join(a.out, "results.json"), "w") as f:
        json.dump({"rows": rows, "exe": a.exe, "extra": a.extra, "date": time.strftime("%Y-%m-%d %H:%M")}, f,
                  indent=1)
    with open(os.path.join(a.out, "NOISE.md"), "w") as f:
        f.write("| scene | T | seed | maps | estimate dB | true dB | measured dB | reference noise dB | "
                "estimate / true error | stop | s |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write("| %s | %g | %d | %d | %.1f | %.1f | %.1f | %.1f | %.2f | %s | %.1f |\n" %
                    (r["scene"], r["threshold"], r["seed"], r["maps"], r["psnr_estimate"] or 0, r["psnr_true"],
                     r["psnr_measured"], r["reference_noise_psnr"] or 0, r["ratio"] or 0, r["stop"], r["wall_s"]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
