"""The render engine's writer on Principled BSDF v2 (Blender 4.0+) materials.

    python tests/blender/principled2_writer.py PHOTONBRIDGE WORKDIR    (bpy 4.x as a module)
    blender -b --factory-startup --python-exit-code 1 -P tests/blender/principled2_writer.py -- PHOTONBRIDGE WORKDIR

Builds, in the running Blender (4.0 or later), one plane per material with
Principled v2 inputs away from their defaults (every socket the node has),
textures on colour, scalar and normal sockets, an Add-Shader emission, a
Mix-Shader transparency, each subsurface method, the Metallic, Sheen,
Glossy, Glass and Refraction BSDFs;
writes the scene with the add-on's writer (photonbridge/writer.py) and
checks:
- the extension: model "principled2", every member equal to the socket
  (float precision), subsurfaceMethod version-neutral, texture entries where
  linked;
- the plain glTF: KHR_materials_specular / ior / sheen / clearcoat /
  transmission / emissive and the core factors equal to what Blender's own
  glTF exporter (io_scene_gltf2, bundled with this Blender) writes for the
  same scene;
- photonbridge (PHOTONBRIDGE, '-' to skip) loads the file and reports the
  materials as principled2.
Prints "N passed, M failed" and exits non-zero on a failure."""
import json
import os
import subprocess
import sys

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "exporters", "blender"))
from photonbridge import materials, writer  # noqa: E402

# Socket -> a value away from Blender 4.5's default (and inside its range).
V2_VALUES = {
    "Base Color": (0.6, 0.3, 0.2, 1.0), "Metallic": 0.25, "Roughness": 0.35, "IOR": 1.62, "Alpha": 0.9,
    "Diffuse Roughness": 0.2, "Subsurface Weight": 0.3, "Subsurface Radius": (0.5, 0.25, 0.125),
    "Subsurface Scale": 0.1, "Subsurface IOR": 1.33, "Subsurface Anisotropy": 0.4, "Specular IOR Level": 0.3,
    "Specular Tint": (0.9, 0.7, 0.5, 1.0), "Anisotropic": 0.5, "Anisotropic Rotation": 0.125,
    "Transmission Weight": 0.2, "Coat Weight": 0.4, "Coat Roughness": 0.15, "Coat IOR": 1.7,
    "Coat Tint": (0.8, 0.9, 1.0, 1.0), "Sheen Weight": 0.6, "Sheen Roughness": 0.3,
    "Sheen Tint": (1.0, 0.5, 0.8, 1.0), "Emission Color": (1.0, 0.5, 0.25, 1.0), "Emission Strength": 3.0,
    "Thin Film Thickness": 250.0, "Thin Film IOR": 1.45,
}


def same(a, b, tol=1e-6):
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return abs(a - b) <= tol * max(1.0, abs(a), abs(b))
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(same(x, y, tol) for x, y in zip(a, b))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k], tol) for k in a)
    return a == b


def image(name, color, non_color=False):
    img = bpy.data.images.new(name, 4, 4, alpha=True)
    img.pixels = list(color) * 16
    img.pack()
    if non_color:
        img.colorspace_settings.name = "Non-Color"
    return img


def new_material(name):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    return mat, nt, nt.nodes["Principled BSDF"]


def plane(name, mat, x):
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=(x, 0.0, 0.0))
    ob = bpy.context.active_object
    ob.name = name
    ob.data.materials.append(mat)


