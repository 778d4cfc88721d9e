#!/usr/bin/env python3
"""The PHOTONBRIDGE_blender "mix" member (a Mix Shader of two BSDFs) as the
CLI reads it: the written scene loads without a warning and compiles the mix;
each broken variant is one line naming the file and the member, with exit
code 5 (PB_ERR_SCENE_INVALID); two shaders that can make the same kind of
closure load with a warning and render the first shader alone.

usage: mix_shader_cli.py PHOTONBRIDGE WORKDIR"""
import copy
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "data", "principled2", "mix_diffuse_glossy_layer")
NAME = "mix_diffuse_glossy_layer"


def run(exe, path):
    p = subprocess.run([exe, "info", path], capture_output=True, text=True, timeout=120)
    return p.returncode, p.stdout + p.stderr


def main(argv):
    exe, work = argv[1], argv[2]
    os.makedirs(work, exist_ok=True)
    shutil.copy(os.path.join(SCENE, NAME + ".bin"), work)
    with open(os.path.join(SCENE, NAME + ".gltf")) as f:
        base = json.load(f)
    ext = "materials[0].extensions.PHOTONBRIDGE_blender."

    def variant(tag, edit):
        g = copy.deepcopy(base)
        e = g["materials"][0]["extensions"]["PHOTONBRIDGE_blender"]
        edit(e)
        path = os.path.join(work, tag + ".gltf")
        with open(path, "w") as f:
            json.dump(g, f)
        return path

    failed = 0

    def check(tag, edit, code, text, absent=None):
        nonlocal failed
        rc, out = run(exe, variant(tag, edit))
        ok = rc == code and text in out and (absent is None or absent not in out)
        if code != 0:
            errs = [ln for ln in out.splitlines() if "error:" in ln]
            ok = ok and len(errs) == 1
        print("%s %-18s exit %d: %s" % ("ok  " if ok else "FAIL", tag, rc,
                                        out.strip().splitlines()[-1] if out.strip() else ""))
        failed += not ok

    check("written", lambda e: None, 0, "closures   diffuse reflection mix", absent="warning:")
    check("bad_roughness", lambda e: e["mix"]["shader"]["glossy"].update(roughness=2.0), 5,
          NAME[:0] + "bad_roughness.gltf: " + ext + "mix.shader.glossy.roughness: 2")
    check("bad_fac_from", lambda e: e["mix"].update(facFrom="bump"), 5, ext + "mix.facFrom: 'bump'")
    check("no_blend", lambda e: e["mix"].pop("blend"), 5,
          ext + "mix.blend: missing (required with facFrom 'layerFresnel')")
    check("no_shader", lambda e: e["mix"].pop("shader"), 5, ext + "mix.shader: missing")
    check("nested", lambda e: e["mix"]["shader"].update(mix=copy.deepcopy(e["mix"])), 5,
          ext + "mix.shader.mix: a Mix Shader inside a Mix Shader is not read")
    check("emission", lambda e: e["mix"].update(shader={"model": "emission"}), 5,
          ext + "mix.shader.model: 'emission' cannot be mixed (only BSDFs)")
    check("same_kind", lambda e: e["mix"].update(shader={"model": "diffuse"}), 0,
          "both shaders can make a diffuse closure, which is not rendered mixed; only the first shader is rendered")
    check("bad_fac_texture", lambda e: e["mix"].update(facFrom="value", fac=0.5, textures={"fac": {"index": 7}}), 5,
          ext + "mix.textures.fac")
    print("%d failed" % failed)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
