"""The Principled BSDF v2 (Blender 4.x) test scenes and their Cycles 4.x references.

    python exporters/blender/make_principled2_tests.py --out tests/data/principled2 \
        [--only NAME] [--samples 2048] [--no-render]          (bpy 4.x as a module, e.g. tools/bpy45)

The scenes of make_principled_tests.py (one material on a smooth UV sphere,
radius 1 m, 64 x 32 segments, one 500 W point light of radius 0, a black
world, a 50 mm camera 4 m away, 64 x 64 pixels), each with one Principled v2
lobe alone on constant inputs: Lambert diffuse; the dielectric specular of a
black base at three roughnesses, GGX and Multiscatter GGX, with a Specular
IOR Level and a coloured Specular Tint; F82-tint metal (GGX and
Multiscatter); an anisotropic metal; rough glass in front of an emissive
card (GGX and Multiscatter); a tinted coat over a black base; microfiber
sheen lit from behind; emission under a coat and sheen; and, in the
Principled's place, the Metallic BSDF (model metallic: F82 with GGX, and
anisotropic with Multiscatter GGX, F82 with Beckmann; Physical Conductor
with Multiscatter GGX, and anisotropic with GGX) and the Sheen BSDF (model sheen:
Microfiber, lit from behind; Ashikhmin, lit from the front), the Glossy BSDF (model glossy: anisotropic
with Multiscatter GGX, negative Anisotropy with GGX, anisotropic Beckmann),
the Glass BSDF (model glass: Multiscatter GGX, GGX, Beckmann) and the
Refraction BSDF (model refraction: GGX, Beckmann), the glass and refraction
in front of the card; Thin Film iridescence on the dielectric specular,
over a diffuse base and on rough glass; a stripe normal map on the Normal
(at strengths 0.5 and 2, and under a coat, which keeps the interpolated
normal) and on the Coat Normal; Mix Shaders of two BSDFs (Diffuse and
Glossy by a Layer Weight's Fresnel and by a Fresnel node, Principled and
Metallic by an image mask, Diffuse and Sheen by a Layer Weight's Facing)
and an Add Shader of a Diffuse and a Glossy BSDF.
Each NAME gets

  OUT/NAME/NAME.gltf + .bin   written by the render engine's writer
                              (photonbridge/writer.py: model principled2);
  OUT/NAME/cycles.exr         Cycles (CPU) of this Blender, 32-bit float RGB,
                              box filter of width 1, no denoising, no
                              clamping, seed 0 (validation/run_cycles.py);

and OUT/cycles.json records Blender's version, the samples, the settings and
Cycles' own noise (two more renders of half the samples, seeds 1 and 2)."""
import argparse
import importlib.util
import json
import os
import sys
import time

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)


