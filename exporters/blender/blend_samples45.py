"""The .blend samples as Blender 4.5 LTS saves them, with what 4.x adds,
and their Cycles 4.5 renders (the references of tests/blender_samples.py
--set 45).

    tools/bpy45/bin/python exporters/blender/blend_samples45.py --out samples/blender45 \\
        [--only NAME] [--samples 1024] [--no-render]            (bpy 4.5 as a module)

Each scene is samples/blender/NAME/NAME.blend (Blender 3.4, made by
blend_samples.py) opened in Blender 4.5, which versions its Principled BSDFs
to v2 (Specular becomes Specular IOR Level, ...), then given what only 4.x
has:

  metal_plastic  the red plastic gets a Principled v2 coat (Coat Weight
                 0.6, roughness 0.08, IOR 1.5), the blue box a sheen (Sheen
                 Weight 0.5, roughness 0.3, pale tint), the copper sphere a
                 warm F82 Specular Tint; the sun's colour is a 5,000 K black
                 body (Light temperature) and the point light carries one
                 stop of its power in Light exposure (60 W x 2^1);
  hdri           the same props on the open floor, the World's HDRI as
                 before, the copper's F82 tint;
  glass_ball     the spot light with Normalize off (its power given per m^2
                 of its radius: 250 W / (pi 0.2^2)) and -0.5 stops of
                 exposure (x 2^0.5 on the power);

and every scene is viewed through AgX (Blender 4.x's default view). Each
NAME gets OUT/NAME/:

  NAME.blend   saved by Blender 4.5, images packed, Cycles with the settings
               of the committed render;
  handoff/     the render engine's writer on that file (NAME.gltf + .bin,
               + sky.hdr): tests/blender_samples.py --set 45 renders it when
               Blender 4.5 is not installed;
  cycles.exr   Cycles 4.5 (CPU), 32-bit float RGB, seed 0, the settings of
               validation/run_cycles.configure;
  cycles.json  samples, size, time and Cycles' own noise (two renders of
               half the samples, seeds 1 and 2), as blend_samples.py."""
