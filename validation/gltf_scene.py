#!/usr/bin/env python3
"""A glTF scene written by code, not by Blender, for validating the Cycles
glTF path (tests/validate.cmake: validate_gltf_cycles). Standard library
only.

    python3 validation/gltf_scene.py OUT.glb|OUT.gltf [--variant plain|extras|version21]

A 2 m box open towards the camera (the Cornell set-up, y up), lit by an
emissive panel under the ceiling (KHR_materials_emissive_strength) and a
point light (KHR_lights_punctual, 341.5 cd = 0.5 W/sr), holding:

  floor       checker baseColorTexture (sRGB PNG), metallic 0, roughness 1,
              glTF's default 4 % specular layer; its uvs run over [-0.25,
              1.25] x [0, 2] with wrapS CLAMP_TO_EDGE, wrapT MIRRORED_REPEAT
  walls       red / green / white rough dielectrics (roughness 0.9)
  back wall   a normalTexture (scale 0.8) of bumps over the white wall
  sphere      rough gold metal (metallic 1, roughness 0.35)
  block       rough blue dielectric: KHR_materials_specular (factor 1, colour
              1) and KHR_materials_ior 1.6 (F0 5.3 %), roughness from a
              metallicRoughnessTexture (G: stripes 0.25 / 0.6, B: 0)
  panel       emissive (1, 0.85, 0.7) x strength 6, front side down

Variants: `plain` (the above); `extras`, the same picture said with what
photonbridge's loader does not read: the floor's uvs stored as a unit square
in TEXCOORD_1 (TEXCOORD_0 is garbage) and its texture placed by
KHR_texture_transform (texCoord 1, offset, scale), the blue block's colour
given as COLOR_0 on a white base colour; `version21`: `plain` with
asset.version "2.1" (glTF's rule allows a higher minor version; Blender 3.4's
importer refuses it).
"""
import argparse
import base64
import json
import math
import struct
import sys
import zlib


def png(width, height, rows, channels=3):
    """8-bit PNG, RGB or RGBA, rows top to bottom."""
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xffffffff)
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    ctype = 2 if channels == 3 else 6
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, ctype, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def srgb8(lin):
    s = 12.92 * lin if lin <= 0.0031308 else 1.055 * lin ** (1.0 / 2.4) - 0.055
    return max(0, min(255, int(round(255.0 * s))))


