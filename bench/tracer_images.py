#!/usr/bin/env python3
"""The image-space photon tracer (seed 003, `render --tracer images`)
against the BVH tracer: speed against error, error against the number of
maps k, and the miss rate per sample.

  python3 bench/tracer_images.py [--exe build/photonbridge] [--width W]
      [--photons N] [--ks 2,4,8,15] [--ref-spp N] [--out DIR]

Still scenes (cornell_box and the given --scenes): one reference image each
(`photonbridge reference`, cached in the output folder), then `render` with
--tracer bvh and with --tracer images for every k; per run the photon trace
time (GPU timestamps, all iterations), the wall time, the images tracer's
miss rate (photons.image_miss_rate: segments no map confirmed, over all
segments), its map render and selection times, and the display PSNR and
scene-linear relMSE against the reference (`photonbridge compare`).

Animated sample (cornell_caustics_moving_sphere, frames 0:F): `render
--frames` with either tracer, no temporal or A-Trous filter; per frame the
scene update (BVH refit), the photon trace and, for images, the maps'
re-render (every frame) and the candidates' (every 5th); mean over frames
2..F (frame 0 builds everything).

Writes TRACER_IMAGES.md and tracer_images.json to --out (default
bench/results/lavapipe/tracer_images; images and per-run JSON under its
work/, not committed) with the machine and the date."""
import argparse
import datetime
import json
import os
import platform
import re
import subprocess
import sys
import time


def run(cmd):
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (p.returncode, " ".join(cmd), p.stderr[-2000:]))
    return time.time() - t0, p.stdout + p.stderr


