"""Depth of field and panoramic cameras from the command line, against
analytic answers, on the GPU pipeline (render) and the reference
(reference); the scenes are written here (glTF with the PHOTONBRIDGE_blender
camera extension, exporters/blender/PHOTONBRIDGE_blender.md).

dof: a 50 mm lens at f/0.5 (aperture radius 0.05 m, Cycles' lens / (2
  f-stop)) focused at 1 m, 128 x 48 pixels on a 36 mm sensor. Lower half: the
  edge of an emissive plane 6 m away, which a thin lens blurs into a disc of
  radius R |d - f| / (d f) = 0.0417 (screen units at distance 1), 7.4 pixels:
  the measured edge profile is that disc's coverage of the edge (box-filtered
  over the pixel) within 0.05 at every column and 0.015 on average; a pinhole
  (the old behaviour: a sharp edge) is 0.5 off at the edge, 0.08 on average
  over the 40 columns. Upper half: an
  emissive plane's edge at the focus distance stays sharp (one pixel).
equirect: an equirectangular camera (all longitudes and latitudes) in a grey
  world (0.5) sees it everywhere, and a small emissive square 5 m to the
  camera's right at u = 0.75, v = 0.5 of the image (Cycles'
  equirectangular_range_to_direction): its light's centroid within 1 pixel.
fisheye: an equidistant fisheye of 180 degrees in the same world: the world in
  the inscribed circle, black outside it (pi / 4 of a square image within 2
  %; alpha there is the film's, 1 on an opaque film as in Cycles, whose
  camera writes nothing for those pixels).
usage: camera_check.py PHOTONBRIDGE EXR_PROBE WORKDIR"""
import base64
import json
import math
import os
import struct
import subprocess
import sys

