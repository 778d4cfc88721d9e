#!/usr/bin/env python3
"""--frame N of the single-image commands poses skins and morph targets
(tests/data/deform, Blender's skinned cylinder and shape-key cube, and the
same scene baked by Blender at frame 24):

  export-pov --frame 24: every vertex_vectors entry within 1e-5 m of the
      baked scene's export, and the file says it is posed; without --frame,
      the export notes that it is the file's own pose;
  reference --frame 24: the picture against the baked scene's above 30 dB
      (normals follow glTF there and Blender's recomputation in the bake:
      test_deform_blender), while the unposed picture is below 20 dB.

usage: pose_check.py PHOTONBRIDGE ROOT WORKDIR"""
import json
import os
import re
import shutil
import subprocess
import sys

EXE, ROOT, WORK = sys.argv[1:4]
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
D = os.path.join(ROOT, "tests", "data", "deform")
ANIM, BAKED = os.path.join(D, "deform.gltf"), os.path.join(D, "deform_baked_f24.gltf")
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def run(args):
    p = subprocess.run([EXE] + args, capture_output=True, text=True)
    if p.returncode:
        print(" ".join(args), p.stdout[-2000:], p.stderr[-2000:])
    return p


def vertices(path):
    text = open(path).read()
    blocks = re.findall(r"vertex_vectors \{ \d+,(.*?)\}", text, re.S)
    return [tuple(map(float, v)) for b in blocks for v in re.findall(r"<([^,>]+),([^,>]+),([^,>]+)>", b)], text


pov = {}
for name, args in (("posed", [ANIM, "--frame", "24"]), ("baked", [BAKED]), ("rest", [ANIM])):
    out = os.path.join(WORK, name + ".pov")
    p = run(["export-pov"] + args + ["-o", out, "--width", "32"])
    check(p.returncode == 0, "export-pov %s (exit %d)" % (name, p.returncode))
    pov[name] = vertices(out) if p.returncode == 0 else ([], "")
if all(v[0] for v in pov.values()):
    a, b = pov["posed"][0], pov["baked"][0]
    d = max(max(abs(x - y) for x, y in zip(u, v)) for u, v in zip(a, b)) if len(a) == len(b) else float("inf")
    check(len(a) == len(b) and d <= 1e-5, "export-pov --frame 24: %d vertices, max difference to Blender's bake %.2g m"
          % (len(a), d))
    check("Posed at t = 1 s" in pov["posed"][1], "export-pov --frame 24 says it is posed")
    check("exported in the file's own pose" in pov["rest"][1], "export-pov without --frame notes the file's pose")

exr = {}
for name, args in (("posed", [ANIM, "--frame", "24"]), ("baked", [BAKED]), ("rest", [ANIM])):
    out = os.path.join(WORK, name + ".exr")
    p = run(["reference"] + args + ["-o", out, "--width", "48", "--spp", "4", "--max-bounces", "1", "-q"])
    check(p.returncode == 0, "reference %s (exit %d)" % (name, p.returncode))
    exr[name] = out if p.returncode == 0 else None
if all(exr.values()):
    psnr = {}
    for name in ("posed", "rest"):
        p = run(["compare", exr[name], exr["baked"], "--json", "-"])
        psnr[name] = json.loads(p.stdout)["psnr_db"] if p.returncode == 0 else 0
    check(psnr["posed"] > 30, "reference --frame 24 against the bake: %.1f dB (> 30)" % psnr["posed"])
    check(psnr["rest"] < 20, "reference without --frame against the bake: %.1f dB (< 20: it is another pose)" % psnr["rest"])
print("%d passed, %d failed" % (9 - len(failures), len(failures)))
sys.exit(1 if failures else 0)
