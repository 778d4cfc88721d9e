#!/usr/bin/env python3
"""Writes normal_map.gltf and bumps.png next to this script: a small test
scene for normal maps. A 4 x 4 m Lambert floor (albedo 0.8)
with a bumpy tangent-space normal map (bumps.png, 64 x 64, linear RGB, glTF
convention: +X right, +Y up in the image, uv = (x, z) / 4 + 0.5 so the file
needs no TANGENT: the loader generates T = +X), a white wall at x = 1.5
(no normal map), a point light and a camera looking down at the floor.
Deterministic; run it again to regenerate (python3 make_normal_map.py)."""
import base64, json, math, os, struct, zlib

here = os.path.dirname(os.path.abspath(__file__))

def png(path, w, h, rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    def chunk(t, d):
        c = struct.pack(">I", len(d)) + t + d
        return c + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    data = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    data += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    open(path, "wb").write(data)

N = 64
rows = []
for y in range(N):
    row = []
    for x in range(N):
        # Height field h = 0.05 sin(2 pi 4 x/N) sin(2 pi 4 y/N); the image's
        # +Y is up, so the slope along the image's up axis is -dh/dy.
        k = 2 * math.pi * 4 / N
        gx = 0.8 * math.cos(k * x) * math.sin(k * y)
        gy = -0.8 * math.sin(k * x) * math.cos(k * y)
        n = (-gx, -gy, 1.0)
        l = math.sqrt(sum(c * c for c in n))
        row += [int(round((c / l + 1) * 0.5 * 255)) for c in n]
    rows.append(row)
png(os.path.join(here, "bumps.png"), N, N, rows)

def quad(p, n, uv):
    return p, [n] * 4, uv, [0, 2, 1, 0, 3, 2]

floor = quad([(-2, 0, -2), (1.5, 0, -2), (1.5, 0, 2), (-2, 0, 2)], (0, 1, 0),
             [(x / 4 + 0.5, z / 4 + 0.5) for x, _, z in [(-2, 0, -2), (1.5, 0, -2), (1.5, 0, 2), (-2, 0, 2)]])
wall = quad([(1.5, 0, 2), (1.5, 2, 2), (1.5, 2, -2), (1.5, 0, -2)], (-1, 0, 0), [(0, 0), (1, 0), (1, 1), (0, 1)])

buf = b""
views, accessors, prims = [], [], []
def add(data, fmt, count, typ, ctype, minmax=None):
    global buf
    off = len(buf)
    b = b"".join(struct.pack("<" + fmt, *v) if isinstance(v, tuple) else struct.pack("<" + fmt, v) for v in data)
    buf += b
    while len(buf) % 4:
        buf += b"\x00"
    views.append({"buffer": 0, "byteOffset": off, "byteLength": len(b)})
    a = {"bufferView": len(views) - 1, "componentType": ctype, "count": count, "type": typ}
    if minmax:
        a["min"], a["max"] = minmax
    accessors.append(a)
    return len(accessors) - 1

for mat, (p, n, uv, idx) in enumerate([floor, wall]):
    mn = [min(v[i] for v in p) for i in range(3)]
    mx = [max(v[i] for v in p) for i in range(3)]
    ap = add(p, "fff", 4, "VEC3", 5126, (mn, mx))
    an = add(n, "fff", 4, "VEC3", 5126)
    au = add(uv, "ff", 4, "VEC2", 5126)
    ai = add(idx, "H", 6, "SCALAR", 5123)
    prims.append({"attributes": {"POSITION": ap, "NORMAL": an, "TEXCOORD_0": au}, "indices": ai, "material": mat})

doc = {
    "asset": {"version": "2.0", "generator": "tests/data/normal_map/make_normal_map.py"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 1366.0}]}},
    "buffers": [{"uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode(), "byteLength": len(buf)}],
    "bufferViews": views,
    "accessors": accessors,
    "images": [{"uri": "bumps.png"}],
    "samplers": [{"magFilter": 9729, "minFilter": 9729}],
    "textures": [{"source": 0, "sampler": 0}],
    "materials": [
        {"name": "bumpy_floor", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 1},
         "normalTexture": {"index": 0, "scale": 1.0}},
        {"name": "wall", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 1}},
    ],
    "meshes": [{"name": "room", "primitives": prims}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "aspectRatio": 1.333333, "znear": 0.05}}],
    "nodes": [
        {"name": "room", "mesh": 0},
        {"name": "light", "translation": [0.5, 1.2, 0.3], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        # Camera at (0, 3, 0) looking straight down (-Y), image up = -Z.
        {"name": "camera", "translation": [0, 3, 0], "rotation": [-0.70710678, 0, 0, 0.70710678], "camera": 0},
    ],
    "scenes": [{"nodes": [0, 1, 2]}],
    "scene": 0,
}
open(os.path.join(here, "normal_map.gltf"), "w").write(json.dumps(doc, indent=1) + "\n")
