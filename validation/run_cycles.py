"""Render a photonbridge sample with Cycles, headless, from the very Blender
script that builds it (exporters/blender/make_samples.py): Debian's Blender
cannot import glTF, so the scene Cycles sees is the one the glTF was exported
from, not a re-import.

    blender -b --factory-startup --python-exit-code 1 -P validation/run_cycles.py -- \
        --scene cornell_box --out cornell_box_cycles.exr [--width W] [--samples N] \
        [--threads N] [--seed N]

Writes OUT (32-bit float OpenEXR, RGB, scene-linear Rec.709: Blender's view
transform does not touch EXR output) and OUT.json with the render time, the
sample count and the Blender version. Settings chosen for an unbiased
reference: no denoising, no clamping, blur_glossy 0 (no caustic blurring),
reflective and refractive caustics on, light_sampling_threshold 0 (no light
culled), bounces 64 (--bounces; transparent 64), fixed seed. The image size keeps the
scene's aspect (the glTF camera's aspectRatio); --width sets it.
"""
import argparse
import importlib.util
import json
import os
import sys
import time

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def load_samples_module():
    path = os.path.join(ROOT, "exporters", "blender", "make_samples.py")
    spec = importlib.util.spec_from_file_location("pb_make_samples", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def configure(sc, out, samples, threads, seed, bounces):
    """Cycles settings for an unbiased reference (see the module comment),
    32-bit float RGB EXR output to `out`. cycles_calib.py uses them too."""
    r = sc.render
    r.engine = 'CYCLES'
    cy = sc.cycles
    cy.device = 'CPU'
    cy.samples = samples
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.seed = seed
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    cy.light_sampling_threshold = 0.0
    cy.max_bounces = bounces
    cy.diffuse_bounces = bounces
    cy.glossy_bounces = bounces
    cy.transmission_bounces = bounces
    cy.transparent_max_bounces = 64
    if threads:
        r.threads_mode = 'FIXED'
        r.threads = threads
    r.film_transparent = False
    s = r.image_settings
    s.file_format = 'OPEN_EXR'
    s.color_mode = 'RGB'
    s.color_depth = '32'
    s.exr_codec = 'ZIP'
    r.filepath = out
    r.use_file_extension = False


def main(argv):
    ap = argparse.ArgumentParser(prog="run_cycles.py")
    ap.add_argument("--scene", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--width", type=int, default=0, help="image width (height from the aspect)")
    ap.add_argument("--samples", type=int, default=256)
    ap.add_argument("--threads", type=int, default=0, help="0: all cores")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--bounces", type=int, default=64, help="max bounces (0: direct light only)")
    ap.add_argument("--diffuse-bsdf", action="store_true",
                    help="calibration: replace every Principled BSDF whose Specular and Metallic are 0 by a "
                         "Diffuse BSDF of its base colour (Blender 3.4's Principled keeps a grazing GGX layer "
                         "at Specular 0, which glTF's Specular-0 export does not describe)")
    args = ap.parse_args(argv)

    samples = load_samples_module()
    if args.scene not in samples.SCENES:
        print("run_cycles: unknown scene '%s' (have: %s)" % (args.scene, ", ".join(samples.SCENES)),
              file=sys.stderr)
        return 2
    tmpdirs = samples.SCENES[args.scene]() or []
    if args.diffuse_bsdf:
        for mat in bpy.data.materials:
            nt = mat.node_tree
            p = nt.nodes.get("Principled BSDF") if nt else None
            if not p or p.inputs["Specular"].default_value != 0 or p.inputs["Metallic"].default_value != 0 \
                    or p.inputs["Transmission"].default_value != 0 or p.inputs["Base Color"].is_linked:
                continue
            d = nt.nodes.new("ShaderNodeBsdfDiffuse")
            d.inputs["Color"].default_value = p.inputs["Base Color"].default_value
            nt.links.new(d.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    sc = bpy.context.scene
    r = sc.render
    if args.width:
        aspect = r.resolution_y / r.resolution_x
        r.resolution_x = args.width
        r.resolution_y = max(1, round(args.width * aspect))
    r.resolution_percentage = 100
    out = os.path.abspath(args.out)
    configure(sc, out, args.samples, args.threads, args.seed, args.bounces)
    t0 = time.time()
    bpy.ops.render.render(write_still=True)
    dt = time.time() - t0
    for d in tmpdirs:
        for fn in os.listdir(d):
            os.remove(os.path.join(d, fn))
        os.rmdir(d)
    info = {"renderer": "cycles", "blender": bpy.app.version_string, "scene": args.scene,
            "width": r.resolution_x, "height": r.resolution_y, "samples": args.samples,
            "seed": args.seed, "bounces": args.bounces, "diffuse_bsdf": args.diffuse_bsdf,
            "render_s": round(dt, 3)}
    with open(out + ".json", "w") as f:
        json.dump(info, f, indent=1)
    print("run_cycles: %s %dx%d %d spp in %.3f s" % (out, r.resolution_x, r.resolution_y, args.samples, dt))
    return 0


if __name__ == "__main__":
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    rc = main(argv)
    if rc:
        sys.exit(rc)
