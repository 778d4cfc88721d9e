#!/usr/bin/env python3
"""Blender's Principled BSDF against Cycles 3.4: speed and error on the studio
scenes of tests/data/principled (exporters/blender/make_principled_tests.py:
floor, wall, two spheres and a box, all Blender's default Principled BSDF,
one 150 W point light, 128 x 96), with the GGX distribution (Blender's
default) and with Multiscatter GGX, and what the Blender materials cost
against the same scene in glTF's metallic-roughness model.

    python3 bench/principled_studio.py [--exe build/photonbridge] [--out DIR]
                                       [--quick | --smoke] [--device N]
    (make bench-principled)

Scenes:
  studio        Principled, GGX;
  studio_multi  Principled, Multiscatter GGX (its Cycles render is its own);
  studio_gltf   the studio's glTF without the PHOTONBRIDGE_blender extension
                (Blender's exporter's metallic-roughness material: base 0.8,
                metallic 0, roughness 0.5), written into DIR/work: the cost
                baseline, compared with the GGX studio's Cycles render (the
                error of reading a Blender scene as plain glTF).
For each scene it renders, each in its own process timed from spawn to exit
(wall and CPU seconds: start-up, pipeline compilation, scene load and the EXR
included; the GPU's own pass times from --json next to them):
  - photonbridge (GPU) over photon budgets / maps / spp at the default
    --glossy-path-roughness and, for the Blender scenes, at 1 (every glossy
    layer followed by the eye path); the point 262144 x 16 maps x 16 spp,
    progressive, is the render engine's default;
  - the reference path tracer over spp (--max-bounces 64, as Cycles);
and compares every picture with the committed Cycles render (8192 samples,
64 bounces): PSNR and SSIM on the display image, relMSE, and the mean
difference. Then the sweep behind the default --glossy-path-roughness: the
studio at Roughness 0.05 to 0.5, rendered with every glossy layer followed
(1) and with every one shaded from the photon map (0), against the
reference. Writes DIR/results.json and DIR/PRINCIPLED.md (default
bench/results/DEVICE-SLUG/principled, or .../principled-quick); --smoke (one
tiny point per renderer and scene, for tests/principled.cmake) writes only
DIR/results.json."""
import argparse
import json
import os
import re
import resource
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DATA = os.path.join(ROOT, "tests", "data", "principled")
# scene -> (glTF source, Cycles render it is compared with)
SCENES = {"studio": ("studio", "studio"), "studio_multi": ("studio_multi", "studio_multi"),
          "studio_gltf": ("studio", "studio")}

# photons per map, maps, spp, progressive
ENGINE_DEFAULT = (1 << 18, 16, 16, True)
GPU_POINTS = {"full": [(1 << 16, 1, 4, False), (1 << 16, 4, 16, False), ENGINE_DEFAULT, (1 << 18, 16, 64, True)],
              "quick": [(1 << 16, 1, 4, False), ENGINE_DEFAULT],
              "smoke": [(1 << 12, 1, 1, False)]}
REF_SPP = {"full": [64, 256, 1024, 4096], "quick": [64, 256], "smoke": [4]}
# The glossy-path sweep: Roughness of the studio's material, the GPU points
# and the reference's samples per pixel.
SWEEP_ROUGHNESS = {"full": [0.05, 0.1, 0.15, 0.2, 0.3, 0.5], "quick": [0.1, 0.3], "smoke": []}
SWEEP_POINTS = {"full": [(1 << 16, 4, 16, False), ENGINE_DEFAULT], "quick": [ENGINE_DEFAULT], "smoke": []}
REF_SWEEP_SPP = {"full": 4096, "quick": 1024, "smoke": 4}


def children_cpu_s():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(cmd):
    """Runs cmd; its wall seconds and CPU seconds (user + system, all its
    threads: lavapipe's and Embree's work, which a loaded machine does not
    inflate as it does the wall time)."""
    t0, c0 = time.time(), children_cpu_s()
    p = subprocess.run(cmd, capture_output=True, text=True)
    dt, dc = time.time() - t0, children_cpu_s() - c0
    if p.returncode:
        raise RuntimeError("%s exited %d: %s" % (" ".join(cmd), p.returncode, p.stderr.strip()[-400:]))
    return dt, dc


