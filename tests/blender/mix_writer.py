"""The render engine's writer on Mix Shaders (Blender 4.x).

    python tests/blender/mix_writer.py PHOTONBRIDGE WORKDIR    (bpy 4.x as a module)

Builds one plane per material whose surface is a Mix Shader and checks what
the add-on's writer (photonbridge/writer.py) makes of it: two BSDFs of
different closure kinds are written as the extension's "mix" (the factor
from a constant, an image, a Fresnel node, a Layer Weight's Fresnel or
Facing; the second shader's own colour attribute), without a warning; a
Add Shader of two such BSDFs is "mix" with facFrom "add"; a
constant Fac of 0 or 1 is the shader that weighs everything, without a
warning; everything photonbridge does not render mixed (two shaders of one
kind, a Fac from a Math node, an emitting Principled BSDF, a Transparent
BSDF around the mix) is the larger or first shader with a warning that says
why. Then photonbridge (PHOTONBRIDGE) loads the file: no warning, the mix
compiled. Prints "N passed, M failed"."""
import json
import os
import subprocess
import sys

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "exporters", "blender"))
from photonbridge import writer  # noqa: E402


def bsdf(nt, kind, **socks):
    n = nt.nodes.new(kind)
    for k, v in socks.items():
        n.inputs[k].default_value = v
    return n


