#!/usr/bin/env python3
"""Animated sequences: error against per-frame references and flicker, with
the filters off, the temporal filter only, and temporal + A-Trous,
plus the filters' cost per frame at 1920x1080 (pb_bench_filters).

  python3 bench/run_sequences.py [--exe build/photonbridge] [--device N]
      [--quick] [--frames A:B] [--width W] [--out DIR]

For each animated sample and each filter setting, `photonbridge render
--frames A:B --reference-spp N` renders the sequence and, once per pose
(cached under bench/cache/sequences), the reference renderer's image of the
same pose; --json gives per frame the PSNR and relMSE against it and the
frame-to-frame change of both. Reported per scene and setting:

  PSNR, relMSE    means over the frames (display PSNR, scene-linear relMSE);
  flicker         mean over frame pairs of mean |I_f - I_{f-1}| (linear RGB)
                  for the result, and the excess: that minus the reference's
                  own change (what the renderer adds to the motion's change);
  ms/frame        mean wall time per frame, and the filters' GPU time.

Writes SEQUENCES.md, sequences.json and sequences.csv to
bench/results/DEVICE/sequences/ (DEVICE: the Vulkan device's name) with the
machine, the device and the date.

Deformation cost (DEFORM.md and deform.json in the same folder; --deform-only
runs just this): bench/deform_scene.py's 100,000-triangle cylinder skinned to
four animated joints with two animated morph targets, the same mesh moved
rigidly by its node, and the same mesh static, each rendered as a sequence
(32 px, few photons, no filters, so that the frame is cheap): per frame (the
first, which uploads the scene, left out) the CPU pose (pb_scene_set_time:
skinning and morphing every vertex), the GPU scene update (BVH refit or
rebuild and the vertex upload) and the wall time."""
import argparse
import csv
import datetime
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import run_bench  # noqa: E402  (machine_info, devices, slug)