def load(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


samples = load("pb_make_samples", os.path.join(HERE, "make_samples.py"))
cycles = load("pb_run_cycles", os.path.join(ROOT, "validation", "run_cycles.py"))
v1 = load("pb_make_principled_tests", os.path.join(HERE, "make_principled_tests.py"))
from photonbridge import writer  # noqa: E402

WIDTH = 64
LIGHT_W = 500.0
# Nothing but the lobe under test: black base (no diffuse), Specular IOR
# Level 0 (no dielectric specular: eta 1).
ISOLATED = {"Base Color": (0.0, 0.0, 0.0, 1.0), "Specular IOR Level": 0.0}
COPPER = (0.95, 0.64, 0.54, 1.0)

CASES = {
    "diffuse": {"Base Color": (0.8, 0.45, 0.2, 1.0), "Specular IOR Level": 0.0},
    "specular_ggx_r02": dict(ISOLATED, **{"Specular IOR Level": 0.5, "Roughness": 0.2, "_distribution": "GGX"}),
    "specular_ggx_r05": dict(ISOLATED, **{"Specular IOR Level": 0.8, "Roughness": 0.5, "IOR": 1.6,
                                          "_distribution": "GGX"}),
    "specular_multi_r05": dict(ISOLATED, **{"Specular IOR Level": 0.8, "Roughness": 0.5, "IOR": 1.6}),
    "specular_multi_r09": dict(ISOLATED, **{"Specular IOR Level": 1.0, "Roughness": 0.9,
                                            "Specular Tint": (1.0, 0.6, 0.3, 1.0)}),
    "metal_ggx": {"Base Color": COPPER, "Metallic": 1.0, "Roughness": 0.4, "_distribution": "GGX"},
    "metal_multi": {"Base Color": COPPER, "Metallic": 1.0, "Roughness": 0.8, "Specular Tint": (0.9, 0.7, 0.6, 1.0)},
    "metal_aniso": {"Base Color": (0.9, 0.9, 0.9, 1.0), "Metallic": 1.0, "Roughness": 0.35, "Anisotropic": 0.8,
                    "Anisotropic Rotation": 0.1},
    "glass_ggx": {"Base Color": (1.0, 0.9, 0.7, 1.0), "Transmission Weight": 1.0, "Roughness": 0.3, "IOR": 1.45,
                  "_distribution": "GGX", "_card": True},
    "glass_multi": {"Base Color": (1.0, 1.0, 1.0, 1.0), "Transmission Weight": 1.0, "Roughness": 0.5,
                    "IOR": 1.45, "_card": True},
    "coat": dict(ISOLATED, **{"Coat Weight": 1.0, "Coat Roughness": 0.2, "Coat IOR": 1.6,
                              "Coat Tint": (0.8, 0.9, 1.0, 1.0)}),
    "coat_diffuse": {"Base Color": (0.2, 0.5, 0.8, 1.0), "Coat Weight": 0.7, "Coat Roughness": 0.1,
                     "Coat Tint": (1.0, 0.7, 0.5, 1.0), "Specular IOR Level": 0.0},
    "sheen": dict(ISOLATED, **{"Sheen Weight": 1.0, "Sheen Roughness": 0.5, "Sheen Tint": (1.0, 0.8, 0.6, 1.0)}),
    "sheen_diffuse": {"Base Color": (0.3, 0.3, 0.6, 1.0), "Sheen Weight": 0.8, "Sheen Roughness": 0.3,
                      "Specular IOR Level": 0.0, "_back_light": False},
    "emission_coat": dict(ISOLATED, **{"Emission Color": (1.0, 0.5, 0.25, 1.0), "Emission Strength": 2.0,
                                       "Coat Weight": 1.0, "Coat Roughness": 0.05, "Coat Tint": (0.5, 1.0, 1.0, 1.0),
                                       "Sheen Weight": 0.5}),
    "default": {},
    # A tangent-space Normal Map (stripes tilted +-0.6 along the U tangent)
    # at Strength 0.5 and 2: Cycles 4.0 scales the map's vector before the
    # tangent frame (xy s, z mix(1, z, saturate(s))), 3.x blended normals.
    "normal_half": {"Base Color": (0.8, 0.8, 0.8, 1.0), "Specular IOR Level": 0.0, "_normal": 0.5},
    "normal_double": {"Base Color": (0.8, 0.8, 0.8, 1.0), "Specular IOR Level": 0.0, "_normal": 2.0},
    # A glossy coat over the stripes: mapped on Normal only (the coat keeps
    # the interpolated normal, Cycles' sd->N), and on Coat Normal only.
    "coat_over_normal_map": {"Base Color": (0.5, 0.5, 0.5, 1.0), "Specular IOR Level": 0.0, "Coat Weight": 1.0,
                             "Coat Roughness": 0.1, "_normal": 1.0},
    "coat_normal_map": {"Base Color": (0.5, 0.5, 0.5, 1.0), "Specular IOR Level": 0.0, "Coat Weight": 1.0,
                        "Coat Roughness": 0.3, "_coat_normal": 1.0},
    # Diffuse Roughness (4.3+) and the Diffuse BSDF's Roughness: Oren-Nayar
    # with Cycles 4.3's energy-preserving multiple scattering.
    "diffuse_rough": {"Base Color": (0.8, 0.45, 0.2, 1.0), "Specular IOR Level": 0.0, "Diffuse Roughness": 0.8},
    "diffuse_bsdf_rough": {"_diffuse_bsdf": ((0.7, 0.7, 0.9, 1.0), 1.0)},
    # The Metallic BSDF (4.3+, F82 Fresnel) and the Sheen BSDF (Microfiber)
    # in the Principled's place: (node, its inputs, its settings).
    "metallic_f82_ggx": {"_node": ("ShaderNodeBsdfMetallic",
                                   {"Base Color": (1.0, 0.78, 0.34, 1.0), "Edge Tint": (1.0, 0.9, 0.6, 1.0),
                                    "Roughness": 0.3},
                                   {"fresnel_type": "F82", "distribution": "GGX"})},
    "metallic_f82_multi_aniso": {"_node": ("ShaderNodeBsdfMetallic",
                                           {"Base Color": (0.9, 0.9, 0.92, 1.0), "Edge Tint": (0.7, 0.8, 1.0, 1.0),
                                            "Roughness": 0.5, "Anisotropy": 0.6, "Rotation": 0.15},
                                           {"fresnel_type": "F82", "distribution": "MULTI_GGX"})},
    "metallic_conductor_multi": {"_node": ("ShaderNodeBsdfMetallic",
                                           {"IOR": (0.27, 0.68, 1.32), "Extinction": (3.61, 2.62, 2.29),
                                            "Roughness": 0.45},
                                           {"fresnel_type": "PHYSICAL_CONDUCTOR", "distribution": "MULTI_GGX"})},
    "metallic_f82_beckmann": {"_node": ("ShaderNodeBsdfMetallic",
                                        {"Base Color": (0.95, 0.64, 0.54, 1.0), "Edge Tint": (1.0, 0.8, 0.7, 1.0),
                                         "Roughness": 0.35},
                                        {"fresnel_type": "F82", "distribution": "BECKMANN"})},
    "metallic_conductor_ggx": {"_node": ("ShaderNodeBsdfMetallic",
                                         {"IOR": (1.8, 1.2, 0.6), "Extinction": (2.5, 3.0, 3.5), "Roughness": 0.25,
                                          "Anisotropy": 0.5, "Rotation": 0.3},
                                         {"fresnel_type": "PHYSICAL_CONDUCTOR", "distribution": "GGX"})},
    "sheen_bsdf": {"_node": ("ShaderNodeBsdfSheen", {"Color": (0.9, 0.6, 0.4, 1.0), "Roughness": 0.35},
                             {"distribution": "MICROFIBER"})},
    # The Sheen BSDF's Ashikhmin (3.x's Velvet BSDF), lit from the front.
    "sheen_ashikhmin": {"_node": ("ShaderNodeBsdfSheen", {"Color": (0.7, 0.3, 0.35, 1.0), "Roughness": 0.5},
                                  {"distribution": "ASHIKHMIN"})},
    # The Glossy BSDF (no Fresnel; 4.0's Anisotropy, stretched the other way
    # from the Principled's, both signs), the Glass BSDF (Color on
    # reflection and transmission) and the Refraction BSDF (no Fresnel), in
    # front of the card.
    "glossy_multi_aniso": {"_node": ("ShaderNodeBsdfAnisotropic",
                                     {"Color": (0.9, 0.6, 0.3, 1.0), "Roughness": 0.45, "Anisotropy": 0.6,
                                      "Rotation": 0.15},
                                     {"distribution": "MULTI_GGX"})},
    "glossy_ggx_negative": {"_node": ("ShaderNodeBsdfAnisotropic",
                                      {"Color": (0.7, 0.8, 0.9, 1.0), "Roughness": 0.3, "Anisotropy": -0.5},
                                      {"distribution": "GGX"})},
    "glass_bsdf_multi": {"_node": ("ShaderNodeBsdfGlass",
                                   {"Color": (0.9, 0.7, 0.5, 1.0), "Roughness": 0.35, "IOR": 1.5},
                                   {"distribution": "MULTI_GGX"}), "_card": True},
    "glass_bsdf_ggx": {"_node": ("ShaderNodeBsdfGlass",
                                 {"Color": (0.6, 0.8, 1.0, 1.0), "Roughness": 0.15, "IOR": 1.33},
                                 {"distribution": "GGX"}), "_card": True},
    "refraction_bsdf": {"_node": ("ShaderNodeBsdfRefraction",
                                  {"Color": (1.0, 0.85, 0.6, 1.0), "Roughness": 0.25, "IOR": 1.45},
                                  {"distribution": "GGX"}), "_card": True},
    # Beckmann: the Refraction BSDF's default, and anisotropic on the Glossy.
    "refraction_beckmann": {"_node": ("ShaderNodeBsdfRefraction", {"Roughness": 0.3, "IOR": 1.5},
                                      {"distribution": "BECKMANN"}), "_card": True},
    "glossy_beckmann_aniso": {"_node": ("ShaderNodeBsdfAnisotropic",
                                        {"Color": (0.8, 0.8, 0.8, 1.0), "Roughness": 0.4, "Anisotropy": 0.5,
                                         "Rotation": 0.2},
                                        {"distribution": "BECKMANN"})},
    "glass_beckmann": {"_node": ("ShaderNodeBsdfGlass", {"Color": (0.8, 1.0, 0.9, 1.0), "Roughness": 0.3, "IOR": 1.5},
                                 {"distribution": "BECKMANN"}), "_card": True},
    # Thin Film (4.2+): Belcour-Barla iridescence on the dielectric specular
    # alone (400 nm), over a grey diffuse base it layers (250 nm, Multiscatter
    # GGX), and on the glass's Fresnel (600 nm, in front of the card).
    "thin_film_specular": dict(ISOLATED, **{"Specular IOR Level": 0.5, "IOR": 1.5, "Roughness": 0.25,
                                            "Thin Film Thickness": 400.0, "Thin Film IOR": 1.33,
                                            "_distribution": "GGX"}),
    "thin_film_diffuse": {"Base Color": (0.5, 0.5, 0.5, 1.0), "Roughness": 0.4, "Thin Film Thickness": 250.0,
                          "Thin Film IOR": 1.6},
    "thin_film_glass": {"Base Color": (1.0, 1.0, 1.0, 1.0), "Transmission Weight": 1.0, "Roughness": 0.3,
                        "IOR": 1.45, "Thin Film Thickness": 600.0, "Thin Film IOR": 2.0, "_distribution": "GGX",
                        "_card": True},
    # Mix Shaders of two BSDFs whose closures differ in kind: a Diffuse and a
    # Glossy BSDF by a Layer Weight's Fresnel and by a Fresnel node, a
    # Principled BSDF and a Metallic BSDF by a stripe mask (an image on Fac),
    # a Diffuse and a Sheen BSDF by a Layer Weight's Facing.
    "mix_diffuse_glossy_layer": {"_mix": (("ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.3, 0.1, 1.0)}, {}),
                                          ("ShaderNodeBsdfGlossy", {"Color": (1.0, 1.0, 1.0, 1.0), "Roughness": 0.2},
                                           {"distribution": "GGX"}),
                                          ("layer", "Fresnel", 0.3))},
    "mix_diffuse_glossy_fresnel": {"_mix": (("ShaderNodeBsdfDiffuse", {"Color": (0.2, 0.5, 0.3, 1.0),
                                                                       "Roughness": 0.5}, {}),
                                            ("ShaderNodeBsdfGlossy", {"Color": (0.9, 0.9, 1.0, 1.0), "Roughness": 0.35},
                                             {"distribution": "MULTI_GGX"}),
                                            ("fresnel", 1.6))},
    "mix_principled_metallic_mask": {"_mix": ((None, {"Base Color": (0.55, 0.25, 0.1, 1.0), "Roughness": 0.7}, {}),
                                              ("ShaderNodeBsdfMetallic", {"Base Color": (0.9, 0.9, 0.92, 1.0),
                                                                          "Roughness": 0.25}, {}),
                                              ("mask",))},
    "mix_diffuse_sheen_facing": {"_mix": (("ShaderNodeBsdfDiffuse", {"Color": (0.25, 0.3, 0.6, 1.0)}, {}),
                                          ("ShaderNodeBsdfSheen", {"Color": (1.0, 0.85, 0.7, 1.0), "Roughness": 0.4},
                                           {}),
                                          ("layer", "Facing", 0.65))},
    # An Add Shader of a Diffuse and a Glossy BSDF (each at full weight).
    "add_diffuse_glossy": {"_mix": (("ShaderNodeBsdfDiffuse", {"Color": (0.5, 0.45, 0.4, 1.0), "Roughness": 0.3}, {}),
                                    ("ShaderNodeBsdfGlossy", {"Color": (0.3, 0.35, 0.5, 1.0), "Roughness": 0.3},
                                     {"distribution": "GGX"}),
                                    ("add",))},
}
BACK_LIGHT = ("sheen", "sheen_bsdf")


def stripe_mask(out_dir):
    """A Non-Color 64 x 64 grey PNG beside the glTF: 8 stripes along U of 0.15
    and 0.85."""
    n = 64
    rows = b""
    for y in range(n):
        rows += b"\x00" + bytes(round(255.0 * (0.85 if (x * 8 // n) % 2 else 0.15)) for x in range(n))
    return v1.non_color_png(os.path.join(out_dir, "mask.png"), n, 0, rows)


def mix_shader(mat, p, spec, out_dir):
    """A Mix Shader of two BSDF nodes (None: the Principled BSDF p) into the
    Material Output, its Fac a Layer Weight output, a Fresnel node or a
    stripe mask."""
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    made = []
    for kind, socks, props in spec[:2]:
        n = p if kind is None else nodes.new(kind)
        for k, v in props.items():
            setattr(n, k, v)
        for k, v in socks.items():
            n.inputs[k].default_value = v
        made.append(n)
    fac = spec[2]
    add = fac[0] == "add"
    mix = nodes.new("ShaderNodeAddShader" if add else "ShaderNodeMixShader")
    links.new(made[0].outputs["BSDF"], mix.inputs[0 if add else 1])
    links.new(made[1].outputs["BSDF"], mix.inputs[1 if add else 2])
    if add:
        pass
    elif fac[0] == "layer":
        lw = nodes.new("ShaderNodeLayerWeight")
        lw.inputs["Blend"].default_value = fac[2]
        links.new(lw.outputs[fac[1]], mix.inputs["Fac"])
    elif fac[0] == "fresnel":
        fr = nodes.new("ShaderNodeFresnel")
        fr.inputs["IOR"].default_value = fac[1]
        links.new(fr.outputs["Fac"], mix.inputs["Fac"])
    else:
        tex = nodes.new("ShaderNodeTexImage")
        tex.image = stripe_mask(out_dir)
        links.new(tex.outputs["Color"], mix.inputs["Fac"])
    links.new(mix.outputs["Shader"], nodes["Material Output"].inputs["Surface"])


def build(name, inputs, out_dir):
    sc = samples.reset_scene(WIDTH, WIDTH)
    v1.world_black(sc)
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    p = mat.node_tree.nodes["Principled BSDF"]
    for k, v in inputs.items():
        if not k.startswith("_"):
            p.inputs[k].default_value = v
    p.distribution = inputs.get("_distribution", "MULTI_GGX")
    if "_diffuse_bsdf" in inputs:  # a Diffuse BSDF node in the Principled's place
        color, rough = inputs["_diffuse_bsdf"]
        d = mat.node_tree.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = color
        d.inputs["Roughness"].default_value = rough
        out = mat.node_tree.nodes["Material Output"]
        mat.node_tree.links.new(d.outputs["BSDF"], out.inputs["Surface"])
    if "_node" in inputs:  # another BSDF node in the Principled's place
        kind, socks, props = inputs["_node"]
        n = mat.node_tree.nodes.new(kind)
        for k, v in props.items():
            setattr(n, k, v)
        for k, v in socks.items():
            n.inputs[k].default_value = v
        out = mat.node_tree.nodes["Material Output"]
        mat.node_tree.links.new(n.outputs["BSDF"], out.inputs["Surface"])
    if "_mix" in inputs:
        mix_shader(mat, p, inputs["_mix"], out_dir)
    if "_normal" in inputs:
        v1.normal_map(mat, p, inputs["_normal"], out_dir)
    if "_coat_normal" in inputs:
        v1.normal_map(mat, p, inputs["_coat_normal"], out_dir, "Coat Normal")
    b = samples.MeshBuilder()
    samples.uv_sphere(b, (0.0, 0.0, 0.0), 1.0, 64, 32)
    samples.mesh_object("Sphere", b, [mat])
    if inputs.get("_card"):
        card = samples.MeshBuilder()
        card.face([(-2.5, 3.0, -2.5), (2.5, 3.0, -2.5), (2.5, 3.0, 2.5), (-2.5, 3.0, 2.5)], normal=(0.0, -1.0, 0.0))
        samples.mesh_object("Card", card, [v1.emission_material("Card", 2.0)])
    samples.add_point_light("Light", (3.0, 3.0, 0.5) if name in BACK_LIGHT else (-2.0, -3.0, 3.0), LIGHT_W)
    samples.add_camera((0.0, -4.0, 0.0), (0.0, 0.0, 0.0), 50.0)


def main(argv):
    ap = argparse.ArgumentParser(prog="make_principled2_tests.py")
    ap.add_argument("--out", required=True)
    ap.add_argument("--only", choices=sorted(CASES), action="append")
    ap.add_argument("--samples", type=int, default=2048, help="Cycles samples of the committed image")
    ap.add_argument("--no-render", action="store_true", help="write the glTF only")
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
        writer.write_gltf(bpy.context.evaluated_depsgraph_get(), path)
        print("make_principled2_tests: %s: %s" % (name, path))
        if args.no_render:
            continue
        sc = bpy.context.scene
        half = max(1, args.samples // 2)
        t0 = time.time()
        v1.render(sc, os.path.join(d, "cycles.exr"), 2 * half, 0)
        dt = time.time() - t0
        halves = []
        for seed in (1, 2):
            tmp = os.path.join(d, "half%d.exr" % seed)
            v1.render(sc, tmp, half, seed)
            halves.append(v1.read_exr_rgb(tmp))
            os.remove(tmp)
        (w, h, a), (_, _, b) = halves
        ma = sum(sum(px) for px in a) / (3 * len(a))
        mb = sum(sum(px) for px in b) / (3 * len(b))
        halves_psnr = v1.psnr_srgb(a, b)
        report[name] = {"blender": bpy.app.version_string, "samples": 2 * half, "width": w, "height": h,
                        "render_s": round(dt, 2), "pixel_filter": "BOX 1.0", "device": "CPU", "bounces": 64,
                        "denoising": False, "clamp": 0, "seed": 0,
                        "halves_psnr_db": round(halves_psnr, 2),
                        "noise_psnr_db": round(halves_psnr + 6.02, 2),
                        "halves_mean_diff": round((ma - mb) / max(0.5 * (ma + mb), 1e-12), 5)}
        print("make_principled2_tests: %s: Cycles %d spp in %.1f s; noise %.2f dB" % (
            name, 2 * half, dt, halves_psnr + 6.02))
        with open(report_path, "w") as f:
            json.dump(report, f, indent=1, sort_keys=True)
            f.write("\n")
    bpy.ops.wm.read_factory_settings(use_empty=True)


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:])
