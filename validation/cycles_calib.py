"""Cycles calibration scenes: a Lambertian plane (albedo
0.8, Principled BSDF with Specular 0 and Roughness 1, as the samples' diffuse
materials) seen from 3 m straight above through a narrow camera (0.6 m of the
plane across the image), lit by one light:

  point  100 W point light 1 m above the plane's centre
  spot   100 W spot 1 m above, pointing down, 90 degree cone, blend 0.1
         (the view lies inside the inner cone)
  sun    3 W/m^2 sun at 30 degrees from the plane's normal
  spot_band  100 W spot 1 m above, pointing down, 30 degree cone, blend 0.5:
         the glTF export's inner cone is 7.5, the outer 15 degrees, so the
         view holds the inside, the smooth-step band and the dark outside

Each case is rendered by Cycles with direct light only (max bounces 0, 64
spp, no denoising or clamping) to OUT/CASE.exr and exported with Blender's
glTF exporter (standard lighting units) to OUT/CASE/CASE.gltf, so that
photonbridge renders the very scene Cycles saw.

    blender -b --factory-startup --python-exit-code 1 -P validation/cycles_calib.py -- \
        --out DIR [--width 32] [--samples 64] [--threads N]

validation/cycles_calib_check.py runs it and compares the pictures.
"""
import argparse
import importlib.util
import json
import math
import os
import sys
import time

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

CASES = ("point", "spot", "sun", "spot_band")


def load_module(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def build(S, case, width):
    S.reset_scene(width, width)
    mat = S.diffuse("Plane08", (0.8, 0.8, 0.8))
    me = bpy.data.meshes.new("Plane")
    h = 3.0
    me.from_pydata([(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [], [(0, 1, 2, 3)])
    me.materials.append(mat)
    me.update()
    S.link(bpy.data.objects.new("Plane", me))
    # 3 m above, looking down (+Y up in the image); 0.6 m across at the plane.
    lens = 18.0 / math.tan(math.atan(0.3 / 3.0))
    S.add_camera((0.0, 0.0, 3.0), (0.0, 0.0, 0.0), lens)
    if case == "point":
        S.add_point_light("Point", (0.0, 0.0, 1.0), 100.0)
    elif case == "spot":
        S.add_spot_light("Spot", (0.0, 0.0, 1.0), (0.0, 0.0, 0.0), 100.0, 90.0, 0.1)
    elif case == "spot_band":
        S.add_spot_light("Spot", (0.0, 0.0, 1.0), (0.0, 0.0, 0.0), 100.0, 30.0, 0.5)
    else:
        t = math.radians(30.0)
        S.add_sun("Sun", (math.sin(t), 0.0, -math.cos(t)), 3.0)


def render(RC, path, samples, threads):
    RC.configure(bpy.context.scene, path, samples, threads, 0, 0)  # max bounces 0: direct light only
    t0 = time.time()
    bpy.ops.render.render(write_still=True)
    return time.time() - t0


def main(argv):
    ap = argparse.ArgumentParser(prog="cycles_calib.py")
    ap.add_argument("--out", required=True)
    ap.add_argument("--width", type=int, default=32)
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--threads", type=int, default=0)
    args = ap.parse_args(argv)
    S = load_module("pb_make_samples", os.path.join(ROOT, "exporters", "blender", "make_samples.py"))
    RC = load_module("pb_run_cycles", os.path.join(HERE, "run_cycles.py"))
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    info = {"blender": bpy.app.version_string, "width": args.width, "samples": args.samples, "cases": {}}
    for case in CASES:
        build(S, case, args.width)
        d = os.path.join(out, case)
        os.makedirs(d, exist_ok=True)
        S.gltf_export(os.path.join(d, case + ".gltf"))
        dt = render(RC, os.path.join(out, case + ".exr"), args.samples, args.threads)
        info["cases"][case] = {"render_s": round(dt, 3)}
        print("cycles_calib: %s rendered in %.2f s" % (case, dt))
    with open(os.path.join(out, "cycles.json"), "w") as f:
        json.dump(info, f, indent=1)
    return 0


if __name__ == "__main__":
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    rc = main(argv)
    if rc:
        sys.exit(rc)
