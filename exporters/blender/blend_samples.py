"""The .blend samples: scenes an artist opens in Blender, with
Principled materials and Blender's own lights, and their Cycles 3.4 renders
(the references of tests/blender_samples.py and of `photonbridge validate
FILE.blend`).

    blender -b --factory-startup --python-exit-code 1 \\
        -P exporters/blender/blend_samples.py -- --out samples/blender \\
        [--only NAME] [--samples 2048] [--no-render]

Scenes (96 x 72 pixels, metres, Blender Z up):

  metal_plastic  a studio cove (Blender's default Principled: Base 0.8,
                 Specular 0.5, Roughness 0.5), a copper sphere (Metallic 1,
                 Roughness 0.3), a red glossy plastic sphere (Roughness 0.2)
                 and a blue plastic box (Roughness 0.45, Multiscatter GGX),
                 lit by a soft sun (2.5 W/m^2, angle 8 degrees) and a
                 soft point light (radius 0.25 m, 120 W, warm);
  hdri           the props on an open floor lit by the World alone: an
                 Environment Texture (sky.hdr, 128 x 64 Radiance RGBE made
                 here: a sky gradient, a dark ground, a 3 x 3-texel sun) with
                 a Mapping rotation of 70 degrees about Z, Strength 0.8,
                 seen by the camera as the background;
  glass_ball     a clear Principled glass ball (Transmission 1, Roughness 0,
                 IOR 1.45) on a floor, under a soft spot light (radius
                 0.2 m, 50 degrees, blend 0.2, 250 W): its caustic on the
                 floor; a dim world (0.05) fills the shadows.

For each NAME the script writes OUT/NAME/:

  NAME.blend     the scene, images packed, render engine Cycles with the
                 settings of the committed render (below), so that F12 in
                 Blender gives that picture and the photonbridge engine
                 renders the same file;
  sky.hdr        (hdri) the environment map, also packed in the .blend;
  handoff/       the photonbridge render engine's hand-off of the .blend
                 (exporters/blender/export_photonbridge.py, the F12 writer):
                 NAME.gltf + .bin (+ sky.hdr); tests/blender_samples.py
                 renders it when Blender is not installed;
  cycles.exr     Cycles 3.4 (CPU), 32-bit float RGB, seed 0, the settings of
                 validation/run_cycles.configure (no denoising, no
                 clamping, adaptive sampling off, blur_glossy 0, caustics
                 on, 64 bounces, box pixel filter of width 1);
  cycles.json    samples, size, time, and Cycles' own noise: two more
                 renders of half the samples (seeds 1 and 2), their PSNR on
                 the display image and mean difference, and the committed
                 render's noise PSNR that follows (halves + 6.02 dB).

Same seeds, same pictures. Run Blender without pyenv on PATH.
"""
import argparse
import importlib.util
import json
import math
import os
import subprocess
import sys
import time

import bpy
from mathutils import Vector

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

try:  # Debian's numpy dropped numpy.bool, which Blender 3.4's glTF exporter uses
    import numpy
    if not hasattr(numpy, "bool"):
        numpy.bool = bool
except ImportError:
    pass