def compare(exe, test, ref, work):
    js = os.path.join(work, "cmp.json")
    run([exe, "compare", test, ref, "--json", js, "-q"])
    with open(js) as f:
        return json.load(f)


def mean_exr(probe, path):
    p = subprocess.run([probe, path], capture_output=True, text=True)
    if p.returncode:
        raise RuntimeError(p.stderr)
    ch = json.loads(p.stdout)["channels"]
    vals = ch["R"] + ch["G"] + ch["B"]
    return sum(vals) / len(vals)


def slug(name):
    s = re.sub(r"[^a-z0-9]+", "-", name.lower()).strip("-")
    return "lavapipe" if s.startswith("llvmpipe") else s  # as bench/run_bench.py


def gltf_without_extension(src, work):
    """The studio's glTF with the PHOTONBRIDGE_blender material extension
    removed (and its .bin beside it), in work/: glTF's own model."""
    with open(src) as f:
        doc = json.load(f)
    for m in doc.get("materials", []):
        m.get("extensions", {}).pop("PHOTONBRIDGE_blender", None)
        if not m.get("extensions"):
            m.pop("extensions", None)
    doc["extensionsUsed"] = [e for e in doc.get("extensionsUsed", []) if e != "PHOTONBRIDGE_blender"]
    out = os.path.join(work, "studio_gltf.gltf")
    for b in doc.get("buffers", []):
        shutil.copy(os.path.join(os.path.dirname(src), b["uri"]), os.path.join(work, b["uri"]))
    with open(out, "w") as f:
        json.dump(doc, f, indent=1)
    return out


def cost_rows(results, scene, base):
    """Wall and GPU time of scene over base at each common setting."""
    idx = {(r["label"], r["spp"], r.get("photons"), r.get("maps")): r for r in results["scenes"][base]["points"]}
    rows = []
    for r in results["scenes"][scene]["points"]:
        b = idx.get((r["label"], r["spp"], r.get("photons"), r.get("maps")))
        if b:
            rows.append((r, b))
    return rows


def write_md(path, results, cyc):
    L = ["# Principled studio against Cycles 3.4 (%s, %s)\n" % (results["device"], results["mode"]),
         "Machine %s, %d CPUs, load %.1f before / %.1f after (1-minute average). 128 x 96 pixels; error "
         "against Cycles' %d-sample render (its own noise %.1f dB GGX, %.1f dB Multiscatter GGX); wall seconds "
         "per render (spawn to exit) and CPU seconds (user + system of all its threads: lavapipe's or Embree's "
         "work; the measure of cost on a loaded machine), GPU ms from the render's own timestamps; photons: "
         "paths per map x maps. GPU: the default --glossy-path-roughness (%s); R 1: every glossy layer "
         "followed by the eye path.\n" % (
             results["machine"], results["cpus"], results["load_before"], results["load_after"],
             cyc["studio"]["samples"], cyc["studio"]["noise_psnr_db"], cyc["studio_multi"]["noise_psnr_db"],
             results.get("glossy_path_roughness_default", "?"))]

    def photons(r):
        if "photons" not in r:
            return "-"
        return "%d x %d%s" % (r["photons"], r["maps"], " prog." if r.get("progressive") else "")

    for scene in SCENES:
        L.append("## %s\n\n| renderer | photons | spp | wall | CPU | GPU ms | PSNR | SSIM | relMSE | mean |\n"
                 "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|" % scene)
        for r in results["scenes"][scene]["points"]:
            L.append("| %s | %s | %d | %.1f s | %.1f s | %s | %.2f dB | %.4f | %.5f | %+.2f %% |" % (
                r["label"], photons(r), r["spp"], r["wall_s"], r["cpu_s"],
                "%.0f" % r["gpu_ms"] if "gpu_ms" in r else "-", r["psnr_db"] or 0, r["ssim"], r["relmse"],
                100 * r["mean_diff"]))
        L.append("")
    L.append("## Cost\n\nCPU seconds of the first scene over the second at the same settings, and GPU ms where "
             "the GPU rendered.\n\n| scenes | renderer | photons | spp | CPU | GPU |\n|---|---|---:|---:|---:|---:|")
    for scene, base in (("studio", "studio_gltf"), ("studio_multi", "studio")):
        for r, b in cost_rows(results, scene, base):
            gpu = "%.2fx" % (r["gpu_ms"] / b["gpu_ms"]) if r.get("gpu_ms") and b.get("gpu_ms") else "-"
            L.append("| %s / %s | %s | %s | %d | %.2fx | %s |" % (scene, base, r["label"], photons(r), r["spp"],
                                                                 r["cpu_s"] / max(b["cpu_s"], 1e-3), gpu))
    L.append("\n## Glossy layers: eye path or photon map\n\nThe studio with every surface at one Roughness, "
             "against the reference path tracer (%d spp, 64 bounces); R 1: every glossy layer followed by the "
             "eye path, R 0: every one shaded where the eye path stops (direct light and the photon map).\n\n"
             "| Roughness | photons | spp | R 1 PSNR | R 0 PSNR | R 1 CPU | R 0 CPU |\n"
             "|---:|---:|---:|---:|---:|---:|---:|" % REF_SWEEP_SPP[results["mode"]])
    sw = results["sweep"]
    for a in sw:
        if a["glossy_path_roughness"] != 1:
            continue
        b = next(x for x in sw if x["glossy_path_roughness"] == 0 and all(
            x[k] == a[k] for k in ("roughness", "photons", "maps", "spp", "progressive")))
        L.append("| %g | %s | %d | %.2f dB | %.2f dB | %.1f s | %.1f s |" % (
            a["roughness"], photons(a), a["spp"], a["psnr_db"] or 0, b["psnr_db"] or 0, a["cpu_s"], b["cpu_s"]))
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")