def build():
    """{material name: what to check}; the scene holds one plane each."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    cases = {}

    # 1. Every v2 socket away from its default, constants.
    mat, nt, p = new_material("all_inputs")
    for k, v in V2_VALUES.items():
        if k in p.inputs:
            p.inputs[k].default_value = v
    p.distribution = 'GGX'
    p.subsurface_method = 'RANDOM_WALK'  # 4.x fixed radius
    cases[mat.name] = {"values": True, "method": "RANDOM_WALK_FIXED_RADIUS", "distribution": "GGX"}
    plane("all_inputs", mat, 0.0)

    # 2. Defaults, Skin method; Specular IOR Level above 0.5 (specularColorFactor x 2 level).
    mat, nt, p = new_material("defaults_skin")
    p.subsurface_method = 'RANDOM_WALK_SKIN'
    p.inputs["Specular IOR Level"].default_value = 0.75
    cases[mat.name] = {"method": "RANDOM_WALK_SKIN", "distribution": "MULTI_GGX"}
    plane("defaults_skin", mat, 1.5)

    # 3. Burley, sheen and coat at the plain glTF's edges (tint black, roughness 0).
    mat, nt, p = new_material("burley_sheen")
    p.subsurface_method = 'BURLEY'
    p.inputs["Sheen Weight"].default_value = 1.0
    p.inputs["Sheen Tint"].default_value = (0.0, 0.0, 0.0, 1.0)
    p.inputs["Sheen Roughness"].default_value = 0.0
    p.inputs["Coat Weight"].default_value = 1.0
    p.inputs["Transmission Weight"].default_value = 1.0
    p.inputs["IOR"].default_value = 1.5
    cases[mat.name] = {"method": "BURLEY"}
    plane("burley_sheen", mat, 3.0)

    # 4. Textures: colour sockets, a scalar through Separate Color, normal and coat normal maps.
    mat, nt, p = new_material("textured")
    for sock, img_name, col, nc in (("Specular Tint", "tint_img", (0.5, 0.6, 0.7, 1.0), False),
                                    ("Coat Tint", "coat_img", (0.9, 0.8, 0.7, 1.0), False),
                                    ("Sheen Tint", "sheen_img", (0.2, 0.4, 0.6, 1.0), False),
                                    ("Emission Color", "em_img", (1.0, 0.9, 0.1, 1.0), False),
                                    ("Base Color", "base_img", (0.3, 0.3, 0.3, 1.0), False)):
        t = nt.nodes.new("ShaderNodeTexImage")
        t.image = image(img_name, col, nc)
        nt.links.new(t.outputs["Color"], p.inputs[sock])
    t = nt.nodes.new("ShaderNodeTexImage")
    t.image = image("scalar_img", (0.1, 0.5, 0.9, 1.0), True)
    sep = nt.nodes.new("ShaderNodeSeparateColor")
    nt.links.new(t.outputs["Color"], sep.inputs[0])
    for sock, ch in (("Coat Weight", "Red"), ("Sheen Roughness", "Green"), ("Specular IOR Level", "Blue")):
        nt.links.new(sep.outputs[ch], p.inputs[sock])
    nt.links.new(t.outputs["Alpha"], p.inputs["Thin Film Thickness"])
    for sock, strength in (("Normal", 0.5), ("Coat Normal", 0.75)):
        n = nt.nodes.new("ShaderNodeTexImage")
        n.image = image("n_" + sock, (0.5, 0.5, 1.0, 1.0), True)
        nm = nt.nodes.new("ShaderNodeNormalMap")
        nm.inputs["Strength"].default_value = strength
        nt.links.new(n.outputs["Color"], nm.inputs["Color"])
        nt.links.new(nm.outputs["Normal"], p.inputs[sock])
    p.inputs["Emission Strength"].default_value = 2.0
    cases[mat.name] = {"textures": {"specularTint": "RGB", "coatTint": "RGB", "sheenTint": "RGB",
                                    "emissionColor": "RGB", "baseColor": "RGB", "coatWeight": "R",
                                    "sheenRoughness": "G", "specularIorLevel": "B", "thinFilmThickness": "A",
                                    "normal": 0.5, "coatNormal": 0.75}}
    plane("textured", mat, 4.5)

    # 5. Add Shader(Emission, Principled v2) and Mix Shader(Transparent, Principled v2).
    mat, nt, p = new_material("add_mix")
    out = nt.nodes["Material Output"]
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Color"].default_value = (0.2, 0.4, 1.0, 1.0)
    em.inputs["Strength"].default_value = 5.0
    add = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(em.outputs[0], add.inputs[0])
    nt.links.new(p.outputs[0], add.inputs[1])
    tr = nt.nodes.new("ShaderNodeBsdfTransparent")
    mix = nt.nodes.new("ShaderNodeMixShader")
    mix.inputs[0].default_value = 0.75
    nt.links.new(tr.outputs[0], mix.inputs[1])
    nt.links.new(add.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], out.inputs["Surface"])
    cases[mat.name] = {"expect": {"emissionColor": [0.2, 0.4, 1.0, 1.0], "emissionStrength": 5.0, "alpha": 0.75},
                       "no_exporter": True}  # Blender's exporter reads no Add/Mix Shader emission
    plane("add_mix", mat, 6.0)

    # 7. Metallic BSDF (F82) and Sheen BSDF (Microfiber): models metallic and
    # sheen with the node's values (clamped as Cycles clamps them), F82 and
    # Physical Conductor, the Metallic's Beckmann and the Sheen's Ashikhmin
    # too.
    for name, kind, socks, props, want in (
            ("metallic_f82", "ShaderNodeBsdfMetallic",
             {"Base Color": (1.2, 0.5, 0.25, 1.0), "Edge Tint": (0.9, 0.8, 0.7, 1.0), "Roughness": 0.25,
              "Anisotropy": 0.4, "Rotation": 1.25},
             {"fresnel_type": "F82", "distribution": "GGX"},
             ("metallic", {"baseColor": [1.0, 0.5, 0.25, 1.0], "edgeTint": [0.9, 0.8, 0.7, 1.0], "roughness": 0.25,
                           "anisotropy": 0.4, "rotation": 0.25, "distribution": "GGX", "fresnelType": "F82"})),
            ("sheen_microfiber", "ShaderNodeBsdfSheen", {"Color": (0.3, 0.6, 0.9, 1.0), "Roughness": 0.7},
             {"distribution": "MICROFIBER"},
             ("sheen", {"color": [0.3, 0.6, 0.9, 1.0], "roughness": 0.7, "distribution": "MICROFIBER"})),
            ("metallic_conductor", "ShaderNodeBsdfMetallic",
             {"IOR": (0.2, 0.9, 1.1), "Extinction": (3.9, 2.4, -1.0), "Roughness": 0.6},
             {"fresnel_type": "PHYSICAL_CONDUCTOR", "distribution": "MULTI_GGX"},
             ("metallic", {"ior": [0.2, 0.9, 1.1], "extinction": [3.9, 2.4, 0.0], "roughness": 0.6,
                           "anisotropy": 0.0, "rotation": 0.0, "distribution": "MULTI_GGX",
                           "fresnelType": "PHYSICAL_CONDUCTOR"})),
            ("metallic_beckmann", "ShaderNodeBsdfMetallic", {"Roughness": 0.4}, {"distribution": "BECKMANN"},
             ("metallic", {"baseColor": [0.617, 0.577, 0.540, 1.0], "edgeTint": [0.695, 0.726, 0.770, 1.0],
                           "roughness": 0.4, "anisotropy": 0.0, "rotation": 0.0, "distribution": "BECKMANN",
                           "fresnelType": "F82"})),
            ("sheen_ashikhmin", "ShaderNodeBsdfSheen", {"Color": (0.5, 0.2, 0.2, 1.0), "Roughness": 0.6},
             {"distribution": "ASHIKHMIN"},
             ("sheen", {"color": [0.5, 0.2, 0.2, 1.0], "roughness": 0.6, "distribution": "ASHIKHMIN"})),
            # 6. The Glossy (4.x: anisotropic, idname ShaderNodeBsdfAnisotropic),
            # Glass and Refraction BSDFs: models glossy, glass and refraction
            # with the node's values, Rotation turned into 0..1, Beckmann (the
            # Refraction BSDF's default) kept; Ashikhmin-Shirley written as
            # GGX with a warning.
            ("glossy_aniso", "ShaderNodeBsdfAnisotropic",
             {"Color": (0.5, 0.6, 0.7, 1.0), "Roughness": 0.3, "Anisotropy": -0.4, "Rotation": 1.3},
             {"distribution": "MULTI_GGX"},
             ("glossy", {"color": [0.5, 0.6, 0.7, 1.0], "roughness": 0.3, "anisotropy": -0.4, "rotation": 0.3,
                         "distribution": "MULTI_GGX"})),
            ("glass_ggx", "ShaderNodeBsdfGlass", {"Color": (0.9, 0.8, 0.7, 1.0), "Roughness": 0.2, "IOR": 1.33},
             {"distribution": "GGX"},
             ("glass", {"color": [0.9, 0.8, 0.7, 1.0], "roughness": 0.2, "ior": 1.33, "distribution": "GGX"})),
            ("refraction_beckmann", "ShaderNodeBsdfRefraction", {"IOR": 1.6}, {},
             ("refraction", {"color": [1.0, 1.0, 1.0, 1.0], "roughness": 0.0, "ior": 1.6,
                             "distribution": "BECKMANN"})),
            ("glossy_ashikhmin", "ShaderNodeBsdfAnisotropic", {}, {"distribution": "ASHIKHMIN_SHIRLEY"},
             ("glossy", None))):
        mat = bpy.data.materials.new(name)
        mat.use_nodes = True
        nt = mat.node_tree
        nt.nodes.remove(nt.nodes["Principled BSDF"])
        g = nt.nodes.new(kind)
        for k, v in props.items():
            setattr(g, k, v)
        for k, v in socks.items():
            g.inputs[k].default_value = v
        nt.links.new(g.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
        cases[mat.name] = {"node": want}
        plane(name, mat, 7.5 + len(cases))
    return cases


def blender_gltf(path):
    """Blender's own glTF export of the scene: {material name: glTF material}."""
    bpy.ops.export_scene.gltf(filepath=path, export_format='GLTF_SEPARATE', export_materials='EXPORT')
    with open(path) as f:
        return {m["name"]: m for m in json.load(f).get("materials", [])}


