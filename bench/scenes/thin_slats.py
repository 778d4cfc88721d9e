#!/usr/bin/env python3
"""Thin-geometry scene for the RSM first bounce (bench/README.md):

    python3 bench/scenes/thin_slats.py WIDTH_M OUT.gltf

A point light (200 cd) at the origin, a Lambert 0.8 floor disc of radius 1.4 m at
y = -1 and 24 vertical slats WIDTH_M wide, 2 m high, on a circle of radius 1.5 m
facing the light, with nothing behind them; the camera looks down from 3.2 m."""
import base64
import json
import math
import struct
import sys

W_SLAT = float(sys.argv[1]); out = sys.argv[2]
pos, nrm, idx = [], [], []
def quad(p0, p1, p2, p3, n):
    b = len(pos) // 3
    for p in (p0, p1, p2, p3): pos.extend(p); nrm.extend(n)
    idx.extend([b, b + 1, b + 2, b, b + 2, b + 3])
# floor disc as a fan, facing +y
segs = 48
c = len(pos) // 3; pos.extend([0, -1, 0]); nrm.extend([0, 1, 0])
for i in range(segs):
    a = 2 * math.pi * i / segs
    pos.extend([1.4 * math.cos(a), -1, 1.4 * math.sin(a)]); nrm.extend([0, 1, 0])
for i in range(segs):
    idx.extend([c, c + 1 + (i + 1) % segs, c + 1 + i])
nf = len(idx)
for k in range(24):
    a = 2 * math.pi * (k + 0.5) / 24
    cx, cz = 1.5 * math.cos(a), 1.5 * math.sin(a)
    tx, tz = -math.sin(a) * W_SLAT / 2, math.cos(a) * W_SLAT / 2
    n = [-math.cos(a), 0, -math.sin(a)]
    quad([cx - tx, -1, cz - tz], [cx + tx, -1, cz + tz], [cx + tx, 1, cz + tz], [cx - tx, 1, cz - tz], n)
# fix winding: counter-clockwise seen from the normal side
def fixw(i0, i1, i2):
    p = [pos[3*i:3*i+3] for i in (i0, i1, i2)]
    e1 = [p[1][j]-p[0][j] for j in range(3)]; e2 = [p[2][j]-p[0][j] for j in range(3)]
    cr = [e1[1]*e2[2]-e1[2]*e2[1], e1[2]*e2[0]-e1[0]*e2[2], e1[0]*e2[1]-e1[1]*e2[0]]
    n = nrm[3*i0:3*i0+3]
    return (i0, i1, i2) if sum(cr[j]*n[j] for j in range(3)) > 0 else (i0, i2, i1)
tris = [fixw(*idx[i:i+3]) for i in range(0, len(idx), 3)]
idx = [v for t in tris for v in t]
nv = len(pos) // 3
bp = struct.pack("<%df" % len(pos), *pos); bn = struct.pack("<%df" % len(nrm), *nrm); bi = struct.pack("<%dI" % len(idx), *idx)
buf = bp + bn + bi
mn = [min(pos[j::3]) for j in range(3)]; mx = [max(pos[j::3]) for j in range(3)]
g = {"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_lights_punctual"],
     "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 200.0, "color": [1, 1, 1]}]}},
     "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
     "nodes": [{"mesh": 0}, {"extensions": {"KHR_lights_punctual": {"light": 0}}},
               {"camera": 0, "translation": [0, 3.2, 0], "rotation": [-0.7071068, 0, 0, 0.7071068]}],
     "cameras": [{"type": "perspective", "perspective": {"yfov": 0.9, "aspectRatio": 1.0, "znear": 0.01}}],
     "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 1}}],
     "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
     "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
     "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(bp)}, {"buffer": 0, "byteOffset": len(bp), "byteLength": len(bn)},
                     {"buffer": 0, "byteOffset": len(bp) + len(bn), "byteLength": len(bi)}],
     "accessors": [{"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3", "min": mn, "max": mx},
                   {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC3"},
                   {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"}]}
json.dump(g, open(out, "w"))
