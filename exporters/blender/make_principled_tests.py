"""The Principled BSDF test scenes and their Cycles references.

    blender -b --factory-startup --python-exit-code 1 \
        -P exporters/blender/make_principled_tests.py -- --out tests/data/principled \
        [--only NAME] [--samples 2048] [--no-render]

Each scene is one Blender 3.4 material on a smooth UV sphere (radius 1 m,
64 x 32 segments) under one point light (500 W, radius 0) in a black world,
seen by a 50 mm camera 4 m away, 64 x 64 pixels: each Principled lobe alone
(diffuse at roughness 0, 0.5 and 1; the specular layer of a black dielectric
at three roughnesses with GGX and with Multiscatter GGX; a copper metal with
each distribution; Blender's Diffuse BSDF (Oren-Nayar); an anisotropic metal, whose tangent is Cycles' default
(radial about the object's Z); sheen, lit from behind; clearcoat), a rough Principled glass in front of an
emissive card (which it refracts), a white furnace (an albedo-1
Principled sphere inside a closed emissive sphere of radiance 1, which is a
uniform world), and a studio (floor, wall, two spheres and a box, all
Blender's default Principled BSDF, GGX and Multiscatter GGX, 128 x 96,
8192 samples, full global illumination). For each NAME the script writes

  OUT/NAME/NAME.gltf + .bin   Blender's own glTF export, with the
                              PHOTONBRIDGE_blender material extension added
                              by the post-pass below from the material's
                              socket values (the render engine's writer will
                              replace this small helper);
  OUT/NAME/cycles.exr         Cycles 3.4 (CPU), 32-bit float RGB, box pixel
                              filter of width 1 (the reference renderer's
                              pixel), no denoising, no clamping, seed 0;

and OUT/cycles.json the sample count, time and Cycles' own noise per scene,
from two more renders of half the samples each (seeds 1 and 2): their PSNR
and mean difference, and the committed render's noise PSNR that follows.
Same seeds, same pictures."""
import argparse
import importlib.util
import json
import math
import os
import struct
import sys
import time

import bpy

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


samples = load("pb_make_samples", os.path.join(HERE, "make_samples.py"))
cycles = load("pb_run_cycles", os.path.join(ROOT, "validation", "run_cycles.py"))

WIDTH = 64
LIGHT_W = 500.0
# Principled inputs every lobe scene starts from: nothing but the lobe under
# test (black base: no diffuse; Specular 0: no specular layer).
ISOLATED = {"Base Color": (0.0, 0.0, 0.0, 1.0), "Specular": 0.0}

