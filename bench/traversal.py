#!/usr/bin/env python3
"""Per pass, the two ways the GPU pipeline finds surfaces, in one run: ray
queries (VK_KHR_ray_query on the scene's acceleration structures) against
the shaders' own BVH, the same scene, settings and seed, on one device.

    bench/traversal.py [--exe build/photonbridge] [--icd tools/mesa25/lvp_icd.x86_64.json]
                       [--scenes cornell_box,spot_room,sun_atrium] [--width 128] [--reps 2]
                       [--out bench/results/traversal-DATE]

The device: --icd names a Vulkan driver manifest (default tools/mesa25's
lavapipe, Mesa 25: the CPU device with ray queries); --icd '' keeps the
environment's (an NVIDIA GPU). Each scene is rendered once with each
traversal to warm the shader cache, then --reps pairs interleaved (ray
queries, BVH, ray queries, ...); each figure is the median of its reps.
Times are the passes' GPU timestamps (--json passes_ms). Writes OUT.md and
OUT.json with the machine, the device and its driver, scene, resolution,
samples, photons emitted and stored.
"""
import argparse, datetime, json, os, platform, statistics, subprocess, sys

ap = argparse.ArgumentParser()
ap.add_argument("--exe", default="build/photonbridge")
ap.add_argument("--icd", default="tools/mesa25/lvp_icd.x86_64.json")
ap.add_argument("--scenes", default="cornell_box,spot_room,sun_atrium")
ap.add_argument("--width", type=int, default=128)
ap.add_argument("--spp", type=int, default=4)
ap.add_argument("--iterations", type=int, default=2)
ap.add_argument("--reps", type=int, default=2)
ap.add_argument("--out", default=None)
a = ap.parse_args()
day = datetime.date.today().isoformat()
out = a.out or f"bench/results/traversal-{day}"
env = dict(os.environ)
if a.icd:
    if not os.path.isfile(a.icd):
        sys.exit(f"traversal: {a.icd} is missing (scripts/install-deps.sh unpacks Mesa 25 into tools/mesa25)")
    env["VK_ICD_FILENAMES"] = os.path.abspath(a.icd)
PASSES = ["gbuffer", "direct", "photon_trace", "lbvh_build", "gather", "gpu_total"]


def devices():
    p = subprocess.run([a.exe, "info", "--devices", "--json", "-"], capture_output=True, text=True, env=env)
    return json.loads(p.stdout)["devices"] if p.returncode == 0 else []


def render(scene, traversal, tag):
    js = f"/tmp/pb_traversal_{os.getpid()}_{tag}.json"
    args = [a.exe, "render", f"samples/{scene}/{scene}.gltf", "-o", f"/tmp/pb_traversal_{os.getpid()}.exr", "-q",
            "--json", js, "--width", str(a.width), "--spp", str(a.spp), "--iterations", str(a.iterations),
            "--seed", "1", "--traversal", traversal]
    p = subprocess.run(args, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        sys.exit(f"traversal: {' '.join(args)}: exit {p.returncode}: {p.stderr.strip()}")
    with open(js) as f:
        j = json.load(f)
    os.unlink(js)
    return j


rows = []
for scene in a.scenes.split(","):
    for t in ("ray-query", "bvh"):  # warm-up: the shader cache
        render(scene, t, "warm")
    runs = {"ray-query": [], "bvh": []}
    for _ in range(a.reps):
        for t in ("ray-query", "bvh"):
            runs[t].append(render(scene, t, t))
    row = {"scene": scene, "width": runs["bvh"][0]["width"], "height": runs["bvh"][0]["height"],
           "spp": runs["bvh"][0]["spp"], "photons_emitted": runs["bvh"][0]["photons"]["emitted"],
           "photons_stored": {t: runs[t][0]["photons"]["stored"] for t in runs}, "ms": {}}
    for t in runs:
        row["ms"][t] = {p: statistics.median(r["passes_ms"].get(p, 0.0) for r in runs[t]) for p in PASSES}
        row["ms"][t]["wall"] = statistics.median(r["wall_ms"] for r in runs[t])
    rows.append(row)
    print(f"{scene}: " + ", ".join(f"{p} {row['ms']['ray-query'][p]:.0f} vs {row['ms']['bvh'][p]:.0f} ms"
                                   for p in PASSES + ["wall"]), flush=True)

dev = [d for d in devices() if d.get("default")] or devices()
meta = {"date": day, "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
        "cpu": next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?"),
        "device": dev[0]["name"] if dev else "?", "driver": dev[0].get("driver_info", "?") if dev else "?",
        "reps": a.reps, "iterations": a.iterations}
with open(out + ".json", "w") as f:
    json.dump({"meta": meta, "rows": rows}, f, indent=1)
with open(out + ".md", "w") as f:
    f.write(f"# Ray queries against the GLSL BVH, per pass ({day})\n\n")
    f.write(f"Machine: {meta['cpu']}, {os.cpu_count()} cores. Device: {meta['device']}, {meta['driver']}. "
            f"`bench/traversal.py`: warm shader cache, {a.reps} interleaved pairs, medians; GPU timestamps "
            f"(ms). Ratio: BVH / ray queries (above 1: ray queries faster).\n\n")
    for r in rows:
        st = r["photons_stored"]
        f.write(f"## {r['scene']}: {r['width']}x{r['height']}, {r['spp']} spp, {a.iterations} maps, "
                f"{r['photons_emitted']:,} photons emitted, {st['ray-query']:,} stored with ray queries, "
                f"{st['bvh']:,} with the BVH\n\n")
        f.write("| pass | ray queries ms | BVH ms | ratio |\n|---|---:|---:|---:|\n")
        for p in PASSES + ["wall"]:
            q, b = r["ms"]["ray-query"][p], r["ms"]["bvh"][p]
            f.write(f"| {p} | {q:.1f} | {b:.1f} | {b / q if q > 0 else float('nan'):.2f}x |\n")
        f.write("\n")
print(f"wrote {out}.md and {out}.json")
