#!/usr/bin/env python3
"""A camera whose clip range excludes every surface is said, not rendered
black without a word: cornell_box scaled to millimetres (every node under a
0.001 scale, the camera's znear 0.05 m unchanged, as a Blender scene
modelled in millimetres under the default Clip Start) and with zfar pulled
in front of the room; `render` and `reference` warn, naming the file, the
camera and the clip range; the scene as it is does not warn."""
import json, os, shutil, subprocess, sys, tempfile

exe, root = sys.argv[1], sys.argv[2]
src_dir = os.path.join(root, "samples", "cornell_box")
problems, checks = [], 0


def check(ok, what):
    global checks
    checks += 1
    if not ok:
        problems.append(what)


def variant(d, name, edit):
    g = json.load(open(os.path.join(src_dir, "cornell_box.gltf")))
    edit(g)
    path = os.path.join(d, name + ".gltf")
    json.dump(g, open(path, "w"))
    return path


def millimetres(g):
    sc = g["scenes"][g.get("scene", 0)]
    g["nodes"].append({"name": "mm", "scale": [0.001] * 3, "children": sc["nodes"]})
    sc["nodes"] = [len(g["nodes"]) - 1]


def near_far(g):
    g["cameras"][0]["perspective"]["zfar"] = 0.06  # the room starts metres away


def warnings(args):
    p = subprocess.run([exe] + args, capture_output=True, text=True, timeout=600)
    return p.returncode, [l for l in p.stderr.splitlines() if "sees no surface" in l]


with tempfile.TemporaryDirectory() as d:
    shutil.copy(os.path.join(src_dir, "cornell_box.bin"), d)
    mm = variant(d, "mm", millimetres)
    far = variant(d, "far", near_far)
    same = variant(d, "same", lambda g: None)
    small = ["--width", "16", "--direct-only", "-o", os.path.join(d, "x.exr")]
    rc, w = warnings(["render", mm] + small)
    check(rc == 0 and len(w) == 1 and w[0].startswith("warning: render: ") and mm in w[0] and "'Camera'" in w[0]
          and "nearer than its clip range 0.05 m to 200 m" in w[0], "millimetres, render: %d %r" % (rc, w))
    rc, w = warnings(["reference", mm, "--width", "16", "--spp", "1", "-o", os.path.join(d, "r.exr")])
    check(rc == 0 and len(w) == 1 and w[0].startswith("warning: reference: "), "millimetres, reference: %d %r" % (rc, w))
    rc, w = warnings(["render", far] + small)
    check(rc == 0 and len(w) == 1 and "beyond its clip range 0.05 m to 0.06 m" in w[0], "zfar: %d %r" % (rc, w))
    rc, w = warnings(["render", same] + small)
    check(rc == 0 and not w, "the scene as it is: %d %r" % (rc, w))

for m in problems:
    print("FAIL:", m)
print(f"{checks - len(problems)} passed, {len(problems)} failed")
sys.exit(1 if problems else 0)