CASES = {
    "diffuse_r0": {"Base Color": (0.8, 0.45, 0.2, 1.0), "Specular": 0.0, "Roughness": 0.0},
    "diffuse_r05": {"Base Color": (0.8, 0.45, 0.2, 1.0), "Specular": 0.0, "Roughness": 0.5},
    "diffuse_r1": {"Base Color": (0.8, 0.45, 0.2, 1.0), "Specular": 0.0, "Roughness": 1.0},
    "specular_ggx_r02": dict(ISOLATED, **{"Specular": 1.0, "Roughness": 0.2}),
    "specular_ggx_r05": dict(ISOLATED, **{"Specular": 1.0, "Roughness": 0.5}),
    "specular_ggx_r09": dict(ISOLATED, **{"Specular": 1.0, "Roughness": 0.9}),
    "specular_multi_r02": dict(ISOLATED, **{"Specular": 1.0, "Roughness": 0.2, "_distribution": "MULTI_GGX"}),
    "specular_multi_r05": dict(ISOLATED, **{"Specular": 1.0, "Roughness": 0.5, "_distribution": "MULTI_GGX"}),
    "specular_multi_r09": dict(ISOLATED, **{"Specular": 1.0, "Roughness": 0.9, "_distribution": "MULTI_GGX"}),
    "metal_ggx": {"Base Color": (0.95, 0.64, 0.54, 1.0), "Metallic": 1.0, "Roughness": 0.4},
    "metal_multi": {"Base Color": (0.95, 0.64, 0.54, 1.0), "Metallic": 1.0, "Roughness": 0.8,
                    "_distribution": "MULTI_GGX"},
    "metal_aniso": {"Base Color": (0.9, 0.9, 0.9, 1.0), "Metallic": 1.0, "Roughness": 0.35, "Anisotropic": 0.8,
                    "Anisotropic Rotation": 0.1},
    "sheen": dict(ISOLATED, **{"Sheen": 1.0, "Sheen Tint": 0.0}),
    "clearcoat": dict(ISOLATED, **{"Clearcoat": 1.0, "Clearcoat Roughness": 0.2}),
    # A glossy clearcoat over a stripe normal map on Normal only: the coat
    # keeps the interpolated normal (Cycles' sd->N).
    "clearcoat_over_normal_map": {"Base Color": (0.5, 0.5, 0.5, 1.0), "Specular": 0.0, "Clearcoat": 1.0,
                                  "Clearcoat Roughness": 0.1, "_normal": 1.0},
    # ... and the stripes on Clearcoat Normal only.
    "clearcoat_normal_map": {"Base Color": (0.5, 0.5, 0.5, 1.0), "Specular": 0.0, "Clearcoat": 1.0,
                             "Clearcoat Roughness": 0.1, "_coat_normal": 1.0},
    "glass": {"Base Color": (1.0, 1.0, 1.0, 1.0), "Transmission": 1.0, "Roughness": 0.3, "IOR": 1.45},
    "furnace": {"Base Color": (1.0, 1.0, 1.0, 1.0), "_furnace": True},
    # Blender's Diffuse BSDF (Oren-Nayar at roughness 0.6), not a Principled.
    "diffuse_bsdf": {"_diffuse_bsdf": (0.3, 0.6, 0.9, 0.6)},
    # The studio: every surface Blender's default Principled BSDF (Base 0.8,
    # Specular 0.5, Roughness 0.5, GGX), full global illumination.
    "studio": {"_studio": True},
    "studio_multi": {"_studio": True, "_distribution": "MULTI_GGX"},
    # Blender 3.4's Anisotropic (GGX), Glass (GGX) and Refraction (Beckmann)
    # BSDFs in the Principled's place, written by the render engine's writer
    # (models glossy, glass, refraction), the glass and refraction in front
    # of the card: (node, its inputs, its settings).
    "glossy34_aniso": {"_node": ("ShaderNodeBsdfAnisotropic",
                                 {"Color": (0.9, 0.6, 0.3, 1.0), "Roughness": 0.4, "Anisotropy": 0.5,
                                  "Rotation": 0.1}, {"distribution": "GGX"})},
    "glass34_ggx": {"_node": ("ShaderNodeBsdfGlass", {"Color": (0.9, 0.8, 0.6, 1.0), "Roughness": 0.3,
                                                       "IOR": 1.45}, {"distribution": "GGX"}), "_card": True},
    "refraction34_beckmann": {"_node": ("ShaderNodeBsdfRefraction", {"Color": (1.0, 0.9, 0.8, 1.0),
                                                                     "Roughness": 0.25, "IOR": 1.45},
                                        {"distribution": "BECKMANN"}), "_card": True},
    # Blender 3.4's Velvet BSDF (the writer's sheen model, Ashikhmin), lit
    # from the front as 4.5's sheen_ashikhmin is.
    "velvet34": {"_node": ("ShaderNodeBsdfVelvet", {"Color": (0.6, 0.2, 0.3, 1.0), "Sigma": 0.5}, {})},
    # A Mix Shader of Blender 3.4's Diffuse (Oren-Nayar) and Glossy (GGX)
    # BSDFs by a Fresnel node, the layered material of Blender 2.7x.
    "mix34_diffuse_glossy": {"_mix": (("ShaderNodeBsdfDiffuse", {"Color": (0.7, 0.35, 0.15, 1.0), "Roughness": 0.4},
                                       {}),
                                      ("ShaderNodeBsdfGlossy", {"Color": (1.0, 1.0, 1.0, 1.0), "Roughness": 0.15},
                                       {"distribution": "GGX"}),
                                      ("fresnel", 1.45))},
}
# Image size and Cycles samples where a scene needs its own.
SIZE = {"studio": (128, 96), "studio_multi": (128, 96)}
SAMPLES = {"studio": 8192, "studio_multi": 8192}

# Principled BSDF socket -> the extension's lowerCamelCase member.
SOCKETS = ["Base Color", "Subsurface", "Subsurface Radius", "Subsurface Color", "Metallic", "Specular",
           "Specular Tint", "Roughness", "Anisotropic", "Anisotropic Rotation", "Sheen", "Sheen Tint",
           "Clearcoat", "Clearcoat Roughness", "IOR", "Transmission", "Transmission Roughness", "Emission",
           "Emission Strength", "Alpha"]


