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

--parts (default still,sequence) adds, each kept in the JSON beside the
others' last results:

  samples    every glTF sample (the still ones against their reference, the
             animated ones, --frames 0:2, against the BVH tracer's frames)
             with both tracers: it renders, the miss rate, the photons
             stored against the BVH's, the trace time and the error;
  heat       heat maps (`photonbridge compare --heatmap`, the indirect layer)
             of the images tracer against the BVH tracer at many photons, on
             cornell_box and sun_atrium (thin columns, occluded corners): what
             the maps miss; the PNGs beside the report;
  bandwidth  seed 003's variable bandwidth (--bandwidth-c0 C0) against the
             differential footprints (C0 = 0) on the still scenes, both
             tracers: error against the reference, k_PD;
  table1     the shape of seed 003 Table 1: frames per second (1000 / mean
             frame wall ms of frames 1..2 of cornell_caustics_moving_sphere,
             no filters) against resolution and photon paths, both tracers,
             beside the paper's numbers (GTX 260).

Writes TRACER_IMAGES.md and tracer_images.json to --out (default
bench/results/lavapipe/tracer_images; images and per-run JSON under its
work/, not committed) with the machine, the date and the load."""
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


STATIC = ["cornell_box", "cornell_caustics", "ring", "spot_room", "sun_atrium"]
ANIMATED = ["cornell_box_moving_light", "cornell_caustics_moving_sphere", "sun_atrium_flythrough"]
# Seed 003 Table 1 as the paper prints it (GeForce GTX 260, "Performance
# Statistics. T = number of triangles; GP = number of global photons; CP =
# number of caustic photons; B = number of light bounces"): figure, T, GP,
# CP, B, fps at 512^2 / 1024^2.
PAPER_TABLE1 = [
    ("1 (a)", "15k", "376k", "0", "3", "22.3 / 11.4"),
    ("1 (b)", "21k", "91k", "89k", "1", "13.6 / 12.8"),
    ("1 (c)", "84k", "403k", "2.9k", "3", "7.2 / 5.4"),
    ("1 (d)", "79k", "739k", "0", "2", "13.3 / 5.5"),
    ("11 (a)", "58k", "464k", "0", "1", "20.8 / 9.2"),
    ("11 (c)", "101k", "358k", "0", "2", "15.1 / 7.5"),
    ("11 (e)", "2.1k", "0", "164k", "1", "38.9 / 28.2"),
    ("10 (a)", "54k", "536k", "822k", "3", "7.4 / 6.3"),
]


def loadavg():
    try:
        return float(open("/proc/loadavg").read().split()[0])
    except OSError:
        return None


def sample(name):
    return "samples/%s/%s.gltf" % (name, name)


def mean_frames(j, key, first=1):
    fr = j["frames"][first:] or j["frames"]
    return sum(key(x) for x in fr) / len(fr)


def part_samples(a, work, common, width):
    rows = []
    for name in STATIC + ANIMATED:
        animated = name in ANIMATED
        r = {"scene": name, "animated": animated}
        outs = {}
        for tracer in ("bvh", "images"):
            js = os.path.join(work, "smp_%s_%s.json" % (name, tracer))
            if animated:
                pat = os.path.join(work, "smp_%s_%s_#.exr" % (name, tracer))
                cmd = [a.exe, "render", sample(name), "--frames", "0:2", "-o", pat, "--json", js, "--tracer", tracer,
                       "--no-temporal", "--atrous-iterations", "0"] + common
                outs[tracer] = pat.replace("#", "2")
            else:
                exr = os.path.join(work, "smp_%s_%s.exr" % (name, tracer))
                cmd = [a.exe, "render", sample(name), "-o", exr, "--json", js, "--tracer", tracer] + common
                outs[tracer] = exr
            wall, _ = run(cmd)
            j = json.load(open(js))
            if animated:
                ph = j["frames"][-1]["photons"]
                r[tracer] = {"wall_s": wall, "stored": mean_frames(j, lambda x: x["photons"]["stored"]),
                             "trace_ms": mean_frames(j, lambda x: x["passes_ms"].get("photon_trace", 0)),
                             "miss_rate": mean_frames(j, lambda x: x["photons"].get("image_miss_rate", 0))
                             if tracer == "images" else None}
            else:
                ph = j["photons"]
                r[tracer] = {"wall_s": wall, "stored": ph["stored"], "trace_ms": j["passes_ms"]["photon_trace"],
                             "miss_rate": ph.get("image_miss_rate")}
            if tracer == "images":
                r[tracer]["uncovered_share"] = ph.get("uncovered_share")
        if animated:
            r["psnr_vs_bvh_db"], r["relmse_vs_bvh"] = compare(a.exe, outs["images"], outs["bvh"])
        else:
            ref = os.path.join(work, "%s_ref_%d.exr" % (name, width))
            if not os.path.exists(ref):
                run([a.exe, "reference", sample(name), "-o", ref, "--width", str(width), "--spp", str(a.ref_spp)])
            for tracer in ("bvh", "images"):
                r[tracer]["psnr_db"], r[tracer]["relmse"] = compare(a.exe, outs[tracer], ref)
            r["psnr_vs_bvh_db"], r["relmse_vs_bvh"] = compare(a.exe, outs["images"], outs["bvh"])
        rows.append(r)
        print(r, flush=True)
    return rows


def part_heat(a, work, out):
    rows = []
    for name in ("cornell_box", "sun_atrium"):
        exrs = {}
        for tracer in ("bvh", "images"):
            exrs[tracer] = os.path.join(work, "heat_%s_%s.exr" % (name, tracer))
            js = exrs[tracer][:-4] + ".json"
            run([a.exe, "render", sample(name), "-o", exrs[tracer], "--json", js, "--tracer", tracer,
                 "--width", str(a.heat_width), "--photons", str(a.heat_photons), "--iterations", str(a.heat_maps),
                 "--spp", str(a.heat_maps)])
        png = os.path.join(out, "heat_%s_indirect.png" % name)
        _, txt = run([a.exe, "compare", exrs["images"], exrs["bvh"], "--layer", "indirect", "--heatmap", png,
                      "--json", "-"])
        cj = json.loads(txt[txt.index("{"):txt.rindex("}") + 1])
        ji = json.load(open(exrs["images"][:-4] + ".json"))["photons"]
        jb = json.load(open(exrs["bvh"][:-4] + ".json"))["photons"]
        rows.append({"scene": name, "png": os.path.basename(png), "compare": cj,
                     "stored_ratio": ji["stored"] / jb["stored"], "miss_rate": ji.get("image_miss_rate"),
                     "uncovered_share": ji.get("uncovered_share")})
        print(rows[-1], flush=True)
    return rows


def part_bandwidth(a, work, common):
    rows = []
    for scene in a.scenes.split(","):
        name = os.path.splitext(os.path.basename(scene))[0]
        ref = os.path.join(work, "%s_ref_%d.exr" % (name, a.width))
        if not os.path.exists(ref):
            run([a.exe, "reference", scene, "-o", ref, "--width", str(a.width), "--spp", str(a.ref_spp)])
        for tracer in ("bvh", "images"):
            for c0 in [float(x) for x in a.c0s.split(",")]:
                exr = os.path.join(work, "bw_%s_%s_%g.exr" % (name, tracer, c0))
                js = exr[:-4] + ".json"
                cmd = [a.exe, "render", scene, "-o", exr, "--json", js, "--tracer", tracer] + common
                if c0 > 0:
                    cmd += ["--bandwidth-c0", "%g" % c0]
                wall, _ = run(cmd)
                ph = json.load(open(js))["photons"]
                psnr, rel = compare(a.exe, exr, ref)
                rows.append({"scene": name, "tracer": tracer, "c0": c0, "wall_s": wall, "k_pd": ph.get("k_pd"),
                             "stored": ph["stored"], "clamped_share": ph.get("clamped_share"), "psnr_db": psnr,
                             "relmse": rel})
                print(rows[-1], flush=True)
    return rows


def part_table1(a, work):
    rows = []
    scene = sample("cornell_caustics_moving_sphere")
    for width in [int(x) for x in a.t1_widths.split(",")]:
        for photons in [int(x) for x in a.t1_photons.split(",")]:
            for tracer in ("bvh", "images"):
                js = os.path.join(work, "t1_%d_%d_%s.json" % (width, photons, tracer))
                run([a.exe, "render", scene, "--frames", "0:2", "-o", os.path.join(work, "t1_#.exr"), "--json", js,
                     "--tracer", tracer, "--width", str(width), "--height", str(width), "--photons", str(photons),
                     "--no-temporal", "--atrous-iterations", "0"])
                j = json.load(open(js))
                ms = mean_frames(j, lambda x: x["timing"]["frame_wall_ms"])
                rows.append({"width": width, "photons": photons, "tracer": tracer, "frame_wall_ms": ms,
                             "fps": 1000.0 / ms,
                             "trace_ms": mean_frames(j, lambda x: x["passes_ms"].get("photon_trace", 0)),
                             "miss_rate": mean_frames(j, lambda x: x["photons"].get("image_miss_rate", 0))
                             if tracer == "images" else None,
                             "load": loadavg()})
                print(rows[-1], flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--exe", default="build/photonbridge")
    ap.add_argument("--width", type=int, default=64)
    ap.add_argument("--photons", type=int, default=1 << 16)
    ap.add_argument("--iterations", type=int, default=2)
    ap.add_argument("--ks", default="2,4,8,15")
    ap.add_argument("--ref-spp", type=int, default=512)
    ap.add_argument("--frames", type=int, default=5)
    ap.add_argument("--parts", default="still,sequence", help="still,sequence,samples,heat,bandwidth,table1")
    ap.add_argument("--heat-width", type=int, default=96)
    ap.add_argument("--heat-photons", type=int, default=1 << 17)
    ap.add_argument("--heat-maps", type=int, default=2, help="photon maps (iterations) of the heat renders")
    ap.add_argument("--t1-widths", default="128,256,512")
    ap.add_argument("--c0s", default="0,0.5,1,2,4", help="--bandwidth-c0 values (0: the differential footprints)")
    ap.add_argument("--t1-photons", default="16384,65536")
    ap.add_argument("--scenes", default="samples/cornell_box/cornell_box.gltf")
    ap.add_argument("--out", default="bench/results/lavapipe/tracer_images")
    a = ap.parse_args()
    work = os.path.join(a.out, "work")  # images, per-run JSON, the cached reference (ignored by git)
    os.makedirs(work, exist_ok=True)
    ks = [int(k) for k in a.ks.split(",")]
    common = ["--width", str(a.width), "--photons", str(a.photons), "--iterations", str(a.iterations),
              "--spp", str(a.iterations)]
    parts = a.parts.split(",")
    jpath = os.path.join(a.out, "tracer_images.json")
    res = json.load(open(jpath)) if os.path.exists(jpath) else {}
    load0 = loadavg()
    dev = subprocess.run([a.exe, "info", "--devices"], capture_output=True, text=True).stdout.strip()
    meta = {"date": datetime.datetime.utcnow().isoformat() + "Z", "machine": platform.node(),
            "cpus": os.cpu_count(), "devices": dev, "width": a.width, "photons": a.photons,
            "iterations": a.iterations, "ref_spp": a.ref_spp}
    res.setdefault("runs", {})

    def done(pt, t0, l0):
        # Saved after every part: a later failure keeps what was measured.
        res["runs"][pt] = {"date": t0, "load_start": l0, "load_end": loadavg()}
        if pt == "still" or "meta" not in res:
            res["meta"] = meta
        json.dump(res, open(jpath, "w"), indent=1)
        write_md(res, os.path.join(a.out, "TRACER_IMAGES.md"))

    for pt in parts:
        t0, l0 = datetime.datetime.utcnow().isoformat() + "Z", loadavg()
        if pt == "still":
            res["still"] = part_still(a, work, ks, common)
        elif pt == "sequence":
            res["sequence"] = part_sequence(a, work, common)
        elif pt == "samples":
            res["samples"] = part_samples(a, work, ["--width", "48", "--photons", "32768", "--iterations", "2",
                                                    "--spp", "2"], 48)
            res["samples_settings"] = ("48 px, 32,768 photon paths x 2 maps, 2 spp, k = 8 maps of 128^2, reference "
                                       "%d spp" % a.ref_spp)
        elif pt == "heat":
            res["heat"] = part_heat(a, work, a.out)
            res["heat_settings"] = "%d px, %d photon paths x %d photon maps, %d spp, k = 8 environment maps of 128^2" % (
                a.heat_width, a.heat_photons, a.heat_maps, a.heat_maps)
        elif pt == "bandwidth":
            res["bandwidth"] = part_bandwidth(a, work, common)
            res["bandwidth_settings"] = "%d px, %d photon paths x %d photon maps, %d spp, reference %d spp" % (
                a.width, a.photons, a.iterations, a.iterations, a.ref_spp)
        elif pt == "table1":
            res["table1"] = part_table1(a, work)
        else:
            sys.exit("unknown part %s" % pt)
        done(pt, t0, l0)


def part_still(a, work, ks, common):
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
    return rows


def part_sequence(a, work, common):
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
    return seq


def fmt(v, f="%.3f"):
    return f % v if isinstance(v, (int, float)) else "-"


def write_md(res, path):
    meta = res.get("meta", {})
    with open(path, "w") as f:
        f.write("# --tracer images against --tracer bvh\n\n%s, %s CPUs, %s\n\n" % (
            meta.get("date"), meta.get("cpus"), meta.get("devices")))
        runs = res.get("runs", {})
        if runs:
            f.write("Parts last run (UTC, 1-min load at start / end): %s\n\n" % "; ".join(
                "%s %s (%s / %s)" % (k, v["date"][:16], fmt(v["load_start"], "%.1f"), fmt(v["load_end"], "%.1f"))
                for k, v in sorted(runs.items())))
        if res.get("still"):
            f.write("%d px, %d photon paths x %d photon maps (iterations), reference %d spp\n\n" % (
                meta["width"], meta["photons"], meta["iterations"], meta["ref_spp"]))
            f.write("| scene | tracer | k | trace ms | wall s | stored | miss rate | maps ms | select ms | PSNR dB | relMSE |\n")
            f.write("|---|---|---|---|---|---|---|---|---|---|---|\n")
            for r in res["still"]:
                f.write("| %s | %s | %s | %.0f | %.1f | %d | %s | %s | %s | %.2f | %.4f |\n" % (
                    r["scene"], r["tracer"], r["k"] or "-", r["trace_ms"], r["wall_s"], r["stored"],
                    fmt(r["miss_rate"]), fmt(r["map_render_ms"], "%.0f"), fmt(r["select_ms"], "%.0f"), r["psnr_db"],
                    r["relmse"]))
        if res.get("sequence"):
            f.write("\nAnimated: cornell_caustics_moving_sphere, frames 2..4 (means)\n\n")
            f.write("| tracer | scene update ms | trace ms | maps ms | frame wall ms | stored | miss rate |\n"
                    "|---|---|---|---|---|---|---|\n")
            for q in res["sequence"]:
                f.write("| %s | %.1f | %.0f | %.0f | %.0f | %.0f | %.3f |\n" % (
                    q["tracer"], q["scene_update_ms"], q["trace_ms"], q["map_render_ms"], q["frame_wall_ms"],
                    q["stored"], q["miss_rate"]))
        for line in samples_md(res, ""):
            f.write(line + "\n")


def samples_md(res, prefix=""):
    """The per-sample, heat-map and Table 1 tables (also run_bench.py's
    BENCHMARKS.md section, which imports this)."""
    L = []
    if res.get("samples"):
        L.append("\nEvery sample with either tracer (%s; animated: frames 0:2, means of frames 1-2, error of the "
                 "last frame against the BVH tracer's): the images tracer renders every one." % res["samples_settings"])
        L.append("")
        L.append("| sample | animated | bvh trace ms | images trace ms | stored / BVH's | miss rate | uncovered share "
                 "| bvh PSNR dB | images PSNR dB | images vs bvh PSNR dB |")
        L.append("|---|---|---|---|---|---|---|---|---|---|")
        for r in res["samples"]:
            b, i = r["bvh"], r["images"]
            L.append("| %s | %s | %.0f | %.0f | %.2f | %s | %s | %s | %s | %.2f |" % (
                r["scene"], "yes" if r["animated"] else "no", b["trace_ms"], i["trace_ms"],
                i["stored"] / b["stored"] if b["stored"] else 0, fmt(i["miss_rate"]), fmt(i.get("uncovered_share")),
                fmt(b.get("psnr_db"), "%.2f"), fmt(i.get("psnr_db"), "%.2f"), r["psnr_vs_bvh_db"]))
    if res.get("heat"):
        L.append("\nWhat the maps miss: heat maps of the indirect layer, `--tracer images` against `--tracer bvh` "
                 "(%s; `photonbridge compare --layer indirect --heatmap`):" % res["heat_settings"])
        L.append("")
        L.append("| sample | heat map | indirect PSNR dB vs bvh | relMSE | stored / BVH's | miss rate | uncovered share |")
        L.append("|---|---|---|---|---|---|---|")
        for h in res["heat"]:
            c = h["compare"]
            L.append("| %s | %s | %s | %s | %.3f | %s | %s |" % (
                h["scene"], "[%s](%s%s)" % (h["png"], prefix, h["png"]), fmt(c.get("psnr_db"), "%.2f"), fmt(c.get("relmse"), "%.4f"), h["stored_ratio"],
                fmt(h["miss_rate"]), fmt(h.get("uncovered_share"))))
    if res.get("bandwidth"):
        L.append("\nSeed 003's variable bandwidth, h = C0 / sqrt(p) sqrt(A / N) (`--bandwidth-c0 C0`; C0 0: the "
                 "differential footprints of seed 000, the default) (%s):" % res["bandwidth_settings"])
        L.append("")
        L.append("| scene | tracer | C0 | k_PD | stored | at r_max | PSNR dB | relMSE |")
        L.append("|---|---|---|---|---|---|---|---|")
        for r in res["bandwidth"]:
            L.append("| %s | %s | %s | %s | %d | %s | %.2f | %.4f |" % (
                r["scene"], r["tracer"], "%g" % r["c0"] if r["c0"] else "0 (differentials)", fmt(r["k_pd"], "%.1f"),
                r["stored"], fmt(r["clamped_share"]), r["psnr_db"], r["relmse"]))
    if res.get("table1"):
        t1 = res["table1"]
        widths = sorted({r["width"] for r in t1})
        photons = sorted({r["photons"] for r in t1})
        L.append("\nThe shape of seed 003 Table 1: frames per second (1000 / mean frame wall ms, frames 1-2 of "
                 "cornell_caustics_moving_sphere, no filters, 1 spp, every frame its maps re-rendered) against "
                 "resolution and photon paths, on this device:")
        L.append("")
        L.append("| photon paths | tracer | " + " | ".join("%d^2 fps" % w for w in widths) + " | images miss rate |")
        L.append("|---|---|" + "---|" * len(widths) + "---|")
        for p in photons:
            for tr in ("bvh", "images"):
                cells = []
                miss = None
                for w in widths:
                    r = next((x for x in t1 if x["width"] == w and x["photons"] == p and x["tracer"] == tr), None)
                    cells.append(fmt(r["fps"], "%.2f") if r else "-")
                    if r and r.get("miss_rate") is not None:
                        miss = r["miss_rate"]
                L.append("| %d | %s | %s | %s |" % (p, tr, " | ".join(cells), fmt(miss)))
        L.append("\nThe paper's Table 1 (GeForce GTX 260; T triangles, GP / CP global / caustic photons, B bounces; "
                 "its scenes, not these):\n")
        L.append("| figure | T | GP | CP | B | fps 512^2 / 1024^2 |")
        L.append("|---|---|---|---|---|---|")
        for row in PAPER_TABLE1:
            L.append("| " + " | ".join(row) + " |")
    return L


if __name__ == "__main__":
    main()
