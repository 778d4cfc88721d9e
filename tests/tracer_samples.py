#!/usr/bin/env python3
"""`render --tracer images` renders every glTF sample and animated sample
("--tracer images renders every sample and animated sample"), and
the .blend samples as the Blender render engine hands them over
(samples/blender/NAME/handoff/NAME.gltf: soft lights, an HDRI world, glass):
exit 0 under the validation layers (PB_VK_VALIDATION=1 from ctest), the JSON
names the images tracer, photons were stored, and its miss rate (segments no
map confirmed, over all) is reported and below 0.5; the animated samples as
a two-frame sequence, whose maps follow the pose. Prints the miss rate per
sample. Exit 77 without a Vulkan device.
usage: tracer_samples.py PHOTONBRIDGE ROOT OUTDIR"""
import json
import os
import subprocess
import sys

EXE, ROOT, OUT = sys.argv[1:4]
STATIC = ["cornell_box", "cornell_caustics", "ring", "spot_room", "sun_atrium"]
ANIMATED = ["cornell_box_moving_light", "cornell_caustics_moving_sphere", "sun_atrium_flythrough"]
BLEND = ["glass_ball", "hdri", "metal_plastic"]
SMALL = ["--width", "16", "--photons", "4096", "--tracer", "images", "--image-maps", "4",
         "--image-map-resolution", "32", "-q"]
os.makedirs(OUT, exist_ok=True)
if subprocess.run([EXE, "info", "--devices"], capture_output=True).returncode == 12:
    print("tracer_samples: SKIP: no usable Vulkan device")
    sys.exit(77)
failures = []
for name in STATIC + ANIMATED + BLEND:
    scene = os.path.join(ROOT, "samples", name, name + ".gltf")
    if name in BLEND:
        scene = os.path.join(ROOT, "samples", "blender", name, "handoff", name + ".gltf")
    js = os.path.join(OUT, name + ".json")
    if name in ANIMATED:
        cmd = [EXE, "render", scene, "--frames", "0:1", "-o", os.path.join(OUT, name + "_#.exr"), "--json", js]
    else:
        cmd = [EXE, "render", scene, "-o", os.path.join(OUT, name + ".exr"), "--json", js]
    p = subprocess.run(cmd + SMALL, capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        failures.append("%s: exit %d: %s" % (name, p.returncode, p.stderr.strip()[-400:]))
        continue
    j = json.load(open(js))
    phs = [f["photons"] for f in j["frames"]] if name in ANIMATED else [j["photons"]]
    rates = [ph.get("image_miss_rate") for ph in phs]
    ok = all(ph.get("tracer") == "images" and ph["stored"] > 0 for ph in phs) and \
        all(r is not None and 0 <= r < 0.5 for r in rates)
    print("tracer_samples: %-32s %s frame(s), stored %s, miss rate %s%s" % (
        name, len(phs), [ph["stored"] for ph in phs], ["%.3f" % r if r is not None else None for r in rates],
        "" if ok else "  FAIL"))
    if not ok:
        failures.append("%s: tracer %r, stored %r, miss rates %r" % (
            name, [ph.get("tracer") for ph in phs], [ph["stored"] for ph in phs], rates))
for f in failures:
    print("FAIL:", f)
total = len(STATIC + ANIMATED + BLEND)
print("tracer_samples: %d of %d samples rendered with --tracer images" % (total - len(failures), total))
sys.exit(1 if failures else 0)