EXE, PROBE, WORK = sys.argv[1:4]
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def exr(path):
    p = subprocess.run([PROBE, path], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(p.stderr)
    return json.loads(p.stdout)


def scene(path, quads, cam_ext, world=None):
    """quads: (corners [4][3], emissive rgb); the camera at the origin looking
    down -Z."""
    pos, idx = [], []
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [],
           "materials": [], "accessors": [], "bufferViews": [], "buffers": [],
           "extensionsUsed": ["PHOTONBRIDGE_blender"],
           "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.01, "zfar": 1000,
                                                               "aspectRatio": 1.0},
                        "extensions": {"PHOTONBRIDGE_blender": cam_ext}}]}
    if world:
        doc["extensions"] = {"PHOTONBRIDGE_blender": {"version": 1, "world": {"color": world, "strength": 1.0}}}
    blob = b""
    for q, (corners, rgb) in enumerate(quads):
        vo = len(blob)
        blob += b"".join(struct.pack("<3f", *c) for c in corners)
        io = len(blob)
        blob += struct.pack("<6H", 0, 1, 2, 0, 2, 3)
        blob += b"\0" * (-len(blob) % 4)
        lo = [min(c[k] for c in corners) for k in range(3)]
        hi = [max(c[k] for c in corners) for k in range(3)]
        doc["bufferViews"] += [{"buffer": 0, "byteOffset": vo, "byteLength": 48},
                               {"buffer": 0, "byteOffset": io, "byteLength": 12}]
        doc["accessors"] += [{"bufferView": 2 * q, "componentType": 5126, "count": 4, "type": "VEC3",
                              "min": lo, "max": hi},
                             {"bufferView": 2 * q + 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]
        k = max(rgb)
        mat = {"emissiveFactor": [c / k for c in rgb],
               "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0}}
        if k != 1:
            mat["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": k}}
            if "KHR_materials_emissive_strength" not in doc["extensionsUsed"]:
                doc["extensionsUsed"].append("KHR_materials_emissive_strength")
        doc["materials"].append(mat)
        doc["meshes"].append({"primitives": [{"attributes": {"POSITION": 2 * q}, "indices": 2 * q + 1,
                                              "material": q}]})
        doc["nodes"].append({"mesh": q})
    doc["nodes"].append({"camera": 0})
    doc["scenes"][0]["nodes"] = list(range(len(doc["nodes"])))
    doc["buffers"] = [{"byteLength": len(blob),
                       "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}]
    with open(path, "w") as f:
        json.dump(doc, f)


def render(gltf, out, w, h, which, spp):
    if which == "render":
        args = [EXE, "render", gltf, "-o", out, "--width", str(w), "--height", str(h), "--spp", str(spp),
                "--direct-only", "-q"]
    else:
        args = [EXE, "reference", gltf, "-o", out, "--width", str(w), "--height", str(h), "--spp", str(spp),
                "--threads", "2", "-q"]
    p = subprocess.run(args, capture_output=True, text=True)
    check(p.returncode == 0, "%s %s (%s)" % (which, os.path.basename(gltf), p.stderr.strip()[-300:]))
    return exr(out) if p.returncode == 0 else None


def coverage(s, rho):
    """Share of a disc of radius rho (pixels) centred s pixels right of the
    edge that lies left of it."""
    if s >= rho:
        return 0.0
    if s <= -rho:
        return 1.0
    t = s / rho
    return (math.acos(t) - t * math.sqrt(1 - t * t)) / math.pi


def pixel_profile(col, edge, rho):
    """coverage box-filtered over pixel col (centre col + 0.5)."""
    n = 64
    return sum(coverage(col + (i + 0.5) / n - edge, rho) for i in range(n)) / n


def part_dof(which):
    W, H = 128, 48
    lens, fstop, focus, d = 50.0, 0.5, 1.0, 6.0
    R = lens * 1e-3 / (2 * fstop)
    gltf = os.path.join(WORK, "dof.gltf")
    far = ([(-40, -40, -d), (0, -40, -d), (0, 0, -d), (-40, 0, -d)], (1, 1, 1))
    near = ([(-5, 0, -focus), (0, 0, -focus), (0, 5, -focus), (-5, 5, -focus)], (1, 1, 1))
    scene(gltf, [far, near], {"type": "PERSP", "lens": lens, "sensorWidth": 36.0, "sensorFit": "AUTO",
                              "clipStart": 0.01, "clipEnd": 1000, "aspect": W / H,
                              "apertureFstop": fstop, "focusDistance": focus})
    img = render(gltf, os.path.join(WORK, "dof_%s.exr" % which), W, H, which, 256 if which == "render" else 128)
    if not img:
        return
    dx = 36.0 / lens / W                      # screen units per pixel at distance 1
    rho = R * abs(d - focus) / (d * focus) / dx
    r = img["channels"]["R"]
    rows_far, rows_near = range(H - 8, H), range(0, 8)
    cols = range(W // 2 - 20, W // 2 + 20)
    prof = [sum(r[y * W + x] for y in rows_far) / len(rows_far) for x in cols]
    want = [pixel_profile(x, W / 2, rho) for x in cols]
    pin = [pixel_profile(x, W / 2, 1e-6) for x in cols]
    worst = max(abs(a - b) for a, b in zip(prof, want))
    mean = sum(abs(a - b) for a, b in zip(prof, want)) / len(cols)
    mean_pin = sum(abs(a - b) for a, b in zip(pin, want)) / len(cols)
    check(worst < 0.05 and mean < 0.015,
          "%s dof: the far edge is the thin lens' disc of %.2f px (largest difference %.3f, mean %.4f; a pinhole "
          "%.3f)" % (which, rho, worst, mean, mean_pin))
    check(mean_pin > 0.05, "%s dof: a sharp edge would fail (%.3f)" % (which, mean_pin))
    sharp = [sum(r[y * W + x] for y in rows_near) / len(rows_near) for x in cols]
    soft = sum(1 for v in sharp if 0.05 < v < 0.95)
    check(soft <= 2, "%s dof: the edge at the focus distance stays sharp (%d soft columns)" % (which, soft))


def part_pano(which):
    W, H = 128, 64
    gltf = os.path.join(WORK, "equirect.gltf")
    square = ([(5, 0.4, 0.4), (5, 0.4, -0.4), (5, -0.4, -0.4), (5, -0.4, 0.4)], (8, 8, 8))  # facing -x
    scene(gltf, [square], {"type": "PANO", "panoramaType": "EQUIRECTANGULAR", "clipStart": 0.01,
                           "clipEnd": 1000, "aspect": 2.0}, world=[0.5, 0.5, 0.5])
    img = render(gltf, os.path.join(WORK, "equirect_%s.exr" % which), W, H, which, 16)
    if img:
        r = img["channels"]["R"]
        bright = [(i % W + 0.5, i // W + 0.5, v - 0.5) for i, v in enumerate(r) if v > 1.0]
        s = sum(b[2] for b in bright)
        cx = sum(b[0] * b[2] for b in bright) / s if s else -1
        cy = sum(b[1] * b[2] for b in bright) / s if s else -1
        world = [v for v in r if v <= 1.0]
        wmean = sum(world) / len(world) if world else 0
        check(abs(cx - 0.75 * W) < 1 and abs(cy - 0.5 * H) < 1,
              "%s equirect: the square to the right at (%.2f, %.2f), expected (%g, %g)"
              % (which, cx, cy, 0.75 * W, 0.5 * H))
        check(abs(wmean - 0.5) < 0.01 and min(r) > 0.45, "%s equirect: the world everywhere else (mean %.4f, min %.3f)"
              % (which, wmean, min(r)))
    gltf = os.path.join(WORK, "fisheye.gltf")
    scene(gltf, [square], {"type": "PANO", "panoramaType": "FISHEYE_EQUIDISTANT", "fisheyeFov": math.pi,
                           "clipStart": 0.01, "clipEnd": 1000, "aspect": 1.0}, world=[0.5, 0.5, 0.5])
    img = render(gltf, os.path.join(WORK, "fisheye_%s.exr" % which), 64, 64, which, 16)
    if img:
        r = img["channels"]["R"]
        lit = sum(1 for v in r if v > 0.25) / len(r)
        check(abs(lit / (math.pi / 4) - 1) < 0.02, "%s fisheye: the circle is lit (%.4f of the image, pi/4 = %.4f)"
              % (which, lit, math.pi / 4))
        corners = [r[0], r[63], r[63 * 64], r[64 * 64 - 1]]
        check(max(corners) == 0, "%s fisheye: black outside the circle (%s)" % (which, corners))


def main():
    if subprocess.run([EXE, "info", "--devices"], capture_output=True).returncode != 0:
        print("skip: no Vulkan device")
        return 77
    os.makedirs(WORK, exist_ok=True)
    for which in ("render", "reference"):
        part_dof(which)
        part_pano(which)
    print("%d failed" % len(failures) if failures else "all checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
