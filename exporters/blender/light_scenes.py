"""Small Blender scenes, one per kind of light (and the world), exported as
glTF with the PHOTONBRIDGE_blender extension added from Blender's own values,
and rendered by Cycles: the committed references of tests/lights_cycles.py.

    blender -b --factory-startup --python-exit-code 1 \\
        -P exporters/blender/light_scenes.py -- --out tests/data/lights \\
        [--only NAME] [--samples 2048] [--width 48] [--no-render]
    ... -- --bench --out bench/scenes/lights [--samples 4096]   (bench/run_lights.py's scenes)

Each scene NAME goes to OUT/NAME/: NAME.gltf + NAME.bin (Blender's glTF
exporter, "Standard" lighting units), its environment map when it has one,
cycles.exr (32-bit float RGB) and cycles.json (samples, seeds, Blender's
version, render time, and the render's own noise: two renders with seeds 1
and 2, the committed one is seed 1, Var = E[(A - B)^2] / 2 per pixel; the
benchmark's scenes keep the second as cycles_seed2.exr).

The add-on's writer is not part of this script: the extension is written
here by a small helper, from the same Blender data the writer would read
(light type, colour, power or strength, radius, spot size and blend, angle,
shape, size, spread; the World's Background colour and strength, an
Environment Texture's image, the Mapping node's rotation and the texture's
strength), in the contract's units (exporters/blender/PHOTONBRIDGE_blender.md).
Area lights have no glTF form, so the helper adds their nodes; every light's
node gets the transform Blender's own conversion gives (Z up to Y up: the
rotation q_C of -90 degrees about X, times the object's, so that the node's
-Z is the light's), which the KHR light on the node shares.

Materials of the one-light scenes are Principled BSDFs of Specular 0 and
Roughness 1 in the file (a diffuse glTF material) and Diffuse BSDFs of the
same colour in the Cycles render (Blender 3.4's Principled BSDF at Specular
0 is not Lambertian: shared/BLENDER.md), so that the comparison is one of
lights. The benchmark's two scenes carry Principled materials as artists
leave them (Blender's defaults, a glossy plastic, a rough metal), written
with the PHOTONBRIDGE_blender material extension
(make_principled_tests.material_extension) and rendered as they are by
Cycles.
"""
import argparse
import importlib.util
import json
import math
import os
import struct
import sys
import time