def compare(exe, a, b):
    _, out = run([exe, "compare", a, b])
    psnr = float(re.search(r"PSNR\s+([-0-9.]+)", out).group(1))
    rel = float(re.search(r"relMSE\s+([-0-9.e]+)", out).group(1))
    return psnr, rel


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--exe", default="build/photonbridge")
    ap.add_argument("--width", type=int, default=64)
    ap.add_argument("--photons", type=int, default=1 << 16)
    ap.add_argument("--iterations", type=int, default=2)
    ap.add_argument("--ks", default="2,4,8,15")
    ap.add_argument("--ref-spp", type=int, default=512)
    ap.add_argument("--frames", type=int, default=5)
    ap.add_argument("--scenes", default="samples/cornell_box/cornell_box.gltf")
    ap.add_argument("--out", default="bench/results/lavapipe/tracer_images")
    a = ap.parse_args()
    work = os.path.join(a.out, "work")  # images, per-run JSON, the cached reference (ignored by git)
    os.makedirs(work, exist_ok=True)
    ks = [int(k) for k in a.ks.split(",")]
    common = ["--width", str(a.width), "--photons", str(a.photons), "--iterations", str(a.iterations),
              "--spp", str(a.iterations)]
    rows = []
    for scene in a.scenes.split(","):
        name = os.path.splitext(os.path.basename(scene))[0]
        ref = os.path.join(work, "%s_ref_%d.exr" % (name, a.width))
        if not os.path.exists(ref):
            run([a.exe, "reference", scene, "-o", ref, "--width", str(a.width), "--spp", str(a.ref_spp)])
        for tracer, k in [("bvh", 0)] + [("images", k) for k in ks]:
            exr = os.path.join(work, "%s_%s_%d.exr" % (name, tracer, k))
            js = exr[:-4] + ".json"
            cmd = [a.exe, "render", scene, "-o", exr, "--json", js, "--tracer", tracer] + common
            if k:
                cmd += ["--image-maps", str(k)]
            wall, _ = run(cmd)
            j = json.load(open(js))
            ph = j["photons"]
            psnr, rel = compare(a.exe, exr, ref)
            rows.append({"scene": name, "tracer": tracer, "k": k, "wall_s": wall,
                         "trace_ms": j["passes_ms"]["photon_trace"], "stored": ph["stored"],
                         "emitted": ph["emitted"], "miss_rate": ph.get("image_miss_rate"),
                         "map_render_ms": ph.get("map_render_ms"), "select_ms": ph.get("select_ms"),
                         "psnr_db": psnr, "relmse": rel})
            print(rows[-1], flush=True)
    seq = []
    scene = "samples/cornell_caustics_moving_sphere/cornell_caustics_moving_sphere.gltf"
    for tracer in ["bvh", "images"]:
        pat = os.path.join(work, "seq_%s_#.exr" % tracer)
        js = os.path.join(work, "seq_%s.json" % tracer)
        run([a.exe, "render", scene, "--frames", "0:%d" % (a.frames - 1), "-o", pat, "--json", js,
             "--tracer", tracer, "--no-temporal", "--atrous-iterations", "0"] + common)
        j = json.load(open(js))
        fr = j["frames"][2:]
        mean = lambda f: sum(f(x) for x in fr) / len(fr)
        seq.append({"tracer": tracer, "frames": len(j["frames"]),
                    "scene_update_ms": mean(lambda x: x["passes_ms"]["scene_update"]),
                    "trace_ms": mean(lambda x: x["passes_ms"].get("photon_trace", 0)),
                    "frame_wall_ms": mean(lambda x: x["timing"]["frame_wall_ms"]),
                    "stored": mean(lambda x: x["photons"]["stored"]),
                    "miss_rate": mean(lambda x: x["photons"].get("image_miss_rate", 0)),
                    "map_render_ms": mean(lambda x: x["photons"].get("map_render_ms", 0))})
        print(seq[-1], flush=True)
    dev = subprocess.run([a.exe, "info", "--devices"], capture_output=True, text=True).stdout.strip()
    meta = {"date": datetime.datetime.utcnow().isoformat() + "Z", "machine": platform.node(),
            "cpus": os.cpu_count(), "devices": dev, "width": a.width, "photons": a.photons,
            "iterations": a.iterations, "ref_spp": a.ref_spp}
    json.dump({"meta": meta, "still": rows, "sequence": seq}, open(os.path.join(a.out, "tracer_images.json"), "w"),
              indent=1)
    with open(os.path.join(a.out, "TRACER_IMAGES.md"), "w") as f:
        f.write("# --tracer images against --tracer bvh\n\n%s, %d CPUs, %s\n\n" % (meta["date"], meta["cpus"], dev))
        f.write("%d px, %d photon paths x %d photon maps (iterations), reference %d spp\n\n" % (a.width, a.photons, a.iterations, a.ref_spp))
        f.write("| scene | tracer | k | trace ms | wall s | stored | miss rate | maps ms | select ms | PSNR dB | relMSE |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write("| %s | %s | %s | %.0f | %.1f | %d | %s | %s | %s | %.2f | %.4f |\n" % (
                r["scene"], r["tracer"], r["k"] or "-", r["trace_ms"], r["wall_s"], r["stored"],
                "%.3f" % r["miss_rate"] if r["miss_rate"] is not None else "-",
                "%.0f" % r["map_render_ms"] if r["map_render_ms"] is not None else "-",
                "%.0f" % r["select_ms"] if r["select_ms"] is not None else "-", r["psnr_db"], r["relmse"]))
        f.write("\nAnimated: cornell_caustics_moving_sphere, frames 2..%d (means)\n\n" % (a.frames - 1))
        f.write("| tracer | scene update ms | trace ms | maps ms | frame wall ms | stored | miss rate |\n|---|---|---|---|---|---|---|\n")
        for s in seq:
            f.write("| %s | %.1f | %.0f | %.0f | %.0f | %.0f | %.3f |\n" % (
                s["tracer"], s["scene_update_ms"], s["trace_ms"], s["map_render_ms"], s["frame_wall_ms"],
                s["stored"], s["miss_rate"]))


if __name__ == "__main__":
    main()