class Ctx:
    """What every point shares: executables, device option, work folder."""

    def __init__(self, args, work):
        self.exe, self.probe, self.work = args.exe, args.probe, work
        self.dev_opt = ["--device", str(args.device)] if args.device is not None else []
        self.default_r = None  # the render's default --glossy-path-roughness, from its --json


def point(ctx, scene, label, cmd, settings, ref, width, rows):
    """Renders cmd (its own process) and compares it with ref: one row."""
    tag = "_".join(str(v) for v in settings.values())
    exr = os.path.join(ctx.work, "%s_%s_%s.exr" % (scene, slug(label), tag))
    js = exr[:-4] + ".json"
    dt, dc = run(cmd + ["-o", exr, "--width", width, "--json", js, "-q"])
    c = compare(ctx.exe, exr, ref, ctx.work)
    with open(js) as f:
        stats = json.load(f)
    row = dict(settings, label=label, wall_s=round(dt, 2), cpu_s=round(dc, 2), psnr_db=c["psnr_db"],
               ssim=c["ssim"], relmse=c["relmse"],
               mean_diff=round(mean_exr(ctx.probe, exr) / mean_exr(ctx.probe, ref) - 1.0, 5))
    if "glossy_path_roughness" in stats and "--glossy-path-roughness" not in cmd:
        ctx.default_r = stats["glossy_path_roughness"]
    if "passes_ms" in stats:
        row["gpu_ms"] = round(stats["passes_ms"].get("gpu_total", 0.0), 1)
        row["photons_stored"] = stats.get("photons", {}).get("stored")
    rows.append(row)
    print("%-12s %-22s %s: %6.2f dB, mean %+.2f %%, %.1f s wall, %.1f s CPU" % (
        scene, label, tag, row["psnr_db"] or 0, 100 * row["mean_diff"], dt, dc), flush=True)
    return exr


def gpu_cmd(ctx, gltf, photons, maps, spp, prog):
    cmd = [ctx.exe, "render", gltf, "--photons", str(photons), "--iterations", str(maps), "--spp", str(spp)]
    return cmd + ctx.dev_opt + (["--progressive"] if prog else [])


def studio_with_roughness(r, work):
    """The GGX studio with every surface's Roughness r, in work/."""
    src = os.path.join(DATA, "studio", "studio.gltf")
    with open(src) as f:
        doc = json.load(f)
    for m in doc["materials"]:
        m["extensions"]["PHOTONBRIDGE_blender"]["principled"]["roughness"] = r
    out = os.path.join(work, "studio_r%g.gltf" % r)
    for b in doc.get("buffers", []):
        shutil.copy(os.path.join(DATA, "studio", b["uri"]), os.path.join(work, b["uri"]))
    with open(out, "w") as f:
        json.dump(doc, f, indent=1)
    return out


