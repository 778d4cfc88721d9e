#!/usr/bin/env python3
"""Animated variants of committed samples for bench/anim.c (pb_bench_anim):
the sample's JSON with an `animations` block whose keys live in a second,
data-URI buffer; the sample's .bin (and images) are copied next to it.

  bench/anim_scenes.py OUT_DIR

sun_atrium_anim: the Columns node (123,080 of 123,582 triangles) turns 45
degrees about +Y around its origin and slides 4 m along +X between 0 and 1 s
(LINEAR), sweeping through the walls. spot_room_anim: the Ball rolls 1.8 m
along +X and the Crate turns 90 degrees about +Y and rises 1 m (0 to 1 s).
spot_room_debris: spot_room plus 48 more instances of the Ball mesh (108k
triangles in all) packed in a 4 x 4 x 3 block at 0 s that flies apart to
fill the room at 1 s and keeps going (through the walls) to three times
that spread at 3 s, each ball spinning: objects moving apart, the case a
refitted BVH handles worst.
"""
import base64
import json
import math
import os
import shutil
import struct
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# name -> {node name: (translation at 1 s minus rest, degrees about +Y at 1 s)}
MOTION = {
    "sun_atrium": {"Columns": ((4.0, 0.0, 0.0), 45.0)},
    "spot_room": {"Ball": ((1.8, 0.0, 0.0), 0.0), "Crate": ((0.0, 1.0, 0.0), 90.0)},
}
KEYS = 11  # keys at 0, 0.1, ..., 1 s


def make(name, out_dir, debris=False):
    src_dir = os.path.join(ROOT, "samples", name)
    d = json.load(open(os.path.join(src_dir, name + ".gltf")))
    dst = os.path.join(out_dir, name + ("_debris" if debris else "_anim"))
    os.makedirs(dst, exist_ok=True)
    for f in os.listdir(src_dir):
        if not f.endswith(".gltf"):
            shutil.copy(os.path.join(src_dir, f), dst)
    data = bytearray()
    d.setdefault("bufferViews", [])
    d.setdefault("accessors", [])
    buf = len(d["buffers"])

    def accessor(values, comps):
        off = len(data)
        for v in values:
            data.extend(struct.pack("<%df" % comps, *(v if comps > 1 else (v,))))
        d["bufferViews"].append({"buffer": buf, "byteOffset": off, "byteLength": len(data) - off})
        d["accessors"].append({"bufferView": len(d["bufferViews"]) - 1, "componentType": 5126, "count": len(values),
                               "type": {1: "SCALAR", 3: "VEC3", 4: "VEC4"}[comps]})
        return len(d["accessors"]) - 1

    span = 3.0 if debris else 1.0  # debris keeps flying out to 3 s
    times = [span * k / (KEYS - 1) for k in range(KEYS)]
    t_acc = accessor(times, 1)
    samplers, channels = [], []
    motion = dict(MOTION[name])
    if debris:
        motion = {}
        ball = next(n["mesh"] for n in d["nodes"] if n.get("name") == "Ball")
        scene_nodes = d["scenes"][d.get("scene", 0)]["nodes"]
        k = 0
        for x in range(4):
            for y in range(3):
                for z in range(4):
                    start = (0.35 * (x - 1.5), 1.2 + 0.35 * (y - 1), 0.35 * (z - 1.5))
                    end = (2.6 * (x - 1.5) / 1.5, 0.4 + 1.2 * y, 2.1 * (z - 1.5) / 1.5)
                    nm = "Debris%02d" % k
                    d["nodes"].append({"name": nm, "mesh": ball, "translation": list(start), "scale": [0.5, 0.5, 0.5]})
                    scene_nodes.append(len(d["nodes"]) - 1)
                    motion[nm] = (tuple(end[c] - start[c] for c in range(3)), 90.0 + 10 * k)
                    k += 1
    for ni, n in enumerate(d["nodes"]):
        if n.get("name") not in motion:
            continue
        dt, deg = motion[n["name"]]
        rest = n.get("translation", [0.0, 0.0, 0.0])
        tr = [tuple(rest[c] + u * dt[c] for c in range(3)) for u in times]
        rot = [(0.0, math.sin(math.radians(deg * u) / 2), 0.0, math.cos(math.radians(deg * u) / 2)) for u in times]
        samplers.append({"input": t_acc, "output": accessor(tr, 3)})
        channels.append({"sampler": len(samplers) - 1, "target": {"node": ni, "path": "translation"}})
        samplers.append({"input": t_acc, "output": accessor(rot, 4)})
        channels.append({"sampler": len(samplers) - 1, "target": {"node": ni, "path": "rotation"}})
    d["buffers"].append({"byteLength": len(data),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(data)).decode()})
    d["animations"] = [{"name": "bench", "samplers": samplers, "channels": channels}]
    path = os.path.join(dst, os.path.basename(dst) + ".gltf")
    json.dump(d, open(path, "w"))
    print(path)


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "build/anim_scenes"
    for name in MOTION:
        make(name, out)
    make("spot_room", out, debris=True)