def plain_part(gm):
    """What the plain-glTF comparison covers."""
    pbr = dict(gm.get("pbrMetallicRoughness", {}))
    for k in list(pbr):
        if k.endswith("Texture"):
            del pbr[k]
    pbr.setdefault("baseColorFactor", [1.0, 1.0, 1.0, 1.0])
    pbr.setdefault("metallicFactor", 1.0)
    pbr.setdefault("roughnessFactor", 1.0)
    exts = {}
    for k, v in gm.get("extensions", {}).items():
        if k.startswith("KHR_materials_") and k not in ("KHR_materials_anisotropy",):
            exts[k] = {kk: vv for kk, vv in v.items() if not kk.endswith("Texture")}
    if exts.get("KHR_materials_ior") == {}:
        del exts["KHR_materials_ior"]  # ior 1.5 either way
    # alphaMode: from the node tree in 4.2+ (BLEND where Alpha < 1 or driven).
    return {"pbr": pbr, "emissive": gm.get("emissiveFactor", [0.0, 0.0, 0.0]), "ext": exts,
            "alphaMode": gm.get("alphaMode", "OPAQUE")}


def check(cases, got, ref, mats):
    failed = 0
    for name, case in sorted(cases.items()):
        why = []
        g = got.get(name)
        if g is None:
            print("FAIL %s: not written" % name)
            failed += 1
            continue
        e = g["extensions"]["PHOTONBRIDGE_blender"]
        node = next((n for n in mats[name].node_tree.nodes if n.type == 'BSDF_PRINCIPLED'), None)
        if case.get("node"):
            model, members = case["node"]
            if e.get("model") != model:
                why.append("model %s, want %s" % (e.get("model"), model))
            elif members is not None and not same(e.get(model), members, 1e-5):
                why.append("%s %s, want %s" % (model, e.get(model), members))
            if (members is None) != bool(e.get("warnings")):
                why.append("warnings %s" % e.get("warnings"))
        elif case.get("other"):
            if e.get("model") not in ("principled", "principled2"):
                why.append("model %s" % e.get("model"))
        else:
            if e.get("model") != "principled2":
                why.append("model %s" % e.get("model"))
            p = e.get("principled2", {})
            for sock, member in materials.PRINCIPLED2_INPUTS:
                if sock not in node.inputs:
                    if member in p:
                        why.append("%s written without a socket" % member)
                    continue
                linked = member in case.get("textures", {})
                want = case.get("expect", {}).get(member)
                if want is None:
                    v = node.inputs[sock].default_value
                    want = [float(x) for x in v] if hasattr(v, "__len__") else float(v)
                if not linked and not same(p.get(member), want):
                    why.append("%s %s, socket %s" % (member, p.get(member), want))
            if "method" in case and p.get("subsurfaceMethod") != case["method"]:
                why.append("subsurfaceMethod %s, want %s" % (p.get("subsurfaceMethod"), case["method"]))
            if "distribution" in case and p.get("distribution") != case["distribution"]:
                why.append("distribution %s" % p.get("distribution"))
            tex = e.get("textures", {})
            for member, what in case.get("textures", {}).items():
                t = tex.get(member)
                if t is None:
                    why.append("textures.%s missing" % member)
                elif isinstance(what, str) and t.get("channel") != what:
                    why.append("textures.%s channel %s, want %s" % (member, t.get("channel"), what))
                elif not isinstance(what, str) and not same(t.get("strength"), what):
                    why.append("textures.%s strength %s, want %s" % (member, t.get("strength"), what))
            if set(tex) - set(case.get("textures", {})):
                why.append("unexpected textures %s" % sorted(set(tex) - set(case.get("textures", {}))))
            if e.get("warnings"):
                why.append("warnings %s" % e["warnings"])
        if not case.get("other") and not case.get("node") and not case.get("no_exporter") \
                and not case.get("textures"):
            a, b = plain_part(g), plain_part(ref.get(name, {}))
            if not same(a, b, 1e-5):
                why.append("plain glTF %s, Blender's exporter %s" % (json.dumps(a), json.dumps(b)))
        print("%s %s%s" % ("FAIL" if why else "ok  ", name, ": " + "; ".join(why) if why else ""))
        failed += bool(why)
    return failed