import argparse
import importlib.util
import json
import math
import os
import subprocess
import sys
import time

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def load(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


RC = load("pb_run_cycles", os.path.join(ROOT, "validation", "run_cycles.py"))
PT = load("pb_make_principled_tests", os.path.join(HERE, "make_principled_tests.py"))

SRC = os.path.join(ROOT, "samples", "blender")
BOUNCES = 64
SAMPLES = {"glass_ball": 65536}
SCENES = {}


def scene(fn):
    SCENES[fn.__name__] = fn
    return fn


def principled(name):
    return bpy.data.materials[name].node_tree.nodes["Principled BSDF"]


def copper_tint():
    principled("Copper").inputs["Specular Tint"].default_value = (1.0, 0.8, 0.7, 1.0)


@scene
def metal_plastic():
    red = principled("RedPlastic")
    red.inputs["Coat Weight"].default_value = 0.6
    red.inputs["Coat Roughness"].default_value = 0.08
    red.inputs["Coat IOR"].default_value = 1.5
    blue = principled("BluePlastic")
    blue.inputs["Sheen Weight"].default_value = 0.5
    blue.inputs["Sheen Roughness"].default_value = 0.3
    blue.inputs["Sheen Tint"].default_value = (0.9, 0.95, 1.0, 1.0)
    copper_tint()
    key = bpy.data.objects["Key"].data
    key.use_temperature = True
    key.temperature = 5000.0
    fill = bpy.data.objects["Fill"].data
    fill.energy = 60.0
    fill.exposure = 1.0


@scene
def hdri():
    copper_tint()


@scene
def glass_ball():
    spot = bpy.data.objects["Spot"].data
    spot.normalize = False
    spot.energy = 250.0 / (math.pi * spot.shadow_soft_size ** 2) / 2.0 ** -0.5
    spot.exposure = -0.5


def render(sc, out, spp, seed):
    RC.configure(sc, out, spp, 0, seed, BOUNCES)
    bpy.ops.render.render(write_still=True)


def main(argv):
    ap = argparse.ArgumentParser(prog="blend_samples45.py")
    ap.add_argument("--out", required=True)
    ap.add_argument("--only", choices=sorted(SCENES), action="append")
    ap.add_argument("--samples", type=int, default=1024, help="Cycles samples of the committed image")
    ap.add_argument("--no-render", action="store_true", help="the .blend and its hand-off only")
    args = ap.parse_args(argv)
    out = os.path.abspath(args.out)
    for name in SCENES:
        if args.only and name not in args.only:
            continue
        d = os.path.join(out, name)
        os.makedirs(os.path.join(d, "handoff"), exist_ok=True)
        bpy.ops.wm.open_mainfile(filepath=os.path.join(SRC, name, name + ".blend"), load_ui=False)
        SCENES[name]()
        sc = bpy.context.scene
        sc.view_settings.view_transform = 'AgX'
        sc.view_settings.look = 'None'
        spp = SAMPLES.get(name, args.samples)
        RC.configure(sc, "//cycles.exr", spp, 0, 0, BOUNCES)
        blend = os.path.join(d, name + ".blend")
        if bpy.data.images:
            bpy.ops.file.pack_all()
        if os.path.exists(blend):
            os.remove(blend)
        bpy.ops.wm.save_as_mainfile(filepath=blend, compress=True, check_existing=False)
        # The hand-off of the saved file in a Blender 4.5 of its own (this
        # interpreter's bpy through tests/blender/bpy_blender.py, Blender's
        # command line over the module), as F12 writes it.
        gltf = os.path.join(d, "handoff", name + ".gltf")
        cmd = [sys.executable, os.path.join(ROOT, "tests", "blender", "bpy_blender.py"), "-b", blend,
               "--factory-startup", "--python-exit-code", "1", "-P",
               os.path.join(HERE, "export_photonbridge.py"), "--", gltf]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode:
            raise RuntimeError("hand-off of %s failed: %s" % (blend, (p.stdout + p.stderr)[-600:]))
        print("blend_samples45: %s" % [l for l in p.stdout.splitlines() if "export_photonbridge" in l][-1])
        if args.no_render:
            continue
        half = max(1, spp // 2)
        t0 = time.time()
        render(sc, os.path.join(d, "cycles.exr"), 2 * half, 0)
        dt = time.time() - t0
        halves = []
        for seed in (1, 2):
            tmp = os.path.join(d, "half%d.exr" % seed)
            render(sc, tmp, half, seed)
            halves.append(PT.read_exr_rgb(tmp))
            os.remove(tmp)
        (w, h, a), (_, _, b) = halves
        ma = sum(sum(p) for p in a) / (3 * len(a))
        mb = sum(sum(p) for p in b) / (3 * len(b))
        hp = PT.psnr_srgb(a, b)
        info = {"blender": bpy.app.version_string, "samples": 2 * half, "width": w, "height": h, "seed": 0,
                "render_s": round(dt, 2), "threads": sc.render.threads, "device": "CPU",
                "view_transform": sc.view_settings.view_transform,
                "settings": "validation/run_cycles.configure: no denoising, no clamping, adaptive sampling off, "
                            "blur_glossy 0, caustics on, light threshold 0, %d bounces (transparent 64), "
                            "box pixel filter 1 px, no shadow-terminator offsets" % BOUNCES,
                "halves_psnr_db": round(hp, 2), "noise_psnr_db": round(hp + 6.02, 2),
                "halves_mean_diff": round((ma - mb) / max(0.5 * (ma + mb), 1e-12), 5)}
        with open(os.path.join(d, "cycles.json"), "w") as f:
            json.dump(info, f, indent=1, sort_keys=True)
            f.write("\n")
        print("blend_samples45: %s: Cycles %d spp in %.1f s; noise %.2f dB" % (name, 2 * half, dt, hp + 6.02))
    bpy.ops.wm.read_factory_settings(use_empty=True)


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
    # bpy as a module can hang in its own clean-up at interpreter exit
    # (seen after Cycles renders); everything is written by now.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)