def load(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


S = load("pb_make_samples", os.path.join(HERE, "make_samples.py"))
RC = load("pb_run_cycles", os.path.join(ROOT, "validation", "run_cycles.py"))
L = load("pb_light_scenes", os.path.join(HERE, "light_scenes.py"))
PT = load("pb_make_principled_tests", os.path.join(HERE, "make_principled_tests.py"))

W, H = 96, 72
BOUNCES = 64
# Cycles samples where a scene needs more than --samples: the caustic is
# reached only by paths that hit the spot's sphere through the glass.
SAMPLES = {"glass_ball": 8192}
SCENES = {}


def scene(fn):
    SCENES[fn.__name__] = fn
    return fn


def principled(name, base, roughness=0.5, metallic=0.0, specular=0.5, transmission=0.0, ior=1.45,
               distribution='GGX'):
    """A Principled BSDF with Blender's defaults but for what is given."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    p = mat.node_tree.nodes["Principled BSDF"]
    p.distribution = distribution
    p.inputs["Base Color"].default_value = (*base, 1.0)
    p.inputs["Roughness"].default_value = roughness
    p.inputs["Metallic"].default_value = metallic
    p.inputs["Specular"].default_value = specular
    p.inputs["Transmission"].default_value = transmission
    p.inputs["IOR"].default_value = ior
    mat.diffuse_color = (*base, 1.0)
    return mat


def world(color, strength):
    w = bpy.data.worlds.new("World")
    bpy.context.scene.world = w
    w.use_nodes = True
    bg = w.node_tree.nodes["Background"]
    bg.inputs[0].default_value = (*color, 1.0)
    bg.inputs[1].default_value = strength
    return w


def props():
    """A copper sphere, a red plastic sphere and a blue plastic box."""
    copper = principled("Copper", (0.95, 0.64, 0.54), roughness=0.3, metallic=1.0)
    red = principled("RedPlastic", (0.7, 0.08, 0.06), roughness=0.2)
    blue = principled("BluePlastic", (0.1, 0.25, 0.6), roughness=0.45, distribution='MULTI_GGX')
    b = S.MeshBuilder()
    S.uv_sphere(b, (-0.7, 0.2, 0.4), 0.4, 48, 24)
    S.mesh_object("CopperSphere", b, [copper])
    b = S.MeshBuilder()
    S.uv_sphere(b, (0.15, -0.45, 0.25), 0.25, 48, 24)
    S.mesh_object("PlasticSphere", b, [red])
    b = S.MeshBuilder()
    S.box(b, (0.75, 0.3, 0.3), (0.6, 0.6, 0.6), rot_z_deg=25.0, skip=('-z',))
    S.mesh_object("PlasticBox", b, [blue])


def cove(mat):
    """A floor that curves up into a back wall (radius 0.8 m)."""
    b = S.MeshBuilder()
    r, y0, n = 0.8, 1.2, 12
    b.quad((-4, -3, 0), (4, -3, 0), (4, y0, 0), (-4, y0, 0), (0, 0, 1))
    for i in range(n):
        a0, a1 = math.pi / 2 * i / n, math.pi / 2 * (i + 1) / n
        p = [(y0 + r * math.sin(a), r * (1 - math.cos(a))) for a in (a0, a1)]
        nrm = (0.0, -math.sin(0.5 * (a0 + a1)), math.cos(0.5 * (a0 + a1)))
        b.face([(-4, p[0][0], p[0][1]), (4, p[0][0], p[0][1]), (4, p[1][0], p[1][1]), (-4, p[1][0], p[1][1])],
               normal=nrm, smooth=True, group="cove")
    b.quad((-4, y0 + r, r), (4, y0 + r, r), (4, y0 + r, 4), (-4, y0 + r, 4), (0, -1, 0))
    S.mesh_object("Cove", b, [mat])


@scene
def metal_plastic(outdir):
    S.reset_scene(W, H)
    cove(principled("Default", (0.8, 0.8, 0.8)))
    props()
    S.add_camera((0.4, -4.2, 1.8), (0.0, 0.4, 0.45), 40.0)
    world((0.0, 0.0, 0.0), 0.0)
    # The key: a soft sun from the area light's old place (its irradiance
    # there, 80 W / (pi 10.7 m^2) = 2.4 W/m^2, so the exposure stays), 8
    # degrees wide (its penumbra about 0.14 rad x the occluder's height).
    o = L.light("Key", 'SUN', (-1.8, -1.6, 2.4), 2.5, target=(0.0, 0.3, 0.4))
    o.data.angle = math.radians(8.0)
    o = L.light("Fill", 'POINT', (1.8, -1.2, 1.6), 120.0, color=(1.0, 0.85, 0.7))
    o.data.shadow_soft_size = 0.25


@scene
def hdri(outdir):
    S.reset_scene(W, H)
    b = S.MeshBuilder()
    b.quad((-8, -8, 0), (8, -8, 0), (8, 8, 0), (-8, 8, 0), (0, 0, 1))
    S.mesh_object("Floor", b, [principled("Floor", (0.6, 0.6, 0.6), roughness=0.6)])
    props()
    S.add_camera((0.4, -4.2, 1.5), (0.0, 0.4, 0.6), 40.0)
    w = world((0.0, 0.0, 0.0), 0.8)
    path = os.path.join(outdir, "sky.hdr")
    L.write_hdr(path, 128, 64, L.sky)
    nt = w.node_tree
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = bpy.data.images.load(path)
    env.image.name = "sky"  # the writer names the map's file after the image
    env.interpolation = 'Linear'
    tc = nt.nodes.new("ShaderNodeTexCoord")
    mp = nt.nodes.new("ShaderNodeMapping")
    mp.vector_type = 'POINT'
    mp.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(70.0))
    nt.links.new(tc.outputs["Generated"], mp.inputs["Vector"])
    nt.links.new(mp.outputs[0], env.inputs["Vector"])
    nt.links.new(env.outputs["Color"], nt.nodes["Background"].inputs["Color"])


@scene
def glass_ball(outdir):
    S.reset_scene(W, H)
    b = S.MeshBuilder()
    b.quad((-4, -4, 0), (4, -4, 0), (4, 4, 0), (-4, 4, 0), (0, 0, 1))
    S.mesh_object("Floor", b, [principled("Floor", (0.8, 0.8, 0.8))])
    glass = principled("Glass", (1.0, 1.0, 1.0), roughness=0.0, transmission=1.0, ior=1.45)
    b = S.MeshBuilder()
    S.uv_sphere(b, (0.0, 0.0, 0.45), 0.45, 64, 32)
    S.mesh_object("GlassBall", b, [glass])
    S.add_camera((0.0, -3.6, 2.2), (0.0, 0.3, 0.3), 40.0)
    world((1.0, 1.0, 1.0), 0.05)
    o = L.light("Spot", 'SPOT', (-0.6, -0.5, 2.6), 250.0, target=(0.15, 0.15, 0.0))
    o.data.shadow_soft_size = 0.2
    o.data.spot_size = math.radians(50.0)
    o.data.spot_blend = 0.2


def cycles_settings(sc, spp, seed, out):
    RC.configure(sc, out, spp, 0, seed, BOUNCES)


def render(sc, out, spp, seed):
    cycles_settings(sc, spp, seed, out)
    bpy.ops.render.render(write_still=True)


def handoff(blend, outdir):
    """The render engine's writer on the saved .blend, in a Blender of its
    own (what F12 and `photonbridge validate FILE.blend` hand over)."""
    hdir = os.path.join(outdir, "handoff")
    os.makedirs(hdir, exist_ok=True)
    gltf = os.path.join(hdir, os.path.splitext(os.path.basename(blend))[0] + ".gltf")
    cmd = [bpy.app.binary_path, "-b", blend, "--factory-startup", "--python-exit-code", "1", "-P",
           os.path.join(HERE, "export_photonbridge.py"), "--", gltf]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode:
        raise RuntimeError("hand-off of %s failed: %s" % (blend, (p.stdout + p.stderr)[-600:]))
    print("blend_samples: %s" % [l for l in p.stdout.splitlines() if "export_photonbridge" in l][-1])


def main(argv):
    ap = argparse.ArgumentParser(prog="blend_samples.py")
    ap.add_argument("--out", required=True)
    ap.add_argument("--only", choices=sorted(SCENES), action="append")
    ap.add_argument("--samples", type=int, default=2048, help="Cycles samples of the committed image")
    ap.add_argument("--no-render", action="store_true", help="the .blend and its hand-off only")
    args = ap.parse_args(argv)
    out = os.path.abspath(args.out)
    for name in SCENES:
        if args.only and name not in args.only:
            continue
        d = os.path.join(out, name)
        os.makedirs(d, exist_ok=True)
        SCENES[name](d)
        sc = bpy.context.scene
        cycles_settings(sc, SAMPLES.get(name, args.samples), 0, "//cycles.exr")
        blend = os.path.join(d, name + ".blend")
        if bpy.data.images:
            bpy.ops.file.pack_all()
        if os.path.exists(blend):  # no NAME.blend1 backup beside it
            os.remove(blend)
        bpy.ops.wm.save_as_mainfile(filepath=blend, compress=True, check_existing=False)
        print("blend_samples: %s written" % blend)
        handoff(blend, d)
        if args.no_render:
            continue
        half = max(1, SAMPLES.get(name, args.samples) // 2)
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
                "settings": "validation/run_cycles.configure: no denoising, no clamping, adaptive sampling off, "
                            "blur_glossy 0, caustics on, light threshold 0, %d bounces (transparent 64), "
                            "box pixel filter 1 px, no shadow-terminator offsets" % BOUNCES,
                "halves_psnr_db": round(hp, 2), "noise_psnr_db": round(hp + 6.02, 2),
                "halves_mean_diff": round((ma - mb) / max(0.5 * (ma + mb), 1e-12), 5)}
        with open(os.path.join(d, "cycles.json"), "w") as f:
            json.dump(info, f, indent=1, sort_keys=True)
            f.write("\n")
        print("blend_samples: %s: Cycles %d spp in %.1f s; noise %.2f dB, halves' means %.5f / %.5f" % (
            name, 2 * half, dt, hp + 6.02, ma, mb))
    bpy.ops.wm.read_factory_settings(use_empty=True)


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