import bpy
from mathutils import Euler, Quaternion, Vector

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def load_module(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


S = load_module("pb_make_samples", os.path.join(HERE, "make_samples.py"))
RC = load_module("pb_run_cycles", os.path.join(ROOT, "validation", "run_cycles.py"))

SCENES = {}        # tests/data/lights: one light each, 48 px
BENCH_SCENES = {}  # bench/scenes/lights: the benchmark's two scenes (bench/run_lights.py)


def scene(fn):
    SCENES[fn.__name__] = fn
    return fn


def bench_scene(fn):
    BENCH_SCENES[fn.__name__] = fn
    return fn


# ---- building ---------------------------------------------------------------

def stage(width):
    """A 4 x 4 m floor (albedo 0.8), a 0.5 m box (albedo 0.6, reddish) and
    a camera 45 degrees above, looking at the box."""
    S.reset_scene(width, width)
    floor = S.diffuse("Floor", (0.8, 0.8, 0.8))
    box = S.diffuse("Box", (0.6, 0.35, 0.3))
    b = S.MeshBuilder()
    h = 2.0
    b.quad((-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0), (0, 0, 1), mat=0)
    S.mesh_object("Floor", b, [floor])
    b = S.MeshBuilder()
    S.box(b, (0.3, -0.2, 0.25), (0.5, 0.5, 0.5), rot_z_deg=20.0, skip=('-z',))
    S.mesh_object("Box", b, [box])
    S.add_camera((0.0, -3.0, 3.0), (0.0, 0.0, 0.2), 35.0)
    w = bpy.data.worlds.new("World")
    bpy.context.scene.world = w
    w.use_nodes = True
    w.node_tree.nodes["Background"].inputs[0].default_value = (0, 0, 0, 1)


def light(name, kind, location, watts, target=(0.0, 0.0, 0.0), color=(1, 1, 1)):
    lamp = bpy.data.lights.new(name, kind)
    lamp.energy = watts
    lamp.color = color
    lamp.use_nodes = False
    obj = S.link(bpy.data.objects.new(name, lamp))
    obj.location = location
    S.look_at(obj, target)
    return obj


@scene
def area_square(width):
    stage(width)
    o = light("Area", 'AREA', (-0.5, -0.6, 2.0), 250.0)
    o.data.shape = 'SQUARE'
    o.data.size = 1.0


@scene
def area_rectangle_spread(width):
    stage(width)
    o = light("Area", 'AREA', (0.4, -0.8, 1.8), 400.0, target=(0.0, 0.3, 0.0))
    o.data.shape = 'RECTANGLE'
    o.data.size, o.data.size_y = 1.4, 0.5
    o.data.spread = math.radians(70.0)


@scene
def area_ellipse(width):
    stage(width)
    o = light("Area", 'AREA', (-0.6, 0.2, 1.6), 300.0, target=(0.3, 0.0, 0.0), color=(1.0, 0.85, 0.7))
    o.data.shape = 'ELLIPSE'
    o.data.size, o.data.size_y = 1.2, 0.6


@scene
def point_soft(width):
    stage(width)
    o = light("Point", 'POINT', (-0.6, -0.4, 1.4), 300.0, color=(1.0, 0.8, 0.6))
    o.data.shadow_soft_size = 0.25


@scene
def spot_soft(width):
    stage(width)
    o = light("Spot", 'SPOT', (-0.8, -1.0, 2.2), 800.0, target=(0.2, 0.0, 0.0))
    o.data.shadow_soft_size = 0.1
    o.data.spot_size = math.radians(60.0)
    o.data.spot_blend = 0.3


@scene
def sun_soft(width):
    stage(width)
    o = light("Sun", 'SUN', (0.0, 0.0, 5.0), 3.0)
    o.data.angle = math.radians(8.0)
    o.rotation_mode = 'QUATERNION'
    o.rotation_quaternion = Vector((0.5, 0.3, -1.0)).to_track_quat('-Z', 'Y')


@scene
def world_color(width):
    stage(width)
    bg = bpy.context.scene.world.node_tree.nodes["Background"]
    bg.inputs[0].default_value = (0.4, 0.5, 0.7, 1.0)
    bg.inputs[1].default_value = 1.5


def write_hdr(path, w, h, rgb_at):
    """Flat (uncompressed) Radiance RGBE, rows from the top: our decoder and
    Blender's read it the same way (mantissa + 1/2, Radiance's convention)."""
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
        for j in range(h):
            row = bytearray()
            for i in range(w):
                c = rgb_at(i, j)
                m = max(c)
                if m < 1e-32:
                    row += bytes(4)
                    continue
                e = math.frexp(m)[1]
                s = math.ldexp(1.0, -e) * 256.0
                row += bytes((min(255, int(c[0] * s)), min(255, int(c[1] * s)), min(255, int(c[2] * s)), e + 128))
            f.write(row)


def sky(i, j, w=128, h=64):
    """A sky: blue above, brighter at the horizon, a dark ground, and a sun
    of 3 x 3 texels 35 degrees up."""
    v = (j + 0.5) / h            # 0 at the zenith
    elev = (0.5 - v) * math.pi
    if elev < 0:
        return (0.15, 0.12, 0.1)
    c = (0.25 + 0.5 * (1 - math.sin(elev)), 0.35 + 0.45 * (1 - math.sin(elev)), 0.6 + 0.2 * (1 - math.sin(elev)))
    si, sj = int(0.3 * w), int((0.5 - math.radians(35.0) / math.pi) * h)
    if abs(i - si) <= 1 and abs(j - sj) <= 1:
        return (400.0, 380.0, 330.0)
    return c


@scene
def world_hdri(width, outdir=None):
    stage(width)
    path = os.path.join(outdir, "sky.hdr")
    write_hdr(path, 128, 64, sky)
    nt = bpy.context.scene.world.node_tree
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = bpy.data.images.load(path)
    env.interpolation = 'Linear'
    tc = nt.nodes.new("ShaderNodeTexCoord")
    mp = nt.nodes.new("ShaderNodeMapping")
    mp.vector_type = 'POINT'
    mp.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(70.0))
    nt.links.new(tc.outputs["Generated"], mp.inputs["Vector"])
    nt.links.new(mp.outputs[0], env.inputs["Vector"])
    nt.links.new(env.outputs["Color"], nt.nodes["Background"].inputs["Color"])
    nt.nodes["Background"].inputs[1].default_value = 0.8


