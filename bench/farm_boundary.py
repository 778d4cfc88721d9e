#!/usr/bin/env python3
"""Chunk boundaries against the inside of a chunk.

One run renders frames 0..N-1 of an animated sample with per-frame
references (--reference-spp, cached); then the shot is cut into chunks of C
frames, every chunk after the first rendered as its own process with
--warmup W (the first chunk is the one run's first C frames, as a farm's
first task with the same warm-up would be), for several W. Reported, per W:

  excess flicker at the boundaries: mean over the boundary pairs (f-1 from
      the previous chunk, f from the next) of |I_f - I_{f-1}| - |R_f - R_{f-1}|
      (scene-linear beauty, mean over pixels and R,G,B; R the reference),
      against the one run's excess flicker at the same pairs and over all
      its pairs (mean and standard deviation, the noise);
  error: mean relMSE against the reference of the chunks' first frames and
      of the one run's same frames;
  difference: mean |chunk frame - one-run frame| over the chunks' first
      frames, relative to the mean beauty (how much older history mattered).

usage: farm_boundary.py PHOTONBRIDGE EXR_PROBE ROOT WORKDIR [--frames N] [--chunk C]
         [--warmups 0,1,2,4,8] [--size 48] [--photons 8192] [--reference-spp 256]
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time


def exr_rgb(probe, path):
    p = subprocess.run([probe, path], capture_output=True, text=True, check=True)
    d = json.loads(p.stdout)
    return [d["channels"][c] for c in ("R", "G", "B")]


def mean_abs(a, b):
    n = len(a[0]) * 3
    return sum(abs(x - y) for ca, cb in zip(a, b) for x, y in zip(ca, cb)) / n


def mean_val(a):
    return sum(sum(c) for c in a) / (3 * len(a[0]))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe")
    ap.add_argument("probe")
    ap.add_argument("root")
    ap.add_argument("work")
    ap.add_argument("--scene", default="cornell_box_moving_light")
    ap.add_argument("--frames", type=int, default=24)
    ap.add_argument("--chunk", type=int, default=6)
    ap.add_argument("--warmups", default="0,1,2,4,8")
    ap.add_argument("--size", type=int, default=48)
    ap.add_argument("--photons", type=int, default=8192)
    ap.add_argument("--reference-spp", type=int, default=256)
    ap.add_argument("--seed", type=int, default=11)
    a = ap.parse_args()
    scene = os.path.join(a.root, "samples", a.scene, a.scene + ".gltf")
    os.makedirs(a.work, exist_ok=True)
    cache = os.path.join(a.work, "reference_cache")
    common = [a.exe, "render", scene, "--width", str(a.size), "--height", str(a.size), "--photons", str(a.photons),
              "--seed", str(a.seed), "--reference-spp", str(a.reference_spp), "--reference-cache", cache, "-q"]
    t0 = time.time()
    one = os.path.join(a.work, "one")
    os.makedirs(one, exist_ok=True)
    subprocess.run(common + ["--frames", "0:%d" % (a.frames - 1), "-o", one + "/f_###.exr",
                             "--json", one + "/seq.json"], check=True)
    js = json.load(open(one + "/seq.json"))
    fr = {f["frame"]: f for f in js["frames"]}
    excess_one = {f: fr[f]["reference"]["change_result"] - fr[f]["reference"]["change_reference"]
                  for f in fr if "change_result" in fr[f]["reference"]}
    vals = list(excess_one.values())
    m_in = sum(vals) / len(vals)
    sd_in = math.sqrt(sum((v - m_in) ** 2 for v in vals) / max(len(vals) - 1, 1))
    bounds = list(range(a.chunk, a.frames, a.chunk))
    ref = {f: exr_rgb(a.probe, fr[f]["reference"]["file"]) for f in fr}
    img_one = {f: exr_rgb(a.probe, one + "/f_%03d.exr" % f) for f in fr}
    level = sum(mean_val(img_one[f]) for f in fr) / len(fr)
    print("one run: %d frames of %s, %d px, %d photons, seed %d, reference %d spp (%.0f s)" %
          (a.frames, a.scene, a.size, a.photons, a.seed, a.reference_spp, time.time() - t0))
    print("one run excess flicker over all %d pairs: mean %.3g, sd %.3g (mean beauty %.3g)" %
          (len(vals), m_in, sd_in, level))
    print("boundaries at frames %s (chunks of %d)" % (bounds, a.chunk))
    rows = []
    for w in [int(x) for x in a.warmups.split(",")]:
        d = os.path.join(a.work, "w%d" % w)
        os.makedirs(d, exist_ok=True)
        t1 = time.time()
        img, err = {}, {}
        for b in bounds:
            e = min(b + a.chunk - 1, a.frames - 1)
            subprocess.run(common + ["--frames", "%d:%d" % (b, e), "--warmup", str(w), "-o", d + "/f_###.exr",
                                     "--json", d + "/c%d.json" % b], check=True)
            cj = json.load(open(d + "/c%d.json" % b))
            err[b] = cj["frames"][0]["reference"]["relmse"]
            img[b] = exr_rgb(a.probe, d + "/f_%03d.exr" % b)
        ex_b = [mean_abs(img[b], img_one[b - 1]) - mean_abs(ref[b], ref[b - 1]) for b in bounds]
        ex_same = [excess_one[b] for b in bounds]
        diff = [mean_abs(img[b], img_one[b]) / level for b in bounds]
        err_one = [fr[b]["reference"]["relmse"] for b in bounds]
        row = {"warmup": w, "boundary_excess": sum(ex_b) / len(ex_b), "one_run_same_pairs": sum(ex_same) / len(ex_same),
               "relmse_chunk": sum(err.values()) / len(err), "relmse_one": sum(err_one) / len(err_one),
               "diff_rel": sum(diff) / len(diff), "seconds": time.time() - t1}
        rows.append(row)
        print("warmup %2d: boundary excess flicker %.3g (one run, same pairs %.3g; inside mean %.3g sd %.3g); "
              "relMSE first frames %.4g (one run %.4g); |chunk - one run| %.3g of the mean; %.0f s" %
              (w, row["boundary_excess"], row["one_run_same_pairs"], m_in, sd_in, row["relmse_chunk"],
               row["relmse_one"], row["diff_rel"], row["seconds"]), flush=True)
    json.dump({"scene": a.scene, "frames": a.frames, "chunk": a.chunk, "size": a.size, "photons": a.photons,
               "reference_spp": a.reference_spp, "seed": a.seed, "inside_excess_mean": m_in,
               "inside_excess_sd": sd_in, "rows": rows}, open(os.path.join(a.work, "boundary.json"), "w"), indent=1)


if __name__ == "__main__":
    main()