def main(argv):
    exe, work = argv[0], argv[1]
    os.makedirs(work, exist_ok=True)
    if bpy.app.version < (4, 0, 0):
        print("skip: Blender %s has no Principled v2" % bpy.app.version_string)
        return 77
    cases = build()
    mats = {m.name: m for m in bpy.data.materials}
    out = os.path.join(work, "principled2", "principled2.gltf")
    writer.write_gltf(bpy.context.evaluated_depsgraph_get(), out)
    with open(out) as f:
        got = {m["name"]: m for m in json.load(f)["materials"]}
    ref = blender_gltf(os.path.join(work, "blender_exporter", "scene.gltf"))
    failed = check(cases, got, ref, mats)
    n = len(cases)
    if exe != "-":
        p = subprocess.run([exe, "info", "--json", "-", out], capture_output=True, text=True)
        n += 1
        why = ""
        if p.returncode:
            why = "info exited %d: %s" % (p.returncode, p.stderr.strip())
        else:
            models = {m["name"]: m["model"] for m in json.loads(p.stdout)["materials"]}
            bad = {k: v for k, v in models.items() if k in cases and not cases[k].get("other")
                   and v != cases[k].get("node", ("principled2",))[0]}
            if bad:
                why = "loaded as %s" % bad
        print("%s photonbridge info%s" % ("FAIL" if why else "ok  ", ": " + why if why else ""))
        failed += bool(why)
    print("%d passed, %d failed" % (n - failed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    rc = main(args)
    sys.stdout.flush()
    os._exit(rc)