SCENES = ["cornell_box_moving_light", "cornell_caustics_moving_sphere", "sun_atrium_flythrough"]
SETTINGS = [("off", ["--no-temporal", "--atrous-iterations", "0"]),
            ("temporal", ["--atrous-iterations", "0"]),
            ("temporal+atrous", ["--atrous-iterations", "4"])]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "photonbridge"))
    ap.add_argument("--filters-exe", default=None, help="pb_bench_filters (default: beside --exe)")
    ap.add_argument("--device", type=int, default=None)
    ap.add_argument("--quick", action="store_true", help="8 frames, 48 px, one scene")
    ap.add_argument("--frames", default=None, help="frame range (default 0:23, one second at 24 fps)")
    ap.add_argument("--width", type=int, default=None, help="image width (default 96)")
    ap.add_argument("--photons", type=int, default=32768)
    ap.add_argument("--reference-spp", type=int, default=None, help="default 512")
    ap.add_argument("--filter-sizes", default="1920x1080", help="pb_bench_filters sizes")
    ap.add_argument("--out", default=None)
    ap.add_argument("--deform-only", action="store_true", help="only the deformation cost")
    ap.add_argument("--deform-frames", default=None, help="frames of the deformation runs (default 0:23, quick 0:7)")
    a = ap.parse_args()
    frames = a.frames or ("0:7" if a.quick else "0:23")
    width = a.width or (48 if a.quick else 96)
    ref_spp = a.reference_spp or (256 if a.quick else 512)
    scenes = SCENES[:1] if a.quick else SCENES
    dev_args = ["--device", str(a.device)] if a.device is not None else []
    devs = run_bench.devices(a.exe)
    dev = next((d for d in devs if (a.device is None and d["default"]) or d["index"] == a.device), None)
    dev_name = dev["name"] if dev else "unknown"
    out = a.out or os.path.join(HERE, "results", run_bench.slug(dev_name), "sequences" + ("-quick" if a.quick else ""))
    os.makedirs(out, exist_ok=True)
    cache = os.path.join(HERE, "cache", "sequences")
    work = os.path.join(HERE, "cache", "sequences_work")
    os.makedirs(cache, exist_ok=True)
    os.makedirs(work, exist_ok=True)
    deform_cost(a, dev_args, dev_name, out, work, a.deform_frames or ("0:7" if a.quick else "0:23"))
    if a.deform_only:
        return 0
    rows = []
    for scene in scenes:
        gltf = os.path.join(ROOT, "samples", scene, scene + ".gltf")
        for name, args in SETTINGS:
            js = os.path.join(work, "%s_%s.json" % (scene, name))
            cmd = [a.exe, "render", gltf, "--frames", frames, "--width", str(width), "--photons", str(a.photons),
                   "--reference-spp", str(ref_spp), "--reference-cache", cache, "-o",
                   os.path.join(work, "%s_%s_####.exr" % (scene, name)), "--json", js, "-q"] + dev_args + args
            t0 = time.time()
            p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
            took = time.time() - t0
            if p.returncode != 0:
                print("%s %s: failed (exit %d)\n%s" % (scene, name, p.returncode, p.stdout[-2000:]))
                rows.append({"scene": scene, "setting": name, "error": p.stdout.strip().splitlines()[-1:]})
                continue
            j = json.load(open(js))
            s = j["summary"]
            fr = j["frames"]
            filt = sum(f["passes_ms"]["temporal"] + f["passes_ms"]["atrous"] for f in fr) / len(fr)
            row = {"scene": scene, "setting": name, "frames": len(fr), "width": j["width"], "height": j["height"],
                   "psnr_db": s["mean_psnr_db"], "relmse": s["mean_relmse"], "flicker": s["flicker_result"],
                   "flicker_reference": s["flicker_reference"], "flicker_excess": s["flicker_excess"],
                   "ms_per_frame": s["mean_wall_ms"], "filter_ms": filt, "run_s": took,
                   "psnr_per_frame": [f["reference"]["psnr_db"] for f in fr]}
            rows.append(row)
            print("%-32s %-16s %6.2f dB  relMSE %.4f  flicker %.5f (excess %.5f)  %.0f ms/frame, filters %.1f ms" %
                  (scene, name, row["psnr_db"], row["relmse"], row["flicker"], row["flicker_excess"],
                   row["ms_per_frame"], filt))
    # The filters' cost at full HD.
    fexe = a.filters_exe or os.path.join(os.path.dirname(a.exe), "pb_bench_filters")
    timing = []
    p = subprocess.run([fexe] + dev_args + ["--repeat", "5"] + a.filter_sizes.split(), stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, universal_newlines=True)
    for line in p.stdout.splitlines():
        if line.startswith("{"):
            timing.append(json.loads(line))
    print("\n".join(json.dumps(t) for t in timing) or p.stdout)
    result = {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
              "machine": run_bench.machine_info(), "device": dev_name, "frames": frames, "width": width,
              "photons": a.photons, "reference_spp": ref_spp, "rows": rows, "filter_timing": timing,
              "load_1m": os.getloadavg()[0]}
    with open(os.path.join(out, "sequences.json"), "w") as f:
        json.dump(result, f, indent=1)
    with open(os.path.join(out, "sequences.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, ["scene", "setting", "frames", "width", "height", "psnr_db", "relmse", "flicker",
                               "flicker_reference", "flicker_excess", "ms_per_frame", "filter_ms"],
                           extrasaction="ignore")
        w.writeheader()
        for r in rows:
            if "error" not in r:
                w.writerow(r)
    m = result["machine"]
    lines = ["# Sequences: error and flicker against per-frame references", "",
             "Measured %s on %s (%s cores), Vulkan device %s; frames %s at 24 fps, %d px wide, %d photon paths per "
             "frame, references %d spp (the reference renderer, one per pose, cached). Filters: off; temporal (seed "
             "001 24.4.1, alpha = 0.95 w_z w_n); temporal + 4 A-Trous passes (24.4.2). Flicker: mean |I_f - I_{f-1}| "
             "over pixels and RGB (linear), averaged over frame pairs; excess = result's minus the reference's." %
             (result["date"], m.get("cpu", "?"), m.get("cores"), dev_name, frames, width, a.photons, ref_spp), "",
             "| scene | filters | PSNR dB | relMSE | flicker | excess flicker | excess vs off | ms/frame | filters ms |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|"]
    base = {}
    for r in rows:
        if "error" in r:
            lines.append("| %s | %s | failed | | | | | | |" % (r["scene"], r["setting"]))
            continue
        if r["setting"] == "off":
            base[r["scene"]] = r["flicker_excess"]
        ratio = base.get(r["scene"], 0) / r["flicker_excess"] if r["flicker_excess"] > 0 else float("inf")
        lines.append("| %s | %s | %.2f | %.4f | %.5f | %.5f | %s | %.0f | %.1f |" %
                     (r["scene"], r["setting"], r["psnr_db"], r["relmse"], r["flicker"], r["flicker_excess"],
                      "1" if r["setting"] == "off" else ("%.1fx less" % ratio if ratio != float("inf") else
                                                         "below the reference"), r["ms_per_frame"], r["filter_ms"]))
    lines += ["", "Filter cost per frame (pb_bench_filters: synthetic frame with depth and normal edges and a "
              "sub-pixel pan; GPU timestamps of the passes; wall includes the host packing and transfers):", "",
              "| size | temporal ms | 4 A-Trous ms | filters ms | wall ms |", "|---|---:|---:|---:|---:|"]
    for t in timing:
        if "error" in t:
            lines.append("| %dx%d | failed: %s | | | |" % (t["width"], t["height"], t["error"]))
        else:
            lines.append("| %dx%d | %.2f | %.2f | %.2f | %.1f |" % (t["width"], t["height"], t["temporal_ms"],
                                                                    t["atrous_ms"], t["filters_ms"], t["wall_ms"]))
    with open(os.path.join(out, "SEQUENCES.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote %s" % os.path.join(out, "SEQUENCES.md"))
    return 1 if any("error" in r for r in rows) else 0


def deform_cost(a, dev_args, dev_name, out, work, frames):
    """The deformation table (see the module's docstring)."""
    rows = []
    for mode in ("static", "rigid", "skinned"):
        gltf = os.path.join(work, "deform_%s.gltf" % mode)
        subprocess.run([sys.executable, os.path.join(HERE, "deform_scene.py"), gltf, "--mode", mode], check=True,
                       stdout=subprocess.DEVNULL)
        info = json.loads(subprocess.run([a.exe, "info", gltf, "--json", "-"], stdout=subprocess.PIPE,
                                         universal_newlines=True, check=True).stdout)
        js = os.path.join(work, "deform_%s.json" % mode)
        p = subprocess.run([a.exe, "render", gltf, "--frames", frames, "--width", "32", "--photons", "4096",
                            "--no-temporal", "--atrous-iterations", "0", "-o",
                            os.path.join(work, "deform_%s_####.exr" % mode), "--json", js, "-q"] + dev_args,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
        if p.returncode != 0:
            print("deform %s: failed (exit %d)\n%s" % (mode, p.returncode, p.stdout[-2000:]))
            rows.append({"mode": mode, "error": p.stdout.strip().splitlines()[-1:]})
            continue
        fr = json.load(open(js))["frames"][1:]
        mean = lambda key: sum(f["passes_ms"].get(key, 0) for f in fr) / len(fr)
        row = {"mode": mode, "triangles": info["triangles"], "vertices": info["vertices"],
               "posed_per_frame": info["deform"]["posed_per_frame"], "skinned": info["deform"]["skinned_vertices"],
               "morphed": info["deform"]["morphed_vertices"], "frames": len(fr), "pose_ms": mean("pose"),
               "pose_cpu_ms": mean("pose_cpu"),
               "scene_update_ms": mean("scene_update"), "wall_ms": sum(f["wall_ms"] for f in fr) / len(fr)}
        rows.append(row)
        print("deform %-8s %d triangles, %d vertices posed per frame: pose %.2f ms (CPU %.2f ms), GPU scene update "
              "%.2f ms, wall %.1f ms per frame" % (mode, row["triangles"], row["posed_per_frame"], row["pose_ms"],
                                                    row["pose_cpu_ms"], row["scene_update_ms"], row["wall_ms"]))
    result = {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
              "machine": run_bench.machine_info(), "device": dev_name, "frames": frames, "rows": rows,
              "load_1m": os.getloadavg()[0]}
    with open(os.path.join(out, "deform.json"), "w") as f:
        json.dump(result, f, indent=1)
    m = result["machine"]
    lines = ["# Sequences: the cost of skinning and morphing", "",
             "Measured %s on %s (%s cores, load %.1f), Vulkan device %s; frames %s (the first, which uploads the "
             "scene, left out), 32 px, 4096 photon paths, no filters. bench/deform_scene.py: 100,000 triangles; "
             "skinned: four joints (four influences per vertex) and two morph targets (POSITION, NORMAL), all "
             "animated; rigid: its node moves; static: no animation. Pose: pb_scene_set_time on the CPU (one thread), "
             "wall and the thread's CPU time (the cost without the machine's other load); scene update: the GPU BVH "
             "refit (or rebuild) and the vertex upload." %
             (result["date"], m.get("cpu", "?"), m.get("cores"), result["load_1m"], dev_name, frames), "",
             "| mesh | triangles | skinned/morphed vertices posed per frame | pose ms | pose CPU ms | GPU scene update ms "
             "| wall ms/frame |", "|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        if "error" in r:
            lines.append("| %s | failed | | | | | |" % r["mode"])
        else:
            lines.append("| %s | %d | %d | %.2f | %.2f | %.2f | %.1f |" % (
                r["mode"], r["triangles"], r["posed_per_frame"], r["pose_ms"], r["pose_cpu_ms"], r["scene_update_ms"],
                r["wall_ms"]))
    with open(os.path.join(out, "DEFORM.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote %s" % os.path.join(out, "DEFORM.md"))


if __name__ == "__main__":
    sys.exit(main())
