#!/usr/bin/env python3
"""A large deforming mesh for the sequence benchmark's deformation cost
(bench/run_sequences.py): a cylinder of S segments x R rings (2 S (R - 1)
triangles; the defaults make 100,000), skinned to a chain of four joints
(four influences per vertex: hat weights along the height) with two morph
targets (a bulge and a flare, POSITION and NORMAL), a camera and a sun.

    python3 bench/deform_scene.py OUT.gltf [--segments S] [--rings R] [--mode MODE]

MODE: skinned (the joints bend and the morph weights move over frames 0-23:
every vertex is posed every frame), rigid (the same mesh without skin and
targets, its node moving: every vertex transformed every frame), static (no
animation: nothing is posed per frame). One buffer, embedded as a data URI.
"""
import argparse
import base64
import json
import math
import struct


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--segments", type=int, default=250)
    ap.add_argument("--rings", type=int, default=201)
    ap.add_argument("--mode", choices=["skinned", "rigid", "static"], default="skinned")
    a = ap.parse_args()
    S, R, height, radius = a.segments, a.rings, 4.0, 0.5
    pos, nrm, joints, weights, bulge, flare = [], [], [], [], [], []
    for r in range(R):
        z = height * r / (R - 1)
        w = [max(0.0, 1.0 - abs(z - (j + 0.5))) for j in range(4)]
        s = sum(w)
        for k in range(S):
            t = 2 * math.pi * k / S
            c, sn = math.cos(t), math.sin(t)
            pos.append((radius * c, z, radius * sn))  # glTF Y up
            nrm.append((c, 0.0, sn))
            joints.append((0, 1, 2, 3))
            weights.append(tuple(x / s for x in w))
            b = 0.15 * math.sin(math.pi * z / height)
            bulge.append((b * c, 0.0, b * sn))
            f = 0.2 * (z / height) ** 2
            flare.append((f * c, 0.0, f * sn))
    idx = []
    for r in range(R - 1):
        for k in range(S):
            a0, a1 = r * S + k, r * S + (k + 1) % S
            idx += [a0, a0 + S, a1, a1, a0 + S, a1 + S]
    blob = bytearray()
    views, accessors = [], []

    def add(fmt, rows, ct, type_, minmax=False):
        data = b"".join(struct.pack("<" + fmt, *row) for row in rows)
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
        blob.extend(data)
        acc = {"bufferView": len(views) - 1, "componentType": ct, "count": len(rows), "type": type_}
        if minmax:
            acc["min"] = [min(r[i] for r in rows) for i in range(3)]
            acc["max"] = [max(r[i] for r in rows) for i in range(3)]
        accessors.append(acc)
        return len(accessors) - 1

    attrs = {"POSITION": add("3f", pos, 5126, "VEC3", True), "NORMAL": add("3f", nrm, 5126, "VEC3")}
    prim = {"attributes": attrs, "indices": add("I", [(i,) for i in idx], 5125, "SCALAR")}
    nodes = []
    anim = None
    frames = [i / 24.0 for i in range(24)]
    tin = add("f", [(t,) for t in frames], 5126, "SCALAR")
    if a.mode == "skinned":
        attrs["JOINTS_0"] = add("4B", joints, 5121, "VEC4")
        attrs["WEIGHTS_0"] = add("4f", weights, 5126, "VEC4")
        prim["targets"] = [{"POSITION": add("3f", bulge, 5126, "VEC3"), "NORMAL": add("3f", [(0, 0, 0)] * len(bulge), 5126, "VEC3")},
                           {"POSITION": add("3f", flare, 5126, "VEC3")}]
        ibm = []
        for j in range(4):
            ibm.append((1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -float(j), 0, 1))
        nodes = [{"name": "mesh", "mesh": 0, "skin": 0}]
        for j in range(4):
            n = {"name": "joint%d" % j, "translation": [0, 1.0 if j else 0.0, 0]}
            if j < 3:
                n["children"] = [2 + j]
            nodes.append(n)
        channels, samplers = [], []
        for j in (1, 2, 3):
            q = []
            for t in frames:
                ang = 0.4 * math.sin(2 * math.pi * t + j)
                q.append((math.sin(ang / 2), 0.0, 0.0, math.cos(ang / 2)))
            samplers.append({"input": tin, "output": add("4f", q, 5126, "VEC4")})
            channels.append({"sampler": len(samplers) - 1, "target": {"node": 1 + j, "path": "rotation"}})
        wv = []
        for t in frames:
            wv += [(0.5 + 0.5 * math.sin(2 * math.pi * t),), (0.5 + 0.5 * math.cos(2 * math.pi * t),)]
        samplers.append({"input": tin, "output": add("f", wv, 5126, "SCALAR")})
        channels.append({"sampler": len(samplers) - 1, "target": {"node": 0, "path": "weights"}})
        anim = {"name": "bend", "channels": channels, "samplers": samplers}
        skins = [{"joints": [1, 2, 3, 4], "skeleton": 1, "inverseBindMatrices": add("16f", ibm, 5126, "MAT4")}]
        roots = [0, 1]
    else:
        nodes = [{"name": "mesh", "mesh": 0}]
        skins = []
        roots = [0]
        if a.mode == "rigid":
            tr = [(0.3 * math.sin(2 * math.pi * t), 0.0, 0.0) for t in frames]
            anim = {"name": "slide", "samplers": [{"input": tin, "output": add("3f", tr, 5126, "VEC3")}],
                    "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}]}
    s2 = math.sqrt(0.5)
    nodes.append({"name": "camera", "camera": 0, "translation": [0, 2, 8]})
    nodes.append({"name": "sun", "rotation": [-s2 * 0.8, 0.3, 0, s2], "extensions": {"KHR_lights_punctual": {"light": 0}}})
    roots += [len(nodes) - 2, len(nodes) - 1]
    doc = {"asset": {"version": "2.0", "generator": "photonbridge bench/deform_scene.py"},
           "extensionsUsed": ["KHR_lights_punctual"],
           "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 2732}]}},
           "scene": 0, "scenes": [{"nodes": roots}], "nodes": nodes, "meshes": [{"primitives": [prim]}],
           "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "aspectRatio": 1, "znear": 0.1}}],
           "accessors": accessors, "bufferViews": views,
           "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}]}
    if skins:
        doc["skins"] = skins
    if anim:
        doc["animations"] = [anim]
    with open(a.out, "w") as f:
        json.dump(doc, f)
    print("wrote %s: %d triangles, %d vertices, %s" % (a.out, len(idx) // 3, len(pos), a.mode))


if __name__ == "__main__":
    main()
