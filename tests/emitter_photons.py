"""Photons from emissive triangles (render/photon/photon_trace.c emitter slot,
photon_trace.comp PB_GPU_EMITTER_LIGHT): cornell_box with its point light
replaced by an emissive ceiling quad (0.5 x 0.5 m, strength 40, single-sided,
facing down; a second run double-sided and textured: the same quad's emission
from a 2 x 2 texture of mean 1 x 40 through emissiveTexture) renders, on the
GPU, the indirect light the reference path tracer finds: before, such a scene
had no photon stage and lost 42 % of its light (mean R 0.238 against 0.414).

  emitter_photons.py EXE EXR_PROBE ROOT WORKDIR"""
import base64
import json
import os
import shutil
import struct
import subprocess
import sys
import zlib

EXE, PROBE, ROOT, WORK = sys.argv[1:5]
fails = 0


def check(cond, what):
    global fails
    print(("ok   " if cond else "FAIL ") + what)
    fails += 0 if cond else 1


def png_rgb(rows):
    h, w = len(rows), len(rows[0])
    raw = b"".join(b"\0" + bytes(v for px in row for v in px) for row in rows)

    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def scene(name, double_sided=False, textured=False):
    src = os.path.join(ROOT, "samples", "cornell_box")
    j = json.load(open(os.path.join(src, "cornell_box.gltf")))
    for b in j["buffers"]:
        if not b["uri"].startswith("data:"):
            shutil.copy(os.path.join(src, b["uri"]), WORK)
    for n in j["nodes"]:
        n.get("extensions", {}).pop("KHR_lights_punctual", None)
    pos = [(-0.25, 1.74, -0.25), (0.25, 1.74, -0.25), (0.25, 1.74, 0.25), (-0.25, 1.74, 0.25)]
    uv = [(0, 0), (1, 0), (1, 1), (0, 1)]
    data = b"".join(struct.pack("<3f", *p) for p in pos) + b"".join(struct.pack("<2f", *t) for t in uv) + \
        struct.pack("<6H", 0, 2, 1, 0, 3, 2)
    j["buffers"].append({"byteLength": len(data),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()})
    bi, bv, a = len(j["buffers"]) - 1, len(j["bufferViews"]), len(j["accessors"])
    j["bufferViews"] += [{"buffer": bi, "byteOffset": 0, "byteLength": 48},
                         {"buffer": bi, "byteOffset": 48, "byteLength": 32},
                         {"buffer": bi, "byteOffset": 80, "byteLength": 12}]
    j["accessors"] += [{"bufferView": bv, "componentType": 5126, "count": 4, "type": "VEC3",
                        "min": [-0.25, 1.74, -0.25], "max": [0.25, 1.74, 0.25]},
                       {"bufferView": bv + 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                       {"bufferView": bv + 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]
    m = {"name": "Lamp", "emissiveFactor": [1, 1, 1], "doubleSided": double_sided,
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 40.0}},
         "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}}
    if textured:
        # sRGB texels whose linear mean is 1 per channel: 255 and 0 in a
        # checker would be mean 0.5, so strength 80 x (1, 0) averages 40.
        open(os.path.join(WORK, "lamp.png"), "wb").write(png_rgb([[(255, 255, 255), (0, 0, 0)],
                                                                   [(0, 0, 0), (255, 255, 255)]]))
        j.setdefault("images", []).append({"uri": "lamp.png"})
        j.setdefault("samplers", []).append({"magFilter": 9728, "minFilter": 9728})
        j.setdefault("textures", []).append({"source": len(j["images"]) - 1, "sampler": len(j["samplers"]) - 1})
        m["emissiveTexture"] = {"index": len(j["textures"]) - 1}
        m["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = 80.0
    j["materials"].append(m)
    if "KHR_materials_emissive_strength" not in j.setdefault("extensionsUsed", []):
        j["extensionsUsed"].append("KHR_materials_emissive_strength")
    attrs = {"POSITION": a, "TEXCOORD_0": a + 1}
    j["meshes"].append({"primitives": [{"attributes": attrs, "indices": a + 2, "material": len(j["materials"]) - 1}]})
    j["nodes"].append({"mesh": len(j["meshes"]) - 1, "name": "Lamp"})
    j["scenes"][j.get("scene", 0)]["nodes"].append(len(j["nodes"]) - 1)
    path = os.path.join(WORK, name + ".gltf")
    json.dump(j, open(path, "w"))
    return path


def means(exr, layer):
    """Mean R, G, B of the main image or a layer (tests/exr_probe)."""
    p = subprocess.run([PROBE, exr], capture_output=True, text=True)
    if p.returncode != 0:
        return None
    ch = json.loads(p.stdout)["channels"]
    names = [(layer + "." if layer else "") + c for c in "RGB"]
    return [sum(ch[n]) / len(ch[n]) for n in names] if all(n in ch for n in names) else None


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
for name, two, tex in (("emitter", False, False), ("emitter_two_sided_textured", True, True)):
    g = scene(name, two, tex)
    gpu, ref = os.path.join(WORK, name + "_gpu.exr"), os.path.join(WORK, name + "_ref.exr")
    info = subprocess.run([EXE, "info", g], capture_output=True, text=True)
    check("photon stages on" in info.stdout, "%s: photon stages on (info's pipeline line)" % name)
    p1 = subprocess.run([EXE, "render", g, "-o", gpu, "--width", "48", "--spp", "8", "--photons", "131072",
                         "--iterations", "2", "--seed", "3", "-q"], capture_output=True, text=True)
    p2 = subprocess.run([EXE, "reference", g, "-o", ref, "--width", "48", "--spp", "512", "--seed", "3", "-q"],
                        capture_output=True, text=True)
    check(p1.returncode == 0 and p2.returncode == 0, "%s: render and reference ran (%s %s)"
          % (name, p1.stderr.strip()[-200:], p2.stderr.strip()[-200:]))
    for layer, tol in (("", 0.04), ("indirect", 0.08)):
        mt, mr = (means(gpu, layer), means(ref, layer)) if p1.returncode == 0 and p2.returncode == 0 else (None, None)
        ok = mt is not None and mr is not None and all(r > 0 and abs(t / r - 1) <= tol for t, r in zip(mt, mr))
        check(ok, "%s %s: GPU mean RGB %s against the reference's %s (within %d %%)"
              % (name, layer or "beauty", ["%.4f" % x for x in mt or []], ["%.4f" % x for x in mr or []], 100 * tol))
print("%d failed" % fails)
sys.exit(1 if fails else 0)