def checker(size=32, checks=4):
    a, b = (srgb8(0.75), srgb8(0.7), srgb8(0.6)), (srgb8(0.15), srgb8(0.2), srgb8(0.3))
    cell = size // checks
    return [[c for x in range(size) for c in (a if (x // cell + y // cell) % 2 == 0 else b)] for y in range(size)]


def bumps(size=32):
    """A tangent-space normal map of smooth bumps: n = normalize(-dh/du, -dh/dv, 1)."""
    rows = []
    for y in range(size):
        row = []
        for x in range(size):
            u, v = 2 * math.pi * (x + 0.5) / size, 2 * math.pi * (y + 0.5) / size
            nx, ny = -0.6 * math.cos(2 * u) * math.sin(v), -0.3 * math.sin(2 * u) * math.cos(v)
            l = math.sqrt(nx * nx + ny * ny + 1)
            row += [int(round(255 * (0.5 + 0.5 * c / l))) for c in (nx, ny, 1.0)]
        rows.append(row)
    return rows


def stripes(size=16):
    """metallicRoughness: G = roughness 0.25 / 0.6 in stripes along u, B = 0 (dielectric), R unused."""
    return [[c for x in range(size) for c in (0, 64 if (x // 4) % 2 == 0 else 153, 0)] for _ in range(size)]


class Doc:
    def __init__(self):
        self.d = {"asset": {"version": "2.0", "generator": "photonbridge validation/gltf_scene.py"},
                  "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [],
                  "accessors": [], "bufferViews": [], "buffers": [], "textures": [], "images": [], "samplers": []}
        self.bin = bytearray()

    def view(self, data, target=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if target:
            v["target"] = target
        self.bin += data
        self.d["bufferViews"].append(v)
        return len(self.d["bufferViews"]) - 1

    def accessor(self, values, kind):
        """values: list of tuples (VEC2/3/4 float) or ints (SCALAR indices)."""
        if kind == "SCALAR":
            data = struct.pack("<%dI" % len(values), *values)
            acc = {"componentType": 5125, "type": "SCALAR", "count": len(values),
                   "bufferView": self.view(data, 34963)}
        else:
            n = len(values[0])
            data = b"".join(struct.pack("<%df" % n, *v) for v in values)
            acc = {"componentType": 5126, "type": kind, "count": len(values), "bufferView": self.view(data, 34962)}
            if kind == "VEC3":
                acc["min"] = [min(v[k] for v in values) for k in range(3)]
                acc["max"] = [max(v[k] for v in values) for k in range(3)]
        self.d["accessors"].append(acc)
        return len(self.d["accessors"]) - 1

    def image(self, data, sampler):
        self.d["images"].append({"bufferView": self.view(data), "mimeType": "image/png"})
        self.d["samplers"].append(sampler)
        self.d["textures"].append({"source": len(self.d["images"]) - 1, "sampler": len(self.d["samplers"]) - 1})
        return len(self.d["textures"]) - 1

    def material(self, m):
        self.d["materials"].append(m)
        return len(self.d["materials"]) - 1

    def mesh(self, name, prims, translation=None):
        """prims: [(positions, normals, uvs, indices, material, extra attributes)]."""
        ps = []
        for pos, nrm, uv, idx, mat, extra in prims:
            attrs = {"POSITION": self.accessor(pos, "VEC3"), "NORMAL": self.accessor(nrm, "VEC3"),
                     "TEXCOORD_0": self.accessor(uv, "VEC2")}
            for k, (vals, kind) in (extra or {}).items():
                attrs[k] = self.accessor(vals, kind)
            ps.append({"attributes": attrs, "indices": self.accessor(idx, "SCALAR"), "material": mat})
        self.d["meshes"].append({"name": name, "primitives": ps})
        node = {"name": name, "mesh": len(self.d["meshes"]) - 1}
        if translation:
            node["translation"] = list(translation)
        self.node(node)

    def node(self, n):
        self.d["nodes"].append(n)
        self.d["scenes"][0]["nodes"].append(len(self.d["nodes"]) - 1)

    def glb(self):
        self.d["buffers"] = [{"byteLength": len(self.bin)}]
        js = json.dumps(self.d, separators=(",", ":")).encode()
        js += b" " * (-len(js) % 4)
        binary = bytes(self.bin) + b"\0" * (-len(self.bin) % 4)
        body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(binary), 0x004E4942) + binary
        return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body

    def gltf(self):
        self.d["buffers"] = [{"byteLength": len(self.bin),
                              "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(self.bin)).decode()}]
        return json.dumps(self.d, indent=1).encode()


def quad(p0, p1, p2, p3, uv=((0, 0), (1, 0), (1, 1), (0, 1))):
    """Counter-clockwise p0..p3 seen from the front; glTF uv (0,0) top left."""
    e1 = [b - a for a, b in zip(p0, p1)]
    e2 = [b - a for a, b in zip(p0, p3)]
    n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
    l = math.sqrt(sum(c * c for c in n))
    n = tuple(c / l for c in n)
    return [p0, p1, p2, p3], [n] * 4, list(uv), [0, 1, 2, 0, 2, 3]


def box(cx, cy, cz, sx, sy, sz, rot_y):
    """A box of size (sx, sy, sz) centred on (cx, cy, cz), turned rot_y radians about y."""
    c, s = math.cos(rot_y), math.sin(rot_y)

    def P(x, y, z):
        x, z = x * sx / 2, z * sz / 2
        return (cx + c * x + s * z, cy + y * sy / 2, cz - s * x + c * z)
    faces = [((-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)), ((1, -1, -1), (-1, -1, -1), (-1, 1, -1), (1, 1, -1)),
             ((1, -1, 1), (1, -1, -1), (1, 1, -1), (1, 1, 1)), ((-1, -1, -1), (-1, -1, 1), (-1, 1, 1), (-1, 1, -1)),
             ((-1, 1, 1), (1, 1, 1), (1, 1, -1), (-1, 1, -1))]
    pos, nrm, uv, idx = [], [], [], []
    for f in faces:
        p, n, t, i = quad(*[P(*v) for v in f])
        idx += [k + len(pos) for k in i]
        pos += p
        nrm += n
        uv += t
    return pos, nrm, uv, idx


def sphere(cx, cy, cz, r, seg=32, rings=16):
    pos, nrm, uv, idx = [], [], [], []
    for j in range(rings + 1):
        th = math.pi * j / rings
        for i in range(seg + 1):
            ph = 2 * math.pi * i / seg
            n = (math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph))
            pos.append((cx + r * n[0], cy + r * n[1], cz + r * n[2]))
            nrm.append(n)
            uv.append((i / seg, j / rings))
    for j in range(rings):
        for i in range(seg):
            a, b = j * (seg + 1) + i, (j + 1) * (seg + 1) + i
            idx += [a, b, a + 1, a + 1, b, b + 1]
    return pos, nrm, uv, idx


def build(variant):
    D = Doc()
    d = D.d
    d["extensionsUsed"] = ["KHR_materials_emissive_strength", "KHR_materials_specular", "KHR_materials_ior",
                           "KHR_lights_punctual"]
    if variant == "version21":
        d["asset"]["version"] = "2.1"
    floor_tex = D.image(png(32, 32, checker()), {"magFilter": 9729, "minFilter": 9729, "wrapS": 33071,
                                                 "wrapT": 33648})
    bump_tex = D.image(png(32, 32, bumps()), {"magFilter": 9729, "minFilter": 9729})
    mr_tex = D.image(png(16, 16, stripes()), {"magFilter": 9728, "minFilter": 9728})
    floor_info = {"index": floor_tex}
    if variant == "extras":
        # uv = offset + scale x uv1 with uv1 the unit square gives the plain
        # variant's uvs (-0.25..1.25, 0..2); texCoord 1.
        floor_info = {"index": floor_tex, "extensions": {"KHR_texture_transform": {
            "offset": [-0.25, 0.0], "scale": [1.5, 2.0], "texCoord": 1}}}
        d["extensionsUsed"].append("KHR_texture_transform")
    floor = D.material({"name": "CheckerFloor", "pbrMetallicRoughness": {
        "baseColorTexture": floor_info, "metallicFactor": 0.0, "roughnessFactor": 1.0}})
    rough = lambda name, rgb: D.material({"name": name, "pbrMetallicRoughness": {
        "baseColorFactor": list(rgb) + [1.0], "metallicFactor": 0.0, "roughnessFactor": 0.9}})
    white, red, green = rough("White", (0.75, 0.75, 0.72)), rough("Red", (0.6, 0.08, 0.06)), \
        rough("Green", (0.1, 0.45, 0.1))
    back = D.material({"name": "BumpyWhite", "pbrMetallicRoughness": {
        "baseColorFactor": [0.75, 0.75, 0.72, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.9},
        "normalTexture": {"index": bump_tex, "scale": 0.8}})
    gold = D.material({"name": "RoughGold", "pbrMetallicRoughness": {
        "baseColorFactor": [1.0, 0.766, 0.336, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.35}})
    blue = (0.1, 0.3, 0.8)
    block = D.material({"name": "RoughBlue", "pbrMetallicRoughness": {
        "baseColorFactor": ([1.0, 1.0, 1.0] if variant == "extras" else list(blue)) + [1.0],
        "metallicFactor": 1.0, "roughnessFactor": 1.0, "metallicRoughnessTexture": {"index": mr_tex}},
        "extensions": {"KHR_materials_specular": {"specularFactor": 1.0, "specularColorFactor": [1.0, 1.0, 1.0]},
                       "KHR_materials_ior": {"ior": 1.6}}})
    panel = D.material({"name": "Panel", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1],
                                                                  "metallicFactor": 0.0},
                        "emissiveFactor": [1.0, 0.85, 0.7],
                        "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 6.0}}})

    # The box: x in [-1, 1], y (up) in [0, 2], z in [-1, 1], open at z = +1.
    fp, fn, fu, fi = quad((-1, 0, 1), (1, 0, 1), (1, 0, -1), (-1, 0, -1), ((-0.25, 2), (1.25, 2), (1.25, 0),
                                                                            (-0.25, 0)))
    extra = None
    if variant == "extras":
        extra = {"TEXCOORD_1": ([(0, 1), (1, 1), (1, 0), (0, 0)], "VEC2")}
        fu = [(7.0, -3.0)] * 4  # not what the texture uses
    D.mesh("Floor", [(fp, fn, fu, fi, floor, extra)])
    D.mesh("Ceiling", [quad((-1, 2, -1), (1, 2, -1), (1, 2, 1), (-1, 2, 1)) + (white, None)])
    D.mesh("Back", [quad((-1, 0, -1), (1, 0, -1), (1, 2, -1), (-1, 2, -1)) + (back, None)])
    D.mesh("Left", [quad((-1, 0, 1), (-1, 0, -1), (-1, 2, -1), (-1, 2, 1)) + (red, None)])
    D.mesh("Right", [quad((1, 0, -1), (1, 0, 1), (1, 2, 1), (1, 2, -1)) + (green, None)])
    D.mesh("Panel", [quad((-0.3, 1.98, -0.3), (0.3, 1.98, -0.3), (0.3, 1.98, 0.3), (-0.3, 1.98, 0.3)) +
                     (panel, None)])
    D.mesh("Sphere", [sphere(-0.4, 0.4, -0.2, 0.4) + (gold, None)])
    bp, bn, bu, bi = box(0.45, 0.35, 0.25, 0.55, 0.7, 0.55, 0.3)
    extra = {"COLOR_0": ([blue + (1.0,)] * len(bp), "VEC4")} if variant == "extras" else None
    D.mesh("Block", [(bp, bn, bu, bi, block, extra)])
    d["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 341.5,
                                                           "color": [1.0, 1.0, 1.0]}]}}
    D.node({"name": "Light", "translation": [0.3, 1.6, 0.2], "extensions": {"KHR_lights_punctual": {"light": 0}}})
    d["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.75, "aspectRatio": 1.0, "znear": 0.05}}]
    D.node({"name": "Camera", "camera": 0, "translation": [0.0, 1.0, 3.7]})
    return D


def main(argv):
    ap = argparse.ArgumentParser(prog="gltf_scene.py", description=__doc__.split("\n\n")[0])
    ap.add_argument("out", help="OUT.glb or OUT.gltf (buffers and images embedded)")
    ap.add_argument("--variant", choices=["plain", "extras", "version21"], default="plain")
    a = ap.parse_args(argv)
    D = build(a.variant)
    data = D.glb() if a.out.lower().endswith(".glb") else D.gltf()
    with open(a.out, "wb") as f:
        f.write(data)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