def principled(name, base, roughness=0.5, metallic=0.0):
    """Blender's default Principled BSDF (Specular 0.5, GGX) but for these."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    p = mat.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (*base, 1.0)
    p.inputs["Roughness"].default_value = roughness
    p.inputs["Metallic"].default_value = metallic
    mat.diffuse_color = (*base, 1.0)
    return mat


def objects():
    """The benchmark scenes' props on the floor, Principled: a rough
    metal sphere (Metallic 1, Roughness 0.4), a red glossy plastic box
    (Roughness 0.3) and a blue cylinder-like prism (Blender's defaults but
    the colour)."""
    m = [principled("Sphere", (0.7, 0.7, 0.7), roughness=0.4, metallic=1.0),
         principled("Box", (0.75, 0.3, 0.2), roughness=0.3), principled("Prism", (0.2, 0.45, 0.7))]
    b = S.MeshBuilder()
    S.uv_sphere(b, (-0.6, 0.1, 0.4), 0.4, 32, 16, mat=0)
    S.mesh_object("Sphere", b, [m[0]])
    b = S.MeshBuilder()
    S.box(b, (0.55, -0.1, 0.3), (0.6, 0.6, 0.6), rot_z_deg=25.0, skip=('-z',))
    S.mesh_object("Box", b, [m[1]])
    b = S.MeshBuilder()
    S.box(b, (0.05, 0.8, 0.6), (0.35, 0.35, 1.2), rot_z_deg=-10.0, skip=('-z',))
    S.mesh_object("Prism", b, [m[2]])


def studio_stage(width):
    """A studio: a floor that curves up into a back wall (a cove of radius
    0.8 m), Blender's default Principled (Base 0.8, Specular 0.5, Roughness
    0.5), the props, a camera 128 x 96."""
    S.reset_scene(width, width * 3 // 4)
    wall = principled("Cove", (0.8, 0.8, 0.8))
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
    S.mesh_object("Cove", b, [wall])
    objects()
    S.add_camera((0.4, -4.2, 1.8), (0.0, 0.4, 0.45), 40.0)
    w = bpy.data.worlds.new("World")
    bpy.context.scene.world = w
    w.use_nodes = True
    w.node_tree.nodes["Background"].inputs[0].default_value = (0, 0, 0, 1)


@bench_scene
def studio_area(width):
    """A key softbox (1.2 x 0.8 m, 60 W) and a fill (a 1.5 m disc, 15 W,
    spread 100 degrees), no world."""
    studio_stage(width)
    o = light("Key", 'AREA', (-1.8, -1.6, 2.4), 60.0, target=(0.0, 0.3, 0.4))
    o.data.shape = 'RECTANGLE'
    o.data.size, o.data.size_y = 1.2, 0.8
    o = light("Fill", 'AREA', (2.4, -2.0, 1.2), 15.0, target=(0.0, 0.3, 0.4), color=(0.85, 0.9, 1.0))
    o.data.shape = 'DISK'
    o.data.size = 1.5
    o.data.spread = math.radians(100.0)


@bench_scene
def world_only(width):
    """The props on an open floor, lit by a uniform world (0.8, 0.9, 1.0) alone."""
    S.reset_scene(width, width * 3 // 4)
    b = S.MeshBuilder()
    b.quad((-6, -6, 0), (6, -6, 0), (6, 6, 0), (-6, 6, 0), (0, 0, 1))
    S.mesh_object("Floor", b, [principled("Floor", (0.8, 0.8, 0.8))])
    objects()
    S.add_camera((0.4, -4.2, 1.8), (0.0, 0.4, 0.45), 40.0)
    w = bpy.data.worlds.new("World")
    bpy.context.scene.world = w
    w.use_nodes = True
    bg = w.node_tree.nodes["Background"]
    bg.inputs[0].default_value = (0.8, 0.9, 1.0, 1.0)
    bg.inputs[1].default_value = 1.0


# ---- the extension, from Blender's values ------------------------------------

Q_C = Quaternion((math.sqrt(0.5), -math.sqrt(0.5), 0.0, 0.0))  # w, x, y, z: -90 degrees about X


def node_transform(obj):
    loc, rot, _ = obj.matrix_world.decompose()
    q = Q_C @ rot
    t = (loc.x, loc.z, -loc.y)
    return {"translation": [round(x, 7) for x in t],
            "rotation": [round(x, 7) for x in (q.x, q.y, q.z, q.w)]}


def light_ext(obj):
    L = obj.data
    e = {"type": L.type, "name": obj.name, "color": [round(c, 7) for c in L.color],
         "castShadow": True, "useMIS": True}
    if L.type in ('POINT', 'SPOT', 'AREA'):
        e["power"] = L.energy
    if L.type in ('POINT', 'SPOT'):
        e["radius"] = L.shadow_soft_size
    if L.type == 'SPOT':
        e["spotSize"] = L.spot_size
        e["spotBlend"] = L.spot_blend
    if L.type == 'SUN':
        e["strength"] = L.energy
        e["angle"] = L.angle
    if L.type == 'AREA':
        e["shape"] = L.shape
        e["size"] = L.size
        e["sizeY"] = L.size_y
        e["spread"] = L.spread
    return e


def world_ext(outdir):
    w = bpy.context.scene.world
    nt = w.node_tree
    bg = nt.nodes["Background"]
    e = {"color": [round(c, 7) for c in bg.inputs[0].default_value[:3]],
         "strength": bg.inputs[1].default_value, "visibleToCamera": True}
    env = next((n for n in nt.nodes if n.type == 'TEX_ENVIRONMENT'), None)
    if env:
        mp = next((n for n in nt.nodes if n.type == 'MAPPING'), None)
        rot = list(mp.inputs["Rotation"].default_value) if mp else [0.0, 0.0, 0.0]
        e["environment"] = {"uri": os.path.basename(env.image.filepath), "projection": "EQUIRECTANGULAR",
                            "rotation": [round(x, 7) for x in rot], "strength": 1.0}
    return e


def add_extension(path, outdir, materials=False):
    with open(path) as f:
        doc = json.load(f)
    if materials:  # the benchmark's Principled materials, as the render engine's writer has them
        PT = load_module("pb_make_principled_tests", os.path.join(HERE, "make_principled_tests.py"))
        for m in doc.get("materials", []):
            m.setdefault("extensions", {})["PHOTONBRIDGE_blender"] = PT.material_extension(bpy.data.materials[m["name"]])
    nodes = doc.setdefault("nodes", [])
    by_name = {n.get("name"): i for i, n in enumerate(nodes)}
    roots = doc["scenes"][doc.get("scene", 0)]["nodes"]
    for obj in bpy.context.scene.objects:
        if obj.type != 'LIGHT':
            continue
        i = by_name.get(obj.name)
        if i is None:  # area lights: the exporter writes no node
            nodes.append({"name": obj.name})
            i = len(nodes) - 1
            roots.append(i)
        nodes[i].update(node_transform(obj))
        nodes[i].pop("scale", None)
        nodes[i].setdefault("extensions", {})["PHOTONBRIDGE_blender"] = {"light": light_ext(obj)}
    r = bpy.context.scene.render
    doc.setdefault("extensions", {})["PHOTONBRIDGE_blender"] = {
        "version": 1, "blender": bpy.app.version_string, "scene": bpy.context.scene.name,
        "render": {"resolution": [r.resolution_x, r.resolution_y], "filmTransparent": r.film_transparent},
        "world": world_ext(outdir)}
    used = doc.setdefault("extensionsUsed", [])
    if "PHOTONBRIDGE_blender" not in used:
        used.append("PHOTONBRIDGE_blender")
    with open(path, "w") as f:
        json.dump(doc, f, indent=1, sort_keys=True)
        f.write("\n")


# ---- Cycles -------------------------------------------------------------------

def diffuse_for_cycles():
    """Principled (Specular 0, Roughness 1) -> Diffuse BSDF of its colour."""
    for mat in bpy.data.materials:
        nt = mat.node_tree
        p = nt.nodes.get("Principled BSDF") if nt else None
        if not p:
            continue
        d = nt.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = p.inputs["Base Color"].default_value
        nt.links.new(d.outputs[0], nt.nodes["Material Output"].inputs["Surface"])


def read_exr(path):
    im = bpy.data.images.load(path)
    px = list(im.pixels)
    bpy.data.images.remove(im)
    return px


def cycles(outdir, samples, threads, keep_second=False, as_diffuse=True):
    if as_diffuse:  # the one-light scenes; the benchmark's are Principled in Cycles too
        diffuse_for_cycles()
    sc = bpy.context.scene
    info = {"samples": samples, "blender": bpy.app.version_string, "max_bounces": 7, "pixel_filter": "box 1 px",
            "note": "Cycles max_bounces 7 = photonbridge's 8 scattering events",
            "materials": "Diffuse BSDFs of the Principled colours" if as_diffuse else "the scene's Principled BSDFs"}
    paths = []
    for seed in (1, 2):
        p = os.path.join(outdir, "cycles.exr" if seed == 1 else "cycles_seed2.exr")
        RC.configure(sc, p, samples, threads, seed, 7)
        # photonbridge's pixels are boxes: Cycles' default 1.5 px
        # Blackman-Harris would blur every edge across a 48 px image.
        sc.cycles.pixel_filter_type = 'BOX'
        sc.cycles.filter_width = 1.0
        t0 = time.time()
        bpy.ops.render.render(write_still=True)
        info.setdefault("render_s", []).append(round(time.time() - t0, 2))
        paths.append(p)
    a, b = read_exr(paths[0]), read_exr(paths[1])
    n = len(a) // 4
    se, rel, mean = 0.0, 0.0, 0.0
    for i in range(n):
        for c in range(3):
            x, y = a[4 * i + c], b[4 * i + c]
            var = (x - y) ** 2 / 2.0      # one render's variance, per pixel
            se += var
            rel += var / (x * x + 0.01)
            mean += x
    info["seeds"] = [1, 2]
    info["noise_rmse"] = math.sqrt(se / (3 * n))
    info["noise_relmse"] = rel / (3 * n)
    info["mean"] = mean / (3 * n)
    if not keep_second:  # the benchmark keeps it: its noise PSNR is measured with photonbridge compare
        os.remove(paths[1])
    with open(os.path.join(outdir, "cycles.json"), "w") as f:
        json.dump(info, f, indent=1, sort_keys=True)
        f.write("\n")
    return info


def main(argv):
    ap = argparse.ArgumentParser(prog="light_scenes.py")
    ap.add_argument("--out", required=True)
    ap.add_argument("--only", choices=sorted(SCENES) + sorted(BENCH_SCENES), action="append")
    ap.add_argument("--bench", action="store_true", help="the benchmark's scenes (default width 128)")
    ap.add_argument("--samples", type=int, default=2048)
    ap.add_argument("--width", type=int, default=0, help="image width (48; --bench: 128)")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--no-render", action="store_true", help="write the glTF files only")
    args = ap.parse_args(argv)
    table = BENCH_SCENES if args.bench else SCENES
    width = args.width or (128 if args.bench else 48)
    for name in [n for n in table if not args.only or n in args.only]:
        outdir = os.path.abspath(os.path.join(args.out, name))
        os.makedirs(outdir, exist_ok=True)
        fn = table[name]
        if "outdir" in fn.__code__.co_varnames:
            fn(width, outdir=outdir)
        else:
            fn(width)
        path = os.path.join(outdir, name + ".gltf")
        S.gltf_export(path)
        add_extension(path, outdir, materials=args.bench)
        print("light_scenes: %s written" % path)
        if not args.no_render:
            info = cycles(outdir, args.samples, args.threads, keep_second=args.bench, as_diffuse=not args.bench)
            print("light_scenes: %s: Cycles %d spp, %s s, noise RMSE %.4g (relMSE %.3g)" % (
                name, args.samples, info["render_s"], info["noise_rmse"], info["noise_relmse"]))
    bpy.ops.wm.read_factory_settings(use_empty=True)


if __name__ == "__main__":
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    main(argv)