def sweep(ctx, mode, width):
    """Where to shade a glossy layer: followed by the eye path
    (--glossy-path-roughness 1) or where the eye path stops, from direct
    light and the photon map (0), on the studio at each Roughness, against
    the reference path tracer (REF_SWEEP_SPP; no Cycles render of these
    variants: the reference is within 55 dB of Cycles on the studio)."""
    rows = []
    for r in SWEEP_ROUGHNESS[mode]:
        gltf = studio_with_roughness(r, ctx.work)
        name = "studio_r%g" % r
        ref = os.path.join(ctx.work, name + "_ref.exr")
        run([ctx.exe, "reference", gltf, "-o", ref, "--width", width, "--spp", str(REF_SWEEP_SPP[mode]),
             "--max-bounces", "64", "-q"])
        for photons, maps, spp, prog in SWEEP_POINTS[mode]:
            for gr in (1, 0):
                s = {"roughness": r, "glossy_path_roughness": gr, "photons": photons, "maps": maps, "spp": spp,
                     "progressive": prog}
                point(ctx, name, "GPU, R %g" % gr,
                      gpu_cmd(ctx, gltf, photons, maps, spp, prog) + ["--glossy-path-roughness", str(gr)], s, ref,
                      width, rows)
    return rows


def main(argv):
    ap = argparse.ArgumentParser(prog="principled_studio.py")
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "photonbridge"))
    ap.add_argument("--probe", default=os.path.join(ROOT, "build", "tests", "exr_probe"))
    ap.add_argument("--out")
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--quick", action="store_true")
    g.add_argument("--smoke", action="store_true")
    ap.add_argument("--device", type=int)
    args = ap.parse_args(argv)
    mode = "smoke" if args.smoke else "quick" if args.quick else "full"
    p = subprocess.run([args.exe, "info", "--devices"], capture_output=True, text=True)
    if p.returncode:
        print("principled_studio: no Vulkan device: %s" % p.stderr.strip())
        return 77
    m = re.search(r"^\s+%d\*?\s+(.+?)\s{2,}" % (args.device or 0), p.stdout, re.M)
    device = m.group(1).strip() if m else "unknown"
    default_out = os.path.join(HERE, "results", slug(device.split("(")[0]),
                               "principled" if mode == "full" else "principled-" + mode)
    out = args.out or default_out
    work = os.path.join(out, "work")
    os.makedirs(work, exist_ok=True)
    ctx = Ctx(args, work)
    with open(os.path.join(DATA, "cycles.json")) as f:
        cyc = json.load(f)
    results = {"device": device, "mode": mode, "machine": os.uname().nodename, "cpus": os.cpu_count(),
               "load_before": os.getloadavg()[0], "scenes": {}}
    for scene, (src, cycles_name) in SCENES.items():
        gltf = os.path.join(DATA, src, src + ".gltf")
        if scene == "studio_gltf":
            gltf = gltf_without_extension(gltf, work)
        ref = os.path.join(DATA, cycles_name, "cycles.exr")
        w = str(cyc[cycles_name]["width"])
        rows = []
        blender = scene != "studio_gltf"
        for photons, maps, spp, prog in GPU_POINTS[mode]:
            s = {"photons": photons, "maps": maps, "spp": spp, "progressive": prog}
            base = gpu_cmd(ctx, gltf, photons, maps, spp, prog)
            point(ctx, scene, "GPU", base, s, ref, w, rows)
            if blender:  # every glossy layer followed by the eye path instead
                point(ctx, scene, "GPU, R 1", base + ["--glossy-path-roughness", "1"], s, ref, w, rows)
        for spp in REF_SPP[mode]:
            point(ctx, scene, "reference", [args.exe, "reference", gltf, "--spp", str(spp), "--max-bounces", "64"],
                  {"spp": spp}, ref, w, rows)
        results["scenes"][scene] = {"cycles": cyc[cycles_name], "points": rows}
    results["sweep"] = sweep(ctx, mode, str(cyc["studio"]["width"]))
    results["glossy_path_roughness_default"] = ctx.default_r
    results["load_after"] = os.getloadavg()[0]
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)
        f.write("\n")
    if mode != "smoke":
        write_md(os.path.join(out, "PRINCIPLED.md"), results, cyc)
    n = sum(len(v["points"]) for v in results["scenes"].values()) + len(results["sweep"])
    print("principled_studio: %d points, wrote %s" % (n, out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