def camel(name):
    words = name.split()
    return words[0].lower() + "".join(w.capitalize() for w in words[1:])


def world_black(sc):
    w = bpy.data.worlds.new("World")
    w.use_nodes = True
    bg = w.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    bg.inputs["Strength"].default_value = 0.0
    sc.world = w


def emission_material(name, strength):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.remove(nt.nodes["Principled BSDF"])
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    em.inputs["Strength"].default_value = strength
    nt.links.new(em.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    return mat


def build_studio(inputs):
    """A floor and a back wall, a sphere, a box and a small sphere, all one
    default Principled material, lit by a 150 W point light."""
    sc = samples.reset_scene(*SIZE["studio"])
    world_black(sc)
    mat = bpy.data.materials.new("Default")
    mat.use_nodes = True
    mat.node_tree.nodes["Principled BSDF"].distribution = inputs.get("_distribution", "GGX")
    room = samples.MeshBuilder()
    room.face([(-4.0, -4.0, 0.0), (4.0, -4.0, 0.0), (4.0, 3.0, 0.0), (-4.0, 3.0, 0.0)], normal=(0.0, 0.0, 1.0))
    room.face([(-4.0, 3.0, 0.0), (4.0, 3.0, 0.0), (4.0, 3.0, 4.0), (-4.0, 3.0, 4.0)], normal=(0.0, -1.0, 0.0))
    samples.mesh_object("Room", room, [mat])
    ball = samples.MeshBuilder()
    samples.uv_sphere(ball, (-0.8, 0.5, 0.6), 0.6, 64, 32)
    samples.uv_sphere(ball, (0.25, -0.7, 0.3), 0.3, 48, 24, group="small")
    samples.mesh_object("Spheres", ball, [mat])
    box = samples.MeshBuilder()
    samples.box(box, (0.8, 0.4, 0.4), (0.8, 0.8, 0.8), rot_z_deg=25.0, skip=('-z',))
    samples.mesh_object("Box", box, [mat])
    samples.add_point_light("Light", (1.5, -1.5, 3.0), 150.0)
    samples.add_camera((0.0, -5.0, 1.6), (0.0, 0.5, 0.6), 40.0)


def non_color_png(path, n, color_type, rows):
    """Writes an n x n 8-bit PNG (color_type 0 grey, 2 RGB; rows with their
    filter bytes) and loads it into Blender as a Non-Color image."""
    import struct
    import zlib

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", n, n, 8, color_type, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
    img = bpy.data.images.load(path)
    img.colorspace_settings.name = "Non-Color"
    return img


def normal_map(mat, p, strength, out_dir, socket="Normal"):
    """A Non-Color stripe normal map (64 x 64 PNG beside the glTF: 8 stripes
    along U whose normals tilt by +-0.6 along the tangent) through a
    tangent-space Normal Map node of the given Strength into p's `socket`."""
    import math
    n = 64
    rows = b""
    for y in range(n):
        row = b"\x00"  # PNG filter: none
        for x in range(n):
            tx = 0.6 * math.sin(2.0 * math.pi * 8.0 * (x + 0.5) / n)
            ln = math.sqrt(tx * tx + 1.0)
            row += bytes(round(255.0 * (0.5 + 0.5 * c)) for c in (tx / ln, 0.0, 1.0 / ln))
        rows += row
    img = non_color_png(os.path.join(out_dir, "stripes.png"), n, 2, rows)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = img
    nm = nodes.new("ShaderNodeNormalMap")
    nm.space = "TANGENT"
    nm.inputs["Strength"].default_value = strength
    links.new(tex.outputs["Color"], nm.inputs["Color"])
    links.new(nm.outputs["Normal"], p.inputs[socket])


def build(name, inputs, out_dir=None):
    if inputs.get("_studio"):
        return build_studio(inputs)
    sc = samples.reset_scene(WIDTH, WIDTH)
    world_black(sc)
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    p = mat.node_tree.nodes["Principled BSDF"]
    for k, v in inputs.items():
        if not k.startswith("_"):
            p.inputs[k].default_value = v
    p.distribution = inputs.get("_distribution", "GGX")
    if "_diffuse_bsdf" in inputs:
        r, g, b_, rough = inputs["_diffuse_bsdf"]
        nt = mat.node_tree
        nt.nodes.remove(p)
        d = nt.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = (r, g, b_, 1.0)
        d.inputs["Roughness"].default_value = rough
        nt.links.new(d.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    if "_node" in inputs:
        kind, socks, props = inputs["_node"]
        nt = mat.node_tree
        nt.nodes.remove(p)
        n = nt.nodes.new(kind)
        for k, v in props.items():
            setattr(n, k, v)
        for k, v in socks.items():
            n.inputs[k].default_value = v
        nt.links.new(n.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    if "_mix" in inputs:
        nt = mat.node_tree
        made = []
        for kind, socks, props in inputs["_mix"][:2]:
            n = nt.nodes.new(kind)
            for k, v in props.items():
                setattr(n, k, v)
            for k, v in socks.items():
                n.inputs[k].default_value = v
            made.append(n)
        nt.nodes.remove(p)
        mix = nt.nodes.new("ShaderNodeMixShader")
        nt.links.new(made[0].outputs[0], mix.inputs[1])
        nt.links.new(made[1].outputs[0], mix.inputs[2])
        fr = nt.nodes.new("ShaderNodeFresnel")
        fr.inputs["IOR"].default_value = inputs["_mix"][2][1]
        nt.links.new(fr.outputs["Fac"], mix.inputs["Fac"])
        nt.links.new(mix.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    if "_normal" in inputs:
        normal_map(mat, p, inputs["_normal"], out_dir)
    if "_coat_normal" in inputs:
        normal_map(mat, p, inputs["_coat_normal"], out_dir, "Clearcoat Normal")
    b = samples.MeshBuilder()
    samples.uv_sphere(b, (0.0, 0.0, 0.0), 1.0, 64, 32)
    samples.mesh_object("Sphere", b, [mat])
    if inputs.get("_furnace"):
        # A closed sphere of radiance 1 facing inwards all round: a uniform
        # world for the object inside (Cycles and photonbridge alike).
        shell = samples.MeshBuilder()
        samples.uv_sphere(shell, (0.0, 0.0, 0.0), 20.0, 32, 16, group="shell")
        samples.mesh_object("Shell", shell, [emission_material("Shell", 1.0)])
        samples.add_camera((0.0, -4.0, 0.0), (0.0, 0.0, 0.0), 50.0)
        return
    if name == "glass" or inputs.get("_card"):
        card = samples.MeshBuilder()
        card.face([(-2.5, 3.0, -2.5), (2.5, 3.0, -2.5), (2.5, 3.0, 2.5), (-2.5, 3.0, 2.5)], normal=(0.0, -1.0, 0.0))
        samples.mesh_object("Card", card, [emission_material("Card", 2.0)])
    # Sheen lives at grazing half-angles: light it from behind, so the rim
    # the camera sees has wi.h small.
    samples.add_point_light("Light", (3.0, 3.0, 0.5) if name == "sheen" else (-2.0, -3.0, 3.0), LIGHT_W)
    samples.add_camera((0.0, -4.0, 0.0), (0.0, 0.0, 0.0), 50.0)


def material_extension(mat):
    """The PHOTONBRIDGE_blender member of one material, from its node tree
    (only what these scenes use: a Principled BSDF, a Diffuse BSDF or an
    Emission shader on the output)."""
    nt = mat.node_tree
    out = nt.nodes["Material Output"].inputs["Surface"]
    node = out.links[0].from_node
    if node.type == 'BSDF_DIFFUSE':
        return {"model": "diffuse", "diffuse": {"color": list(node.inputs["Color"].default_value),
                                                 "roughness": node.inputs["Roughness"].default_value}}
    if node.type == 'EMISSION':
        return {"model": "emission",
                "emission": {"color": list(node.inputs["Color"].default_value),
                             "strength": node.inputs["Strength"].default_value}}
    assert node.type == 'BSDF_PRINCIPLED', node.type
    pr = {"distribution": node.distribution, "subsurfaceMethod": node.subsurface_method}
    for s in SOCKETS:
        v = node.inputs[s].default_value
        pr[camel(s)] = list(v) if hasattr(v, "__len__") else float(v)
    return {"model": "principled", "principled": pr, "blendMethod": mat.blend_method,
            "alphaThreshold": mat.alpha_threshold, "backfaceCulling": mat.use_backface_culling}


def add_extension(path):
    with open(path) as f:
        doc = json.load(f)
    for m in doc.get("materials", []):
        mat = bpy.data.materials[m["name"]]
        m.setdefault("extensions", {})["PHOTONBRIDGE_blender"] = material_extension(mat)
    used = doc.setdefault("extensionsUsed", [])
    if "PHOTONBRIDGE_blender" not in used:
        used.append("PHOTONBRIDGE_blender")
    with open(path, "w") as f:
        json.dump(doc, f, indent=1, sort_keys=True, allow_nan=False)
        f.write("\n")


def read_exr_rgb(path):
    """Float RGB of a Cycles EXR, through Blender's image loader."""
    img = bpy.data.images.load(path)
    w, h = img.size
    px = list(img.pixels[:])
    bpy.data.images.remove(img)
    return w, h, [(px[4 * i], px[4 * i + 1], px[4 * i + 2]) for i in range(w * h)]


def render(sc, out, spp, seed):
    cycles.configure(sc, out, spp, 0, seed, 64)
    sc.cycles.pixel_filter_type = 'BOX'
    sc.cycles.filter_width = 1.0
    bpy.ops.render.render(write_still=True)


def psnr_srgb(a, b):
    """PSNR of the sRGB-encoded, clipped pictures (the display image)."""
    def enc(v):
        v = min(max(v, 0.0), 1.0)
        return 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055
    se = 0.0
    for pa, pb in zip(a, b):
        for c in range(3):
            se += (enc(pa[c]) - enc(pb[c])) ** 2
    mse = se / (3 * len(a))
    return float("inf") if mse == 0 else 10 * math.log10(1.0 / mse)


def main(argv):
    ap = argparse.ArgumentParser(prog="make_principled_tests.py")
    ap.add_argument("--out", required=True)
    ap.add_argument("--only", choices=sorted(CASES), action="append")
    ap.add_argument("--samples", type=int, default=2048, help="Cycles samples of the committed image")
    ap.add_argument("--no-render", action="store_true", help="export the glTF only")
    args = ap.parse_args(argv)
    out = os.path.abspath(args.out)
    report_path = os.path.join(out, "cycles.json")
    report = {}
    if os.path.exists(report_path):
        with open(report_path) as f:
            report = json.load(f)
    for name in CASES:
        if args.only and name not in args.only:
            continue
        d = os.path.join(out, name)
        os.makedirs(d, exist_ok=True)
        build(name, CASES[name], d)
        path = os.path.join(d, name + ".gltf")
        if any(k in CASES[name] for k in ("_node", "_normal", "_coat_normal", "_mix")):
            # the render engine's writer (the file records its Blender version)
            sys.path.insert(0, HERE)
            from photonbridge import writer
            writer.write_gltf(bpy.context.evaluated_depsgraph_get(), path)
        else:
            samples.gltf_export(path)
            add_extension(path)
        print("make_principled_tests: %s: %s" % (name, path))
        if args.no_render:
            continue
        sc = bpy.context.scene
        half = max(1, SAMPLES.get(name, args.samples) // 2)
        t0 = time.time()
        render(sc, os.path.join(d, "cycles.exr"), 2 * half, 0)
        dt = time.time() - t0
        halves = []
        for seed in (1, 2):
            tmp = os.path.join(d, "half%d.exr" % seed)
            render(sc, tmp, half, seed)
            halves.append(read_exr_rgb(tmp))
            os.remove(tmp)
        (w, h, a), (_, _, b) = halves
        ma = sum(sum(p) for p in a) / (3 * len(a))
        mb = sum(sum(p) for p in b) / (3 * len(b))
        halves_psnr = psnr_srgb(a, b)
        # Two independent halves differ by twice the variance of one; the
        # committed render has half that variance: its own noise against the
        # converged picture is the halves' PSNR + 10 log10(4) = + 6.02 dB.
        report[name] = {"blender": bpy.app.version_string, "samples": 2 * half, "width": w, "height": h,
                        "render_s": round(dt, 2), "pixel_filter": "BOX 1.0",
                        "halves_psnr_db": round(halves_psnr, 2),
                        "noise_psnr_db": round(halves_psnr + 6.02, 2),
                        "halves_mean_diff": round((ma - mb) / max(0.5 * (ma + mb), 1e-12), 5)}
        print("make_principled_tests: %s: Cycles %d spp in %.1f s; noise %.2f dB, halves' means %.5f / %.5f" % (
            name, 2 * half, dt, halves_psnr + 6.02, ma, mb))
    with open(report_path, "w") as f:
        json.dump(report, f, indent=1, sort_keys=True)
        f.write("\n")
    bpy.ops.wm.read_factory_settings(use_empty=True)


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