def mixed(name, x, first, second, fac=None, fac_value=0.5):
    """A material whose Material Output takes Mix(first, second); first and
    second are (node type, sockets) or 'principled'; fac a function making
    the Fac's source node (None: the constant fac_value)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    made = []
    for spec in (first, second):
        made.append(nt.nodes["Principled BSDF"] if spec == "principled" else bsdf(nt, spec[0], **spec[1]))
    mix = nt.nodes.new("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = fac_value
    nt.links.new(made[0].outputs[0], mix.inputs[1])
    nt.links.new(made[1].outputs[0], mix.inputs[2])
    if fac is not None:
        fac(nt, mix)
    nt.links.new(mix.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=(x, 0.0, 0.0))
    ob = bpy.context.active_object
    ob.name = name
    ob.data.materials.append(mat)
    return mat, made, mix


def layer(output, blend):
    def make(nt, mix):
        n = nt.nodes.new("ShaderNodeLayerWeight")
        n.inputs["Blend"].default_value = blend
        nt.links.new(n.outputs[output], mix.inputs["Fac"])
    return make


def fresnel(ior):
    def make(nt, mix):
        n = nt.nodes.new("ShaderNodeFresnel")
        n.inputs["IOR"].default_value = ior
        nt.links.new(n.outputs["Fac"], mix.inputs["Fac"])
    return make


def mask(nt, mix):
    img = bpy.data.images.new("mask", 4, 4)
    img.pixels = [0.2, 0.2, 0.2, 1.0] * 8 + [0.8, 0.8, 0.8, 1.0] * 8
    img.colorspace_settings.name = "Non-Color"
    img.pack()
    t = nt.nodes.new("ShaderNodeTexImage")
    t.image = img
    sep = nt.nodes.new("ShaderNodeSeparateColor")
    nt.links.new(t.outputs["Color"], sep.inputs["Color"])
    nt.links.new(sep.outputs["Green"], mix.inputs["Fac"])


def math_fac(nt, mix):
    m = nt.nodes.new("ShaderNodeMath")
    m.operation = 'MULTIPLY'
    nt.links.new(m.outputs[0], mix.inputs["Fac"])


DIFFUSE = ("ShaderNodeBsdfDiffuse", {"Color": (0.7, 0.3, 0.2, 1.0)})
GLOSSY = ("ShaderNodeBsdfGlossy", {"Color": (0.9, 0.9, 0.9, 1.0), "Roughness": 0.2})


def build():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    cases = {}
    mixed("layer_fresnel", 0.0, DIFFUSE, GLOSSY, layer("Fresnel", 0.3))
    cases["layer_fresnel"] = {"model": "diffuse", "mix": {"facFrom": "layerFresnel", "blend": 0.3},
                              "second": "glossy"}
    mixed("layer_facing", 1.5, DIFFUSE, ("ShaderNodeBsdfSheen", {"Roughness": 0.4}), layer("Facing", 0.7))
    cases["layer_facing"] = {"model": "diffuse", "mix": {"facFrom": "layerFacing", "blend": 0.7},
                             "second": "sheen"}
    mixed("fresnel", 3.0, DIFFUSE, GLOSSY, fresnel(1.6))
    cases["fresnel"] = {"model": "diffuse", "mix": {"facFrom": "fresnel", "ior": 1.6}, "second": "glossy"}
    mixed("mask", 4.5, "principled", ("ShaderNodeBsdfMetallic", {"Roughness": 0.3}), mask)
    cases["mask"] = {"model": "principled2", "mix": {"fac": 0.5}, "second": "metallic", "fac_channel": "G"}
    mixed("constant", 6.0, DIFFUSE, ("ShaderNodeBsdfGlass", {"Roughness": 0.1, "IOR": 1.5}), None, 0.7)
    cases["constant"] = {"model": "diffuse", "mix": {"fac": 0.7}, "second": "glass", "plain_second": True}
    mixed("all_second", 7.5, DIFFUSE, GLOSSY, None, 1.0)
    cases["all_second"] = {"model": "glossy"}
    mat, made, _ = mixed("vcol_second", 9.0, DIFFUSE, GLOSSY, layer("Fresnel", 0.5))
    attr = mat.node_tree.nodes.new("ShaderNodeVertexColor")
    mat.node_tree.links.new(attr.outputs["Color"], made[1].inputs["Color"])
    cases["vcol_second"] = {"model": "diffuse", "mix": {"facFrom": "layerFresnel", "blend": 0.5},
                            "second": "glossy", "second_vcol": "color"}
    mat, made, mix = mixed("add", 16.5, DIFFUSE, GLOSSY, None, 0.5)
    nt = mat.node_tree
    add = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(made[0].outputs[0], add.inputs[0])
    nt.links.new(made[1].outputs[0], add.inputs[1])
    nt.links.new(add.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    cases["add"] = {"model": "diffuse", "mix": {"facFrom": "add"}, "second": "glossy"}
    mixed("same_kind", 10.5, DIFFUSE, ("ShaderNodeBsdfDiffuse", {"Roughness": 0.5}), None, 0.3)
    cases["same_kind"] = {"model": "diffuse", "warn": "both its shaders make diffuse closures"}
    mixed("math_fac", 12.0, DIFFUSE, GLOSSY, math_fac)
    cases["math_fac"] = {"model": "diffuse", "warn": "its Fac is driven by a node that is not translated"}
    mat, made, _ = mixed("emitting", 13.5, "principled", GLOSSY, None, 0.4)
    made[0].inputs["Emission Strength"].default_value = 2.0
    cases["emitting"] = {"model": "principled2", "warn": "a mixed Principled BSDF emits or has an Alpha below 1"}
    mat, made, mix = mixed("transparent_around", 15.0, DIFFUSE, GLOSSY, None, 0.4)
    nt = mat.node_tree
    outer = nt.nodes.new("ShaderNodeMixShader")
    outer.inputs["Fac"].default_value = 0.8
    nt.links.new(nt.nodes.new("ShaderNodeBsdfTransparent").outputs[0], outer.inputs[1])
    nt.links.new(mix.outputs[0], outer.inputs[2])
    nt.links.new(outer.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    cases["transparent_around"] = {"model": "diffuse", "warn": "a Transparent or Emission shader is mixed in too"}
    return cases


def check(name, want, gm, ext):
    why = []
    if ext.get("model") != want["model"]:
        why.append("model %s, expected %s" % (ext.get("model"), want["model"]))
    mix = ext.get("mix")
    warnings = ext.get("warnings", [])
    if "mix" in want:
        if mix is None:
            return why + ["no mix written (warnings %s)" % warnings]
        for k, v in want["mix"].items():
            if not (isinstance(v, float) and abs(mix.get(k, -1.0) - v) < 1e-6 or mix.get(k) == v):
                why.append("mix.%s %s, expected %s" % (k, mix.get(k), v))
        if mix["shader"].get("model") != want["second"]:
            why.append("second shader %s, expected %s" % (mix["shader"].get("model"), want["second"]))
        if "fac_channel" in want and mix.get("textures", {}).get("fac", {}).get("channel") != want["fac_channel"]:
            why.append("fac texture %s, expected channel %s" % (mix.get("textures"), want["fac_channel"]))
        if "second_vcol" in want and (mix["shader"].get("vertexColor") != want["second_vcol"]
                                      or "vertexColor" in ext):
            why.append("vertexColor: first %s, second %s" % (ext.get("vertexColor"), mix["shader"].get("vertexColor")))
        if want.get("plain_second") and gm.get("extensions", {}).get("KHR_materials_transmission") is None:
            why.append("the plain glTF is not the larger (second) shader's")
        if warnings:
            why.append("warnings %s" % warnings)
    elif mix is not None:
        why.append("a mix written: %s" % json.dumps(mix)[:200])
    if "warn" in want and not any(want["warn"] in w for w in warnings):
        why.append("no warning '%s' (warnings %s)" % (want["warn"], warnings))
    if "warn" not in want and "mix" not in want and warnings:
        why.append("warnings %s" % warnings)
    return why


def main(argv):
    exe, work = argv[0], argv[1]
    os.makedirs(work, exist_ok=True)
    if bpy.app.version < (4, 0, 0):
        print("skip: Blender %s" % bpy.app.version_string)
        return 77
    cases = build()
    out = os.path.join(work, "mix.gltf")
    writer.write_gltf(bpy.context.evaluated_depsgraph_get(), out)
    with open(out) as f:
        got = {m["name"]: m for m in json.load(f)["materials"]}
    failed = 0
    for name, want in cases.items():
        gm = got.get(name)
        why = ["not written"] if gm is None else check(name, want, gm, gm["extensions"]["PHOTONBRIDGE_blender"])
        print("%s %s%s" % ("FAIL" if why else "ok  ", name, ": " + "; ".join(why) if why else ""))
        failed += bool(why)
    n = len(cases) + 1
    p = subprocess.run([exe, "info", "--json", "-", out], capture_output=True, text=True)
    why = ""
    if p.returncode:
        why = "info exited %d: %s" % (p.returncode, p.stderr.strip())
    else:
        info = json.loads(p.stdout)
        if "mix" not in info["pipeline"]["blender_closures"]:
            why = "closures %s without mix" % info["pipeline"]["blender_closures"]
        loaded = [w for w in info.get("warnings", []) if "PHOTONBRIDGE_blender.mix" in w]
        if loaded:
            why += " loader warnings %s" % loaded
    print("%s photonbridge info%s" % ("FAIL" if why else "ok  ", ": " + why if why else ""))
    failed += bool(why)
    print("%d passed, %d failed" % (n - failed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    rc = main(args)
    sys.stdout.flush()
    os._exit(rc)
