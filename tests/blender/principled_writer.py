"""The render engine's writer against the Principled tests' hand-made extension.

    blender -b --factory-startup --python-exit-code 1 -P tests/blender/principled_writer.py -- PHOTONBRIDGE WORKDIR

tests/data/principled's scenes carry a PHOTONBRIDGE_blender material
extension written by make_principled_tests.py's small post-pass from the
sockets; their committed Cycles renders are what principled_lobes compares
both renderers with. This builds every one of those scenes again in Blender,
writes it with the render engine's writer (photonbridge/writer.py, as F12
and export_photonbridge.py do) and checks that each material's extension
says what the committed one says (model, distribution, every input the
loader reads, to float precision), that the writer added no texture link or
warning (the textures are the committed ones: a normal map where the
scene has one), and that photonbridge loads the writer's file with the same
Blender model: so the Cycles agreement measured on the committed scenes holds
for a .blend rendered through the writer. Prints "N passed, M failed"."""
import importlib.util
import json
import os
import subprocess
import sys

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "exporters", "blender"))
from photonbridge import writer  # noqa: E402


def load(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def same(a, b):
    """Equal JSON values, numbers to float precision."""
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return abs(a - b) <= 1e-6 * max(1.0, abs(a), abs(b))
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    return a == b


def main(argv):
    exe, work = argv[0], argv[1]
    os.makedirs(work, exist_ok=True)
    mpt = load("pb_make_principled_tests", os.path.join(ROOT, "exporters", "blender", "make_principled_tests.py"))
    data = os.path.join(ROOT, "tests", "data", "principled")
    with open(os.path.join(data, "cycles.json")) as f:
        names = sorted(json.load(f))
    failed = 0
    for name in names:
        os.makedirs(os.path.join(work, name), exist_ok=True)
        mpt.build(name, mpt.CASES[name], os.path.join(work, name))
        out = os.path.join(work, name, name + ".gltf")
        writer.write_gltf(bpy.context.evaluated_depsgraph_get(), out)
        with open(out) as f:
            got = {m["name"]: m["extensions"]["PHOTONBRIDGE_blender"] for m in json.load(f)["materials"]}
        with open(os.path.join(data, name, name + ".gltf")) as f:
            want = {m["name"]: m["extensions"]["PHOTONBRIDGE_blender"] for m in json.load(f)["materials"]}
        why = []
        for mat, w in sorted(want.items()):
            g = got.get(mat)
            if g is None:
                why.append("%s: not written" % mat)
                continue
            model = w["model"]
            if g.get("model") != model or not same(g.get(model), w.get(model)):
                why.append("%s: %s %s, committed %s %s" % (mat, g.get("model"), json.dumps(g.get(g.get("model"))),
                                                          model, json.dumps(w.get(model))))
            if not same(g.get("mix"), w.get("mix")):
                why.append("%s: the writer wrote mix %s, committed %s" % (mat, json.dumps(g.get("mix")),
                                                                        json.dumps(w.get("mix"))))
            if g.get("textures") != w.get("textures"):
                why.append("%s: the writer wrote textures %s, committed %s" % (
                    mat, json.dumps(g.get("textures")), json.dumps(w.get("textures"))))
            if "warnings" in g:
                why.append("%s: the writer added warnings %s" % (mat, json.dumps(g["warnings"])))
        p = subprocess.run([exe, "info", "--json", "-", out], capture_output=True, text=True)
        if p.returncode:
            why.append("info exited %d: %s" % (p.returncode, p.stderr.strip()))
        else:
            models = {m["name"]: m["model"] for m in json.loads(p.stdout)["materials"]}
            for mat, w in want.items():
                if models.get(mat) != w["model"]:
                    why.append("%s: loaded as %s" % (mat, models.get(mat)))
        print("%s %s%s" % ("FAIL" if why else "ok  ", name, ": " + "; ".join(why) if why else ""))
        failed += bool(why)
    print("%d passed, %d failed" % (len(names) - failed, failed))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return 1 if failed else 0


if __name__ == "__main__":
    rc = main(sys.argv[sys.argv.index("--") + 1:])
    sys.stdout.flush()
    os._exit(rc)
