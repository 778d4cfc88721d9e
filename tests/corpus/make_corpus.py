#!/usr/bin/env python3
"""Writes the loader corpus: a small valid glTF scene and broken variants of it.

    python3 tests/corpus/make_corpus.py [OUT_DIR]     (default: this folder)

OUT_DIR receives broken/, valid/, outside.bin and expected.tsv. The output is a
pure function of this script (no time stamps, no randomness, fixed JSON key
order), so the committed files can be compared byte for byte with a fresh run
(ctest loader_corpus_fresh).

Every case is a folder named after it holding CASE.gltf (+ CASE.bin, tex.png)
or CASE.glb, so the loader's error message, which names the file, also names
the case. expected.tsv has one line per run of `photonbridge info`:

    PATH  EXIT  EXPECT  ARGS

PATH is relative to OUT_DIR; EXIT the exact exit status; for a failure EXPECT
lists substrings, separated by '|', that the one-line error must contain (the
JSON path first); for a success EXPECT is '-' or checks separated by '|' on
`info --json -`: 'triangles=N', 'warn=SUBSTRING' or 'has=SUBSTRING' (of the
JSON output). ARGS are extra options,
'-' for none.
"""
import base64
import copy
import json
import os
import shutil
import struct
import sys
import zlib

DELETE = object()  # blender_cases: remove the member

# Result codes (src/core/result.h).
EXIT_OK, EXIT_IO, EXIT_PARSE, EXIT_INVALID, EXIT_UNSUPPORTED = 0, 3, 4, 5, 6
EXIT_IMAGE, EXIT_LIMIT = 8, 10

FLOAT, UBYTE, USHORT, UINT = 5126, 5121, 5123, 5125

HERE = os.path.dirname(os.path.abspath(__file__))


# ---- byte builders ------------------------------------------------------------

def read_bytes(path):
    with open(path, "rb") as f:
        return f.read()


def png_chunk(kind, data):
    return (struct.pack(">I", len(data)) + kind + data +
            struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))


def make_png(w, h, rgba_rows):
    """A real RGBA8 PNG: IHDR, one IDAT (filter 0 on every row), IEND."""
    raw = b"".join(b"\x00" + bytes(row) for row in rgba_rows)
    return (b"\x89PNG\r\n\x1a\n" +
            png_chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
            png_chunk(b"IDAT", zlib.compress(raw, 9)) +
            png_chunk(b"IEND", b""))


# A real 2x2 baseline JPEG of the same checker (Pillow 9.4, quality 90).
JPEG_2X2 = bytes.fromhex(
    "ffd8ffe000104a46494600010100000100010000ffdb0043000302020302020303030304030304050805050404050a07"
    "0706080c0a0c0c0b0a0b0b0d0e12100d0e110e0b0b1016101113141515150c0f171816141812141514ffdb0043010304"
    "0405040509050509140d0b0d141414141414141414141414141414141414141414141414141414141414141414141414"
    "1414141414141414141414141414ffc00011080002000203012200021101031101ffc4001f0000010501010101010100"
    "000000000000000102030405060708090a0bffc400b5100002010303020403050504040000017d010203000411051221"
    "31410613516107227114328191a1082342b1c11552d1f02433627282090a161718191a25262728292a3435363738393a"
    "434445464748494a535455565758595a636465666768696a737475767778797a838485868788898a9293949596979899"
    "9aa2a3a4a5a6a7a8a9aab2b3b4b5b6b7b8b9bac2c3c4c5c6c7c8c9cad2d3d4d5d6d7d8d9dae1e2e3e4e5e6e7e8e9eaf1"
    "f2f3f4f5f6f7f8f9faffc4001f0100030101010101010101010000000000000102030405060708090a0bffc400b51100"
    "020102040403040705040400010277000102031104052131061241510761711322328108144291a1b1c109233352f015"
    "6272d10a162434e125f11718191a262728292a35363738393a434445464748494a535455565758595a63646566676869"
    "6a737475767778797a82838485868788898a92939495969798999aa2a3a4a5a6a7a8a9aab2b3b4b5b6b7b8b9bac2c3c4"
    "c5c6c7c8c9cad2d3d4d5d6d7d8d9dae2e3e4e5e6e7e8e9eaf2f3f4f5f6f7f8f9faffda000c03010002110311003f00f9"
    "f7e3d7c7af899e0ef8e7f11740d03e22f8b343d0b4af11ea363a7e99a6eb9736f6d676f15cc891431448e1638d115555"
    "54000000000514515fd3780ff74a3fe18fe48f3f1bfef557fc4ff33fffd9")


def tex_png():
    """2x2 checker: red, white / white, blue."""
    return make_png(2, 2, [[255, 0, 0, 255, 255, 255, 255, 255],
                           [255, 255, 255, 255, 0, 0, 255, 255]])


def huge_png():
    """A PNG whose IHDR declares 100000 x 100000 RGB (30 GB decoded) with one
    tiny IDAT: a decoder that trusts the header allocates; ours must refuse
    from the header alone."""
    return (b"\x89PNG\r\n\x1a\n" +
            png_chunk(b"IHDR", struct.pack(">IIBBBBB", 100000, 100000, 8, 2, 0, 0, 0)) +
            png_chunk(b"IDAT", zlib.compress(b"\x00" * 64)) +
            png_chunk(b"IEND", b""))


def make_hdr(w, h, rgb=(0.5, 0.6, 0.8), header_res=None):
    """A flat (uncompressed) Radiance RGBE image of one colour; header_res
    replaces the resolution line."""
    m = max(rgb)
    e = (m and __import__("math").frexp(m)[1]) or 0
    sc = 2.0 ** -e * 256.0 if m else 0.0
    px = bytes((min(255, int(rgb[0] * sc)), min(255, int(rgb[1] * sc)), min(255, int(rgb[2] * sc)), e + 128 if m else 0))
    res = header_res if header_res is not None else b"-Y %d +X %d" % (h, w)
    return b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n" + res + b"\n" + px * (w * h)


def pad4(b, fill=b"\x00"):
    return b + fill * ((4 - len(b) % 4) % 4)


def f32(*vals):
    return struct.pack("<%df" % len(vals), *vals)


def to_json(doc):
    return (json.dumps(doc, indent=1, allow_nan=False) + "\n").encode()


def make_glb(doc, bin_data, version=2):
    j = pad4(json.dumps(doc, separators=(",", ":")).encode(), b" ")
    out = struct.pack("<II", len(j), 0x4E4F534A) + j
    if bin_data is not None:
        b = pad4(bin_data)
        out += struct.pack("<II", len(b), 0x004E4942) + b
    return b"glTF" + struct.pack("<II", version, 12 + len(out)) + out


# ---- the base scene -------------------------------------------------------------
#
# A unit quad (4 vertices, 2 triangles) drawn twice: nodes[1] with the textured
# material and nodes[4] (a child of nodes[1]) with a plain red one; a camera
# (nodes[2]), a point light (nodes[3]) and a spot light (unused by any node).
#
#   accessors[0] POSITION  bufferViews[0]   accessors[2] TEXCOORD_0 bufferViews[2]
#   accessors[1] NORMAL    bufferViews[1]   accessors[3] indices     bufferViews[3]

POSITIONS = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
NORMALS = [(0, 0, 1)] * 4
UVS = [(0, 1), (1, 1), (1, 0), (0, 0)]
INDICES = [0, 1, 2, 0, 2, 3]
BASE_TRIANGLES = 4

INDEX_FORMAT = {UBYTE: "B", USHORT: "H", UINT: "I"}


def base(index_type=USHORT, indices=INDICES, positions=POSITIONS, mode=None,
         normals=True, indexed=True):
    """Returns (doc, bin bytes) of the base scene; the caller adds buffers[0]'s
    uri (or none, for a .glb) and any images."""
    pos = b"".join(f32(*p) for p in positions)
    nrm = b"".join(f32(*n) for n in NORMALS[:1] * len(positions))
    uv = b"".join(f32(*t) for t in (UVS * len(positions))[:len(positions)])
    idx = pad4(struct.pack("<%d%s" % (len(indices), INDEX_FORMAT[index_type]), *indices))
    views, accessors = [], []
    blob = b""

    def add(data, acc):
        nonlocal blob
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
        acc["bufferView"] = len(views) - 1
        accessors.append(acc)
        blob += data

    finite = [p for p in positions if all(abs(c) < 1e30 for c in p)] or [(0, 0, 0)]
    add(pos, {"componentType": FLOAT, "count": len(positions), "type": "VEC3",
              "min": [min(p[k] for p in finite) for k in range(3)],
              "max": [max(p[k] for p in finite) for k in range(3)]})
    add(nrm, {"componentType": FLOAT, "count": len(positions), "type": "VEC3"})
    add(uv, {"componentType": FLOAT, "count": len(positions), "type": "VEC2"})
    add(idx, {"componentType": index_type, "count": len(indices), "type": "SCALAR"})

    def prim(material):
        p = {"attributes": {"POSITION": 0, "TEXCOORD_0": 2}, "material": material}
        if normals:
            p["attributes"]["NORMAL"] = 1
        if indexed:
            p["indices"] = 3
        if mode is not None:
            p["mode"] = mode
        return p

    doc = {
        "asset": {"version": "2.0", "generator": "photonbridge make_corpus.py"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "scene": 0,
        "scenes": [{"name": "corpus", "nodes": [0]}],
        "nodes": [
            {"name": "root", "children": [1, 2, 3]},
            {"name": "quad", "mesh": 0, "children": [4]},
            {"name": "camera", "camera": 0, "translation": [0, 0, 5]},
            {"name": "lamp", "translation": [0, 2, 2],
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "quad2", "mesh": 1, "translation": [0, 0, -1], "scale": [2, 2, 2]},
        ],
        "meshes": [{"name": "quad", "primitives": [prim(0)]},
                   {"name": "quad2", "primitives": [prim(1)]}],
        "materials": [
            {"name": "textured", "pbrMetallicRoughness": {
                "baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 0.5}},
            {"name": "red", "pbrMetallicRoughness": {
                "baseColorFactor": [0.8, 0.1, 0.1, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.7},
             "doubleSided": True},
        ],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 33071}],
        "images": [{"name": "checker", "uri": "tex.png"}],
        "cameras": [{"name": "cam", "type": "perspective",
                     "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100, "aspectRatio": 1.5}}],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "bulb", "type": "point", "color": [1, 1, 1], "intensity": 100},
            {"name": "spot", "type": "spot", "intensity": 50,
             "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
        ]}},
        "buffers": [{"byteLength": len(blob)}],
        "bufferViews": views,
        "accessors": accessors,
    }
    return doc, blob


def skinned(d, joints=(5, 6), ibm_count=2, ibm_type="MAT4", joints0=None, weights0=None, drop=None, joints_count=4,
            weights_ubyte=False, normalized=True, node_skin=0):
    """Skins the quad of nodes[1] (mesh 0) to two joints, nodes[5] at the
    origin and its child nodes[6] at (0, 1, 0): the corners y = -1 follow
    joint 0, y = 1 joint 1. Keyword arguments break one thing each."""
    d["nodes"][0]["children"].append(5)
    d["nodes"] += [{"name": "bone0", "children": [6]}, {"name": "bone1", "translation": [0, 1, 0]}]
    j0 = joints0 or [(0, 0, 0, 0), (0, 0, 0, 0), (1, 0, 0, 0), (1, 0, 0, 0)]
    w0 = weights0 or [(1, 0, 0, 0)] * 4
    ibm = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1] + [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1]
    jb = bytes(c for v in j0 for c in v)
    wb = bytes(int(c * 255) for v in w0 for c in v) if weights_ubyte else b"".join(f32(*v) for v in w0)
    jv, wv, iv = add_buffer(d, jb, wb, f32(*ibm))
    na = len(d["accessors"])
    wacc = {"bufferView": wv, "componentType": UBYTE if weights_ubyte else FLOAT, "count": 4, "type": "VEC4"}
    if weights_ubyte and normalized:
        wacc["normalized"] = True
    d["accessors"] += [{"bufferView": jv, "componentType": UBYTE, "count": joints_count, "type": "VEC4"}, wacc,
                       {"bufferView": iv, "componentType": FLOAT, "count": ibm_count, "type": ibm_type}]
    attrs = d["meshes"][0]["primitives"][0]["attributes"]
    attrs["JOINTS_0"], attrs["WEIGHTS_0"] = na, na + 1
    if drop:
        del attrs[drop]
    skin = {"inverseBindMatrices": na + 2}
    if joints is not None:
        skin["joints"] = list(joints)
    d["skins"] = [skin]
    d["nodes"][1]["skin"] = node_skin


def morphed(d, count=4, type="VEC3", nan=False, normal=None, second_primitive=False, mesh_weights=None,
            node_weights=None, camera_weights=None, anim_values=None):
    """One morph target on mesh 0's quad: corners 2 and 3 lifted by z = 1.
    With anim_values, a LINEAR "weights" channel on nodes[1] with keys at 0,
    1 and 2 s. Keyword arguments break one thing each."""
    dz = [(0, 0, 0), (0, 0, 0), (0, 0, float("nan") if nan else 1), (0, 0, 1)]
    data = b"".join(f32(*v[:2] if type == "VEC2" else v) for v in dz)
    (tv,) = add_buffer(d, data)
    na = len(d["accessors"])
    d["accessors"].append({"bufferView": tv, "componentType": FLOAT, "count": count, "type": type})
    t = {"POSITION": na}
    if normal is not None:
        t["NORMAL"] = normal
    d["meshes"][0]["primitives"][0]["targets"] = [t]
    if second_primitive:
        d["meshes"][0]["primitives"].append(copy.deepcopy(d["meshes"][0]["primitives"][0]))
        del d["meshes"][0]["primitives"][1]["targets"]
    if mesh_weights is not None:
        d["meshes"][0]["weights"] = mesh_weights
    if node_weights is not None:
        d["nodes"][1]["weights"] = node_weights
    if camera_weights is not None:
        d["nodes"][2]["weights"] = camera_weights
    if anim_values is not None:
        kv, vv = add_buffer(d, f32(0, 1, 2), f32(*anim_values))
        na = len(d["accessors"])
        d["accessors"] += [{"bufferView": kv, "componentType": FLOAT, "count": 3, "type": "SCALAR"},
                           {"bufferView": vv, "componentType": FLOAT, "count": len(anim_values), "type": "SCALAR"}]
        d["animations"] = [{"samplers": [{"input": na, "output": na + 1}],
                            "channels": [{"sampler": 0, "target": {"node": 1, "path": "weights"}}]}]


def add_buffer(d, *blobs):
    """Appends a data-URI buffer holding `blobs` (each 4-byte aligned) and one
    bufferView per blob; returns the views' indices."""
    data, offsets = b"", []
    for b in blobs:
        offsets.append(len(data))
        data += pad4(b)
    d["buffers"].append({"byteLength": len(data),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()})
    nb, first = len(d["buffers"]) - 1, len(d["bufferViews"])
    for b, off in zip(blobs, offsets):
        d["bufferViews"].append({"buffer": nb, "byteOffset": off, "byteLength": len(b)})
    return list(range(first, first + len(blobs)))


# ---- writing ----------------------------------------------------------------------

class Corpus:
    def __init__(self, root):
        self.root = root
        self.lines = []

    def path(self, rel):
        p = os.path.join(self.root, rel)
        os.makedirs(os.path.dirname(p), exist_ok=True)
        return p

    def raw(self, rel, data):
        with open(self.path(rel), "wb") as f:
            f.write(data)

    def expect(self, rel, code, expect, args="-"):
        if isinstance(expect, (list, tuple)):
            expect = "|".join(expect)
        assert "\t" not in expect and expect, rel
        self.lines.append("\t".join([rel, str(code), expect, args]))

    def gltf(self, group, name, doc, blob, png=b"", bin_name=None, code=None, expect=None,
             args="-"):
        """Writes GROUP/NAME/NAME.gltf with NAME.bin (when the doc's buffer
        has no uri yet) and tex.png (when the doc uses it)."""
        folder = "%s/%s/" % (group, name)
        doc = copy.deepcopy(doc)
        bufs = doc.get("buffers", [])
        if blob is not None and bufs and "uri" not in bufs[0]:
            bufs[0]["uri"] = bin_name or name + ".bin"
        if blob is not None and bufs and bufs[0].get("uri") == (bin_name or name + ".bin"):
            self.raw(folder + bufs[0]["uri"], blob)
        if png and any(im.get("uri") == "tex.png" for im in doc.get("images", [])):
            self.raw(folder + "tex.png", png)
        rel = folder + name + ".gltf"
        self.raw(rel, to_json(doc))
        if code is not None:
            self.expect(rel, code, expect, args)
        return rel

    def glb(self, group, name, data, code, expect, args="-"):
        rel = "%s/%s/%s.glb" % (group, name, name)
        self.raw(rel, data)
        self.expect(rel, code, expect, args)


def glb_doc(doc, blob, png):
    """The base doc as a .glb: buffer 0 is the BIN chunk, the image a bufferView."""
    doc = copy.deepcopy(doc)
    blob = pad4(blob)
    doc["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(png)})
    doc["images"] = [{"name": "checker", "bufferView": len(doc["bufferViews"]) - 1,
                      "mimeType": "image/png"}]
    blob = pad4(blob + png)
    doc["buffers"] = [{"byteLength": len(blob)}]
    return doc, blob


def broken_cases(C, png):
    doc0, bin0 = base()
    B = "broken"

    def case(name, code, expect, edit=None, blob=None, png_data=None, args="-"):
        d = copy.deepcopy(doc0)
        b = bin0 if blob is None else blob
        if edit:
            edit(d)  # edits in place; any return value is ignored
        C.gltf(B, name, d, b, png if png_data is None else png_data, code=code, expect=expect,
               args=args)

    def setp(path, value):
        """edit function: sets doc[path...] = value (path as a tuple of keys)."""
        def f(d):
            o = d
            for k in path[:-1]:
                o = o[k]
            o[path[-1]] = value
        return f

    # -- buffers and files
    case("bin_truncated", EXIT_INVALID, ["buffers[0].uri", "byteLength says %d" % len(bin0)],
         blob=bin0[:100])
    d = copy.deepcopy(doc0)
    d["buffers"][0]["uri"] = "bin_missing.bin"
    C.gltf(B, "bin_missing", d, None, png, code=EXIT_IO, expect=["buffers[0].uri", "bin_missing.bin"])
    case("buffer_bytelength_missing", EXIT_INVALID, "buffers[0].byteLength",
         lambda d: d["buffers"][0].pop("byteLength"))
    case("buffer_uri_none", EXIT_INVALID, "buffers[1]: no uri",
         lambda d: d["buffers"].append({"byteLength": 4}))
    case("bufferview_past_buffer", EXIT_INVALID, ["bufferViews[1]", "exceeds buffers[0]"],
         setp(("bufferViews", 1, "byteLength"), 4096))
    case("bufferview_offset_past_buffer", EXIT_INVALID, ["bufferViews[0]", "exceeds buffers[0]"],
         setp(("bufferViews", 0, "byteOffset"), 1 << 40))
    case("bufferview_buffer_oob", EXIT_INVALID, "bufferViews[1].buffer",
         setp(("bufferViews", 1, "buffer"), 3))
    case("bufferview_stride_bad", EXIT_INVALID, "bufferViews[0].byteStride",
         setp(("bufferViews", 0, "byteStride"), 6))
    case("bufferview_stride_small", EXIT_INVALID, "bufferViews[0].byteStride",
         setp(("bufferViews", 0, "byteStride"), 8))
    case("bufferview_stride_huge", EXIT_INVALID, "bufferViews[0].byteStride",
         setp(("bufferViews", 0, "byteStride"), 256))

    # -- accessors
    case("accessor_count_past_view", EXIT_INVALID,
         "accessors[0]: count 900 x stride 12 exceeds bufferViews[0] (48 bytes)",
         setp(("accessors", 0, "count"), 900))
    case("accessor_offset_past_view", EXIT_INVALID, ["accessors[2]", "exceeds bufferViews[2]"],
         setp(("accessors", 2, "byteOffset"), 8))
    case("accessor_offset_misaligned", EXIT_INVALID, "accessors[1].byteOffset",
         setp(("accessors", 1, "byteOffset"), 2))
    case("accessor_bufferview_oob", EXIT_INVALID, "accessors[1].bufferView",
         setp(("accessors", 1, "bufferView"), 17))
    case("accessor_count_2pow40", EXIT_INVALID, ["accessors[0]", "count 1099511627776"],
         setp(("accessors", 0, "count"), 1 << 40))

    def no_view_huge(d):
        del d["accessors"][0]["bufferView"]
        d["accessors"][0]["count"] = 1 << 40
    case("accessor_count_2pow40_no_view", EXIT_LIMIT, ["accessors[0]", "1099511627776"], no_view_huge)

    def no_view_big(d):
        del d["accessors"][0]["bufferView"]
        d["accessors"][0]["count"] = (1 << 32) - 1
        for m in d["meshes"]:
            del m["primitives"][0]["attributes"]["NORMAL"]
            del m["primitives"][0]["attributes"]["TEXCOORD_0"]
            del m["primitives"][0]["indices"]
    case("accessor_count_4g_no_view", EXIT_LIMIT, "meshes[0].primitives[0]", no_view_big)
    case("accessor_count_negative", EXIT_INVALID, "accessors[0].count: -4",
         setp(("accessors", 0, "count"), -4))
    case("accessor_count_missing", EXIT_INVALID, "accessors[2].count: missing",
         lambda d: d["accessors"][2].pop("count"))
    case("accessor_count_float", EXIT_INVALID, "accessors[2].count: 4.5",
         setp(("accessors", 2, "count"), 4.5))
    case("accessor_component_type_bogus", EXIT_INVALID, "accessors[1].componentType",
         setp(("accessors", 1, "componentType"), 5124))

    def no_view_indexed(d):
        for m in d["meshes"]:
            del m["primitives"][0]["attributes"]["TEXCOORD_0"]
        for k in (0, 1):
            del d["accessors"][k]["bufferView"]
            d["accessors"][k]["count"] = 1 << 31
    case("accessor_count_2g_no_view_indexed", EXIT_LIMIT, ["meshes[0].primitives[0]", "vertices"],
         no_view_indexed)
    case("accessor_count_zero", EXIT_INVALID, "accessors[1]: count is 0", setp(("accessors", 1, "count"), 0))
    case("accessor_type_bogus", EXIT_INVALID, "accessors[2].type", setp(("accessors", 2, "type"), "VEC7"))
    case("position_vec2", EXIT_INVALID, ["accessors[0]", "has 2 components"],
         setp(("accessors", 0, "type"), "VEC2"))
    case("position_ushort", EXIT_INVALID, ["accessors[0]", "componentType 5123"],
         setp(("accessors", 0, "componentType"), USHORT))
    case("indices_float", EXIT_INVALID, ["accessors[3]", "componentType 5126"],
         setp(("accessors", 3, "componentType"), FLOAT))
    # Sparse accessors (glTF 2.0 3.6.2.3): indices and values in a second,
    # data-URI buffer; every rule of the spec's sparse object.
    def sparse(indices, values, ict=USHORT, count=None, acc=0, edit=None):
        def f(d):
            ib = pad4(struct.pack("<%d%s" % (len(indices), INDEX_FORMAT[ict]), *indices))
            vb = b"".join(f32(*v) for v in values)
            views = add_buffer(d, ib, vb)
            d["accessors"][acc]["sparse"] = {
                "count": len(indices) if count is None else count,
                "indices": {"bufferView": views[0], "componentType": ict},
                "values": {"bufferView": views[1]}}
            if edit:
                edit(d["accessors"][acc]["sparse"], d)
        return f
    P2 = [(0, 0, 1), (0, 0, 2)]
    case("sparse_count_zero", EXIT_INVALID, "accessors[0].sparse.count: 0 is not an integer from 1",
         sparse([1, 2], P2, count=0))
    case("sparse_count_over", EXIT_INVALID, "accessors[0].sparse.count: 5 is not in [1, 4]",
         sparse([0, 1, 2, 3, 3], P2 * 3, count=5))
    case("sparse_indices_not_increasing", EXIT_INVALID,
         "accessors[0].sparse.indices: element 1 (1) does not increase on 2", sparse([2, 1], P2))
    case("sparse_index_out_of_range", EXIT_INVALID,
         "accessors[0].sparse.indices: index 4 at element 1 is out of range (count 4)", sparse([1, 4], P2))
    case("sparse_indices_float", EXIT_INVALID, "accessors[0].sparse.indices.componentType: 5126",
         sparse([1, 2], P2, edit=lambda sp, d: sp["indices"].update({"componentType": FLOAT})))
    case("sparse_values_short", EXIT_INVALID,
         "accessors[0].sparse.values: 2 elements of 12 bytes at offset 16 exceed bufferViews[",
         sparse([1, 2], P2, edit=lambda sp, d: sp["values"].update({"byteOffset": 16})))
    case("sparse_values_view_oob", EXIT_INVALID, "accessors[0].sparse.values.bufferView: 17 does not exist",
         sparse([1, 2], P2, edit=lambda sp, d: sp["values"].update({"bufferView": 17})))
    case("sparse_no_indices", EXIT_INVALID, "accessors[0].sparse.indices: missing",
         sparse([1, 2], P2, edit=lambda sp, d: sp.pop("indices")))
    case("sparse_indices_strided", EXIT_INVALID, "accessors[0].sparse.indices: bufferViews[",
         sparse([1, 2], P2, edit=lambda sp, d: d["bufferViews"][sp["indices"]["bufferView"]].update({"byteStride": 4})))
    case("sparse_not_object", EXIT_INVALID, "accessors[0].sparse: not an object", setp(("accessors", 0, "sparse"), 3))
    # A sparse POSITION without a bufferView: one substituted element is all
    # the file holds of 2^31 (indexed, without NORMAL, so that the vertex
    # limit counts only the indexed corners): every element was checked for
    # finiteness by binary search (a minute) before the limit.
    def sparse_2g(d):
        sparse([1], [(0, 0, 1)])(d)
        del d["accessors"][0]["bufferView"]
        d["accessors"][0]["count"] = 1 << 31
        for m in d["meshes"]:
            for a in ("NORMAL", "TEXCOORD_0"):
                del m["primitives"][0]["attributes"][a]
    case("position_sparse_2g_no_view", EXIT_LIMIT,
         "meshes[0].primitives[0].attributes.POSITION: 2147483648 elements is over the limit of 201326592", sparse_2g)
    # KHR_texture_transform's members and KHR_materials_volume's are typed.
    tt = ("materials", 0, "pbrMetallicRoughness", "baseColorTexture", "extensions")
    case("texture_transform_offset_bad", EXIT_INVALID,
         "materials[0].pbrMetallicRoughness.baseColorTexture.extensions.KHR_texture_transform.offset: not an array of 2 numbers",
         setp(tt, {"KHR_texture_transform": {"offset": [1]}}))
    case("texture_transform_texcoord_bad", EXIT_INVALID,
         "baseColorTexture.extensions.KHR_texture_transform.texCoord: -1 is not an index",
         setp(tt, {"KHR_texture_transform": {"texCoord": -1}}))
    case("volume_distance_negative", EXIT_INVALID,
         "materials[1].extensions.KHR_materials_volume.attenuationDistance: -2 is not positive",
         setp(("materials", 1, "extensions"), {"KHR_materials_volume": {"thicknessFactor": 1, "attenuationDistance": -2}}))
    case("volume_color_range", EXIT_INVALID,
         "materials[1].extensions.KHR_materials_volume.attenuationColor[1]: 2 is outside [0, 1]",
         setp(("materials", 1, "extensions"), {"KHR_materials_volume": {"attenuationColor": [1, 2, 1]}}))
    # KHR_materials_iridescence: read and checked (the plain glTF model does
    # not render it; a Blender Principled v2 Thin Film is).
    case("iridescence_factor_range", EXIT_INVALID,
         "materials[1].extensions.KHR_materials_iridescence.iridescenceFactor: 1.5 is outside [0, 1]",
         setp(("materials", 1, "extensions"), {"KHR_materials_iridescence": {"iridescenceFactor": 1.5}}))
    case("iridescence_ior_below_1", EXIT_INVALID,
         "materials[1].extensions.KHR_materials_iridescence.iridescenceIor: 0.8 is outside [1, 1000]",
         setp(("materials", 1, "extensions"), {"KHR_materials_iridescence": {"iridescenceFactor": 1,
                                                                              "iridescenceIor": 0.8}}))
    case("iridescence_thickness_negative", EXIT_INVALID,
         "materials[1].extensions.KHR_materials_iridescence.iridescenceThicknessMaximum: -50 is outside [0, 100000]",
         setp(("materials", 1, "extensions"), {"KHR_materials_iridescence": {"iridescenceFactor": 1,
                                                                              "iridescenceThicknessMaximum": -50}}))
    case("iridescence_thickness_string", EXIT_INVALID,
         "materials[1].extensions.KHR_materials_iridescence.iridescenceThicknessMinimum: not a number",
         setp(("materials", 1, "extensions"), {"KHR_materials_iridescence": {"iridescenceThicknessMinimum": "100"}}))
    case("normal_count_mismatch", EXIT_INVALID, "meshes[0].primitives[0].attributes.NORMAL",
         setp(("accessors", 1, "count"), 3))
    case("texcoord_count_mismatch", EXIT_INVALID, "meshes[0].primitives[0].attributes.TEXCOORD_0",
         setp(("accessors", 2, "count"), 2))
    # TANGENT (normal maps): VEC4 float with POSITION's count, checked when
    # present even where no material has a normal map.
    case("tangent_vec3", EXIT_INVALID, ["accessors[1]", "has 3 components",
                                        "meshes[0].primitives[0].attributes.TANGENT needs 4"],
         setp(("meshes", 0, "primitives", 0, "attributes", "TANGENT"), 1))
    case("prim_tangent_oob", EXIT_INVALID, ["meshes[1].primitives[0].attributes.TANGENT", "accessor 42 does not exist"],
         setp(("meshes", 1, "primitives", 0, "attributes", "TANGENT"), 42))

    # -- primitives
    case("prim_position_oob", EXIT_INVALID, "meshes[0].primitives[0].attributes.POSITION",
         setp(("meshes", 0, "primitives", 0, "attributes", "POSITION"), 42))
    case("prim_normal_oob", EXIT_INVALID, "meshes[1].primitives[0].attributes.NORMAL",
         setp(("meshes", 1, "primitives", 0, "attributes", "NORMAL"), -7))
    case("prim_indices_oob", EXIT_INVALID, "meshes[0].primitives[0].indices",
         setp(("meshes", 0, "primitives", 0, "indices"), 42))
    case("prim_indices_no_view", EXIT_INVALID, "accessors[3]",
         lambda d: d["accessors"][3].pop("bufferView"))
    case("prim_no_position", EXIT_INVALID, "meshes[0].primitives[0].attributes",
         lambda d: d["meshes"][0]["primitives"][0]["attributes"].pop("POSITION"))
    case("prim_material_oob", EXIT_INVALID, "meshes[1].primitives[0].material",
         setp(("meshes", 1, "primitives", 0, "material"), 2))
    case("mesh_oob", EXIT_INVALID, "nodes[4].mesh", setp(("nodes", 4, "mesh"), 2))
    case("mesh_negative", EXIT_INVALID, "nodes[4].mesh: -3", setp(("nodes", 4, "mesh"), -3))
    # tinygltf keeps ids as int: 2^32 + 1 would quietly become mesh 1.
    case("mesh_index_2pow32", EXIT_INVALID, "nodes[4].mesh: 4294967297",
         setp(("nodes", 4, "mesh"), (1 << 32) + 1))
    case("material_index_string", EXIT_INVALID, 'meshes[0].primitives[0].material: "0"',
         setp(("meshes", 0, "primitives", 0, "material"), "0"))
    case("bufferview_offset_negative", EXIT_INVALID, "bufferViews[2].byteOffset: -4",
         setp(("bufferViews", 2, "byteOffset"), -4))

    for ct, name in ((UBYTE, "u8"), (USHORT, "u16"), (UINT, "u32")):
        d, b = base(index_type=ct, indices=[0, 1, 2, 0, 2, 4])
        C.gltf(B, "index_oob_" + name, d, b, png, code=EXIT_INVALID,
               expect=["accessors[3]", "index 4 at element 5"])
    d, b = base(index_type=UINT, indices=[0, 1, 2, 0, 0xFFFFFFFF, 3])
    C.gltf(B, "index_oob_u32_max", d, b, png, code=EXIT_INVALID,
           expect=["accessors[3]", "index 4294967295"])

    nan, inf = float("nan"), float("inf")
    for name, bad in (("position_nan", (0, nan, 0)), ("position_inf", (inf, 1, 0)),
                      ("position_neg_inf", (1, 1, -inf))):
        d, b = base(positions=POSITIONS[:2] + [bad] + POSITIONS[3:])
        C.gltf(B, name, d, b, png, code=EXIT_INVALID, expect=["accessors[0]", "element 2 is not finite"])

    # -- materials, textures, images
    case("material_alpha_mode_bogus", EXIT_INVALID, "materials[1].alphaMode",
         setp(("materials", 1, "alphaMode"), "TRANSLUCENT"))
    case("material_roughness_2", EXIT_INVALID, "materials[0].pbrMetallicRoughness.roughnessFactor",
         setp(("materials", 0, "pbrMetallicRoughness", "roughnessFactor"), 2))
    case("material_base_color_negative", EXIT_INVALID,
         "materials[1].pbrMetallicRoughness.baseColorFactor[1]",
         setp(("materials", 1, "pbrMetallicRoughness", "baseColorFactor"), [0.5, -0.5, 0.5, 1]))
    case("texture_oob", EXIT_INVALID, "materials[0].pbrMetallicRoughness.baseColorTexture.index",
         setp(("materials", 0, "pbrMetallicRoughness", "baseColorTexture", "index"), 7))
    case("texture_source_oob", EXIT_INVALID, "textures[0].source", setp(("textures", 0, "source"), 5))

    # -- the PHOTONBRIDGE_blender material extension (exporters/blender/PHOTONBRIDGE_blender.md)
    X = "materials[0].extensions.PHOTONBRIDGE_blender"

    def blender(ext):
        def f(d):
            d["materials"][0].setdefault("extensions", {})["PHOTONBRIDGE_blender"] = ext
            d["extensionsUsed"].append("PHOTONBRIDGE_blender")
        return f

    def principled(**inputs):
        return blender({"model": "principled", "principled": inputs})

    case("blender_not_object", EXIT_INVALID, X + ": a string, expected an object", blender("principled"))
    case("blender_model_missing", EXIT_INVALID, X + ".model: missing", blender({"principled": {}}))
    # A Mix Shader ("mix"): its second shader missing, a mix inside it, a
    # factor past its range.
    glossy = {"model": "glossy", "glossy": {"roughness": 0.2}}
    case("blender_mix_no_shader", EXIT_INVALID, X + ".mix.shader: missing",
         blender({"model": "diffuse", "mix": {"fac": 0.5}}))
    case("blender_mix_nested", EXIT_INVALID, X + ".mix.shader.mix: a Mix Shader inside a Mix Shader is not read",
         blender({"model": "diffuse", "mix": {"fac": 0.5, "shader": dict(glossy, mix={"fac": 0.5, "shader": glossy})}}))
    case("blender_mix_blend_range", EXIT_INVALID, X + ".mix.blend: 1.5 is outside [0, 1]",
         blender({"model": "diffuse", "mix": {"facFrom": "layerFacing", "blend": 1.5, "shader": glossy}}))
    case("blender_model_bogus", EXIT_INVALID,
         X + ".model: 'toon' is not principled, diffuse, emission, holdout, principled2, metallic, sheen, glossy, glass or refraction",
         blender({"model": "toon"}))
    case("blender_roughness_range", EXIT_INVALID, X + ".principled.roughness: 1.5 is outside [0, 1]",
         principled(roughness=1.5))
    case("blender_roughness_string", EXIT_INVALID, X + ".principled.roughness: a string, expected a number",
         principled(roughness="0.5"))
    case("blender_base_color_short", EXIT_INVALID, X + ".principled.baseColor: 2 elements, expected 3 or 4",
         principled(baseColor=[0.5, 0.5]))
    case("blender_base_color_negative", EXIT_INVALID, X + ".principled.baseColor[1]: -0.1 is outside",
         principled(baseColor=[0.5, -0.1, 0.5, 1.0]))
    case("blender_ior_negative", EXIT_INVALID, X + ".principled.ior: -1 is outside", principled(ior=-1))
    case("blender_emission_strength_negative", EXIT_INVALID, X + ".principled.emissionStrength: -2 is outside",
         principled(emissionStrength=-2))
    case("blender_distribution_bogus", EXIT_INVALID, X + ".principled.distribution: 'BECKMANN' is not GGX or MULTI_GGX",
         principled(distribution="BECKMANN"))
    # Principled v2 (model "principled2", Blender 4.0+).
    def principled2(**inputs):
        return blender({"model": "principled2", "principled2": inputs})

    case("blender2_not_object", EXIT_INVALID, X + ".principled2: an array, expected an object",
         blender({"model": "principled2", "principled2": [1]}))
    case("blender2_coat_weight_range", EXIT_INVALID, X + ".principled2.coatWeight: 1.5 is outside [0, 1]",
         principled2(coatWeight=1.5))
    case("blender2_coat_ior_below_1", EXIT_INVALID, X + ".principled2.coatIor: 0.5 is outside [1, 4]",
         principled2(coatIor=0.5))
    case("blender2_level_negative", EXIT_INVALID, X + ".principled2.specularIorLevel: -0.5 is outside",
         principled2(specularIorLevel=-0.5))
    case("blender2_level_string", EXIT_INVALID, X + ".principled2.specularIorLevel: a string, expected a number",
         principled2(specularIorLevel="0.5"))
    case("blender2_specular_tint_float", EXIT_INVALID,
         X + ".principled2.specularTint: a number, expected an array of 3 or 4 numbers", principled2(specularTint=0.5))
    case("blender2_sheen_tint_negative", EXIT_INVALID, X + ".principled2.sheenTint[2]: -1 is outside",
         principled2(sheenTint=[1, 1, -1]))
    case("blender2_emission_strength_negative", EXIT_INVALID,
         X + ".principled2.emissionStrength: -1 is outside", principled2(emissionStrength=-1))
    case("blender2_thin_film_negative", EXIT_INVALID, X + ".principled2.thinFilmThickness: -10 is outside",
         principled2(thinFilmThickness=-10))
    case("blender2_ss_anisotropy_range", EXIT_INVALID, X + ".principled2.subsurfaceAnisotropy: -2 is outside [-1, 1]",
         principled2(subsurfaceAnisotropy=-2))
    case("blender2_ss_radius_short", EXIT_INVALID,
         X + ".principled2.subsurfaceRadius: an array of another length, expected an array of 3 numbers",
         principled2(subsurfaceRadius=[1, 1]))
    case("blender2_ss_radius_negative", EXIT_INVALID, X + ".principled2.subsurfaceRadius[0]: -1 is outside",
         principled2(subsurfaceRadius=[-1, 1, 1]))
    case("blender2_ss_method_4x_name", EXIT_INVALID,
         X + ".principled2.subsurfaceMethod: 'RANDOM_WALK' is not RANDOM_WALK_SKIN, RANDOM_WALK_FIXED_RADIUS or "
         "BURLEY", principled2(subsurfaceMethod="RANDOM_WALK"))
    case("blender2_distribution_bogus", EXIT_INVALID,
         X + ".principled2.distribution: 'SHARP' is not GGX or MULTI_GGX", principled2(distribution="SHARP"))
    case("blender2_texture_tint_channel", EXIT_INVALID,
         X + ".textures.coatTint: channel R on a colour input (only RGB)",
         blender({"model": "principled2", "textures": {"coatTint": {"index": 0, "channel": "R"}}}))
    case("blender2_texture_coat_normal_oob", EXIT_INVALID, X + ".textures.coatNormal.index: texture 9 does not exist",
         blender({"model": "principled2", "textures": {"coatNormal": {"index": 9}}}))
    case("blender2_vertex_color_input", EXIT_INVALID,
         X + ".vertexColor: 'emissionColor': a colour attribute drives no such input of the principled2 model (only "
         "'baseColor')", blender({"model": "principled2", "vertexColor": "emissionColor"}))
    case("blender_diffuse_roughness_range", EXIT_INVALID, X + ".diffuse.roughness: -1 is outside [0, 1]",
         blender({"model": "diffuse", "diffuse": {"roughness": -1}}))
    case("blender_emission_color_type", EXIT_INVALID, X + ".emission.color: an object, expected an array",
         blender({"model": "emission", "emission": {"color": {"r": 1}}}))
    case("blender_vertex_color_input", EXIT_INVALID,
         X + ".vertexColor: 'roughness': a colour attribute drives no such input of the principled model (only "
         "'baseColor')", blender({"model": "principled", "vertexColor": "roughness"}))
    case("blender_vertex_color_emission", EXIT_INVALID,
         X + ".vertexColor: 'color': a colour attribute drives no such input of the emission model (none)",
         blender({"model": "emission", "vertexColor": "color"}))
    case("blender_vertex_color_type", EXIT_INVALID,
         X + ".vertexColor: a boolean, expected the name of the input a Color Attribute drives",
         blender({"model": "diffuse", "vertexColor": True}))
    case("blender_texture_oob", EXIT_INVALID, X + ".textures.baseColor.index: texture 7 does not exist",
         blender({"model": "principled", "textures": {"baseColor": {"index": 7}}}))
    case("blender_texture_index_float", EXIT_INVALID, X + ".textures.roughness.index: the number is not a texture index",
         blender({"model": "principled", "textures": {"roughness": {"index": 0.5}}}))
    case("blender_texture_index_missing", EXIT_INVALID, X + ".textures.roughness.index: missing",
         blender({"model": "principled", "textures": {"roughness": {"channel": "G"}}}))
    case("blender_texture_channel_bogus", EXIT_INVALID, X + ".textures.roughness.channel: 'X' is not R, G, B, A or RGB",
         blender({"model": "principled", "textures": {"roughness": {"index": 0, "channel": "X"}}}))
    case("blender_texture_transform_offset", EXIT_INVALID,
         X + ".textures.roughness.extensions.KHR_texture_transform.offset: a string, expected an array of 2 numbers",
         blender({"model": "principled", "textures": {"roughness": {
             "index": 0, "extensions": {"KHR_texture_transform": {"offset": "0 0"}}}}}))
    case("blender_texture_texcoord_negative", EXIT_INVALID,
         X + ".textures.baseColor.texCoord: the number is not an integer from 0 to 2^31-1",
         blender({"model": "principled", "textures": {"baseColor": {"index": 0, "texCoord": -1}}}))
    case("blender_warnings_not_strings", EXIT_INVALID, X + ".warnings[0]: a number, expected a string",
         blender({"model": "principled", "warnings": [1]}))
    case("texture_sampler_oob", EXIT_INVALID, "textures[0].sampler", setp(("textures", 0, "sampler"), 3))
    case("sampler_wrap_bogus", EXIT_INVALID, "samplers[0].wrapS", setp(("samplers", 0, "wrapS"), 12345))
    case("image_not_png", EXIT_UNSUPPORTED, ["images[0]", "not a PNG, JPEG, HDR or EXR file"],
         png_data=b"GIF89a\x02\x00\x02\x00\x80\x00\x00\xff\x00\x00\xff\xff\xff!\xf9\x04\x00"
                  b"\x00\x00\x00\x00,\x00\x00\x00\x00\x02\x00\x02\x00\x00\x02\x02\x84\x51\x00;")
    case("image_huge_header", EXIT_LIMIT, ["images[0]", "100000x100000"], png_data=huge_png())
    case("image_truncated", EXIT_IMAGE, "images[0]", png_data=png[:len(png) - 30])
    case("image_missing", EXIT_IO, "images[0].uri", setp(("images", 0, "uri"), "nothere.png"))
    case("image_uri_outside", EXIT_INVALID, ["images[0].uri", "leaves the scene's folder"],
         setp(("images", 0, "uri"), "../image_not_png/tex.png"))
    case("image_bufferview_oob", EXIT_INVALID, "images[0].bufferView",
         setp(("images", 0), {"bufferView": 9, "mimeType": "image/png"}))
    # Data-URI images ("glTF Embedded" files): the same decoder and limits as
    # files, and the URI itself checked before tinygltf's lenient decoder.
    b64 = base64.b64encode(png).decode()
    case("image_data_uri_empty", EXIT_IMAGE, "images[0].uri: data URI holds no image bytes",
         setp(("images", 0, "uri"), "data:image/png;base64,"))
    case("image_data_uri_bad_base64", EXIT_PARSE, "images[0].uri: malformed base64 data",
         setp(("images", 0, "uri"), "data:image/png;base64," + b64[:8] + "!" + b64[9:]))
    case("image_data_uri_wrong_mime", EXIT_UNSUPPORTED,
         "images[0].uri: data URI of media type 'image/gif' (only image/png and image/jpeg are supported)",
         setp(("images", 0, "uri"), "data:image/gif;base64," + b64))
    case("image_data_uri_not_base64", EXIT_INVALID, "images[0].uri: data URI is not base64",
         setp(("images", 0, "uri"), "data:image/png," + b64))
    case("image_data_uri_oversize", EXIT_LIMIT,
         "images[0]: 100000x100000 is over the image size limit (16384 per side, 67108864 pixels)",
         setp(("images", 0, "uri"), "data:image/png;base64," + base64.b64encode(huge_png()).decode()))
    case("image_data_uri_truncated", EXIT_IMAGE, "images[0]: cannot decode: PNG",
         setp(("images", 0, "uri"), "data:image/png;base64," + base64.b64encode(png[:len(png) - 30]).decode()))
    case("image_no_source", EXIT_INVALID, "images[0]: neither uri nor bufferView",
         setp(("images", 0), {"name": "nothing"}))

    # -- nodes and scenes
    case("node_child_oob", EXIT_INVALID, "nodes[1].children[0]", setp(("nodes", 1, "children"), [99]))
    case("node_own_child", EXIT_INVALID, "nodes[1].children[1]", setp(("nodes", 1, "children"), [4, 1]))
    case("node_two_parents", EXIT_INVALID, "nodes[1].children[1]",
         setp(("nodes", 1, "children"), [4, 3]))

    def cycle(d):
        d["nodes"] += [{"name": "a", "children": [6]}, {"name": "b", "children": [5]}]
    case("node_cycle", EXIT_INVALID, ["nodes[5]", "cycle"], cycle)

    def cycle3(d):
        d["nodes"][4]["children"] = [5]
        d["nodes"] += [{"name": "x", "children": [6]}, {"name": "y", "children": [4]}]
    case("node_cycle_via_tree", EXIT_INVALID, "nodes[6].children[0]", cycle3)

    case("node_transform_overflow", EXIT_INVALID, ["nodes[4]", "not finite"],
         lambda d: d["nodes"][4].update({"translation": [1e308, 0, 0], "scale": [1e308, 1, 1]}) or
         d["nodes"][1].update({"scale": [1e10, 1e10, 1e10]}))
    lights_path = ("extensions", "KHR_lights_punctual", "lights")
    # Found by fuzz_gltf: a finite double transform whose result is beyond
    # float range (the scene model stores floats).
    case("node_translation_float_range", EXIT_INVALID, ["nodes[4]", "out of float range"],
         setp(("nodes", 4, "translation"), [1e39, 0, 0]))
    case("camera_position_float_range", EXIT_INVALID, ["nodes[2]", "camera position", "out of float range"],
         setp(("nodes", 2, "translation"), [0, 0, 1e39]))
    case("light_intensity_float_range", EXIT_INVALID, "lights[0].intensity",
         setp(lights_path + (0, "intensity"), 1e39))
    case("camera_zfar_below_znear", EXIT_INVALID, "cameras[0].perspective.zfar",
         setp(("cameras", 0, "perspective", "zfar"), 0.05))
    def huge_no_camera(d):  # found by fuzz_gltf: the default camera's framing overflowed float
        d["nodes"][0]["children"] = [1, 3]
        del d["nodes"][2]["camera"]
        del d["cameras"]
        d["nodes"][4]["scale"] = [1e38, 1e38, 1e38]
    case("no_camera_scene_too_large", EXIT_LIMIT, ["cameras: none", "too large"], huge_no_camera)
    case("scene_oob", EXIT_INVALID, "scene: 4", setp(("scene",), 4))
    case("scene_node_oob", EXIT_INVALID, "scenes[0].nodes[1]", setp(("scenes", 0, "nodes"), [0, 12]))
    case("scene_root_is_child", EXIT_INVALID, "scenes[0].nodes[1]", setp(("scenes", 0, "nodes"), [0, 4]))
    case("camera_oob", EXIT_INVALID, "nodes[2].camera", setp(("nodes", 2, "camera"), 3))
    case("camera_yfov_invalid", EXIT_INVALID, "cameras[0].perspective.yfov",
         setp(("cameras", 0, "perspective", "yfov"), 4.0))
    case("camera_znear_zero", EXIT_INVALID, "cameras[0].perspective.znear",
         setp(("cameras", 0, "perspective", "znear"), 0))
    ortho = {"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}}
    def ortho_with(key, value):
        def f(d):
            d["cameras"][0] = copy.deepcopy(ortho)
            d["cameras"][0]["orthographic"][key] = value
        return f
    case("camera_ortho_ymag_zero", EXIT_INVALID, "cameras[0].orthographic.ymag", ortho_with("ymag", 0))
    case("camera_ortho_zfar_below_znear", EXIT_INVALID, "cameras[0].orthographic.zfar", ortho_with("zfar", 0.05))
    # The Blender render engine's camera extension (exporters/blender/PHOTONBRIDGE_blender.md).
    def cam_ext(value):
        def f(d):
            d["cameras"][0].setdefault("extensions", {})["PHOTONBRIDGE_blender"] = value
            d.setdefault("extensionsUsed", []).append("PHOTONBRIDGE_blender")
        return f
    case("camera_ext_not_object", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender: not an object",
         cam_ext([1, 2]))
    case("camera_ext_lens_string", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender.lens: not a number",
         cam_ext({"type": "PERSP", "lens": "50"}))
    case("camera_ext_lens_negative", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender.lens",
         cam_ext({"type": "PERSP", "lens": -50}))
    case("camera_ext_bad_fit", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender.sensorFit",
         cam_ext({"type": "PERSP", "sensorFit": "DIAGONAL"}))
    case("camera_ext_clip_end_below_start", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender.clipEnd",
         cam_ext({"type": "PERSP", "clipStart": 2, "clipEnd": 1}))
    case("camera_ext_bad_type", EXIT_UNSUPPORTED, "cameras[0].extensions.PHOTONBRIDGE_blender.type",
         cam_ext({"type": "CUSTOM"}))
    case("camera_ext_panorama_polynomial", EXIT_UNSUPPORTED,
         "cameras[0].extensions.PHOTONBRIDGE_blender.panoramaType: 'FISHEYE_LENS_POLYNOMIAL'",
         cam_ext({"type": "PANO", "panoramaType": "FISHEYE_LENS_POLYNOMIAL"}))
    case("camera_ext_panorama_type_number", EXIT_INVALID,
         "cameras[0].extensions.PHOTONBRIDGE_blender.panoramaType: not a string",
         cam_ext({"type": "PANO", "panoramaType": 1}))
    case("camera_ext_fisheye_fov_zero", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender.fisheyeFov: 0",
         cam_ext({"type": "PANO", "panoramaType": "FISHEYE_EQUIDISTANT", "fisheyeFov": 0}))
    case("camera_ext_latitude_range", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender.latitudeMax: 2",
         cam_ext({"type": "PANO", "panoramaType": "EQUIRECTANGULAR", "latitudeMax": 2}))
    case("camera_ext_longitude_range", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender.longitudeMin: -4",
         cam_ext({"type": "PANO", "panoramaType": "EQUIRECTANGULAR", "longitudeMin": -4}))
    # Depth of field (Blender's f-stop, focus distance, blades, rotation, ratio).
    case("camera_ext_fstop_negative", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender.apertureFstop: -2",
         cam_ext({"type": "PERSP", "apertureFstop": -2}))
    case("camera_ext_fstop_zero", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender.apertureFstop: 0",
         cam_ext({"type": "PERSP", "apertureFstop": 0}))
    case("camera_ext_fstop_string", EXIT_INVALID,
         "cameras[0].extensions.PHOTONBRIDGE_blender.apertureFstop: not a number",
         cam_ext({"type": "PERSP", "apertureFstop": "NaN"}))
    case("camera_ext_focus_negative", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender.focusDistance: -1",
         cam_ext({"type": "PERSP", "apertureFstop": 2.8, "focusDistance": -1}))
    case("camera_ext_focus_huge", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender.focusDistance: 1e+300",
         cam_ext({"type": "PERSP", "apertureFstop": 2.8, "focusDistance": 1e300}))
    case("camera_ext_blades_fraction", EXIT_INVALID,
         "cameras[0].extensions.PHOTONBRIDGE_blender.apertureBlades: 5.5 is not a whole number",
         cam_ext({"type": "PERSP", "apertureFstop": 2.8, "apertureBlades": 5.5}))
    case("camera_ext_ratio_zero", EXIT_INVALID, "cameras[0].extensions.PHOTONBRIDGE_blender.apertureRatio: 0",
         cam_ext({"type": "PERSP", "apertureFstop": 2.8, "apertureRatio": 0}))
    lights = ("extensions", "KHR_lights_punctual", "lights")
    case("light_oob", EXIT_INVALID, "nodes[3].extensions.KHR_lights_punctual.light",
         setp(("nodes", 3, "extensions", "KHR_lights_punctual", "light"), 5))
    case("light_index_huge", EXIT_INVALID, "nodes[3].extensions.KHR_lights_punctual.light",
         setp(("nodes", 3, "extensions", "KHR_lights_punctual", "light"), 1e20))
    case("light_negative_intensity", EXIT_INVALID, "lights[0].intensity",
         setp(lights + (0, "intensity"), -3))
    case("light_unknown_type", EXIT_INVALID, "lights[0].type", setp(lights + (0, "type"), "area"))

    def spot(d):
        d["nodes"][3]["extensions"]["KHR_lights_punctual"]["light"] = 1
        d["extensions"]["KHR_lights_punctual"]["lights"][1]["spot"]["innerConeAngle"] = 0.7
    case("light_spot_inner_ge_outer", EXIT_INVALID, "lights[1].spot", spot)

    # -- extensions and asset
    for i, ext in enumerate(("KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_texture_basisu")):
        def req(d, ext=ext):
            d["extensionsUsed"].append(ext)
            d["extensionsRequired"] = ["KHR_lights_punctual", ext]
        case("required_" + ext, EXIT_UNSUPPORTED, ["extensionsRequired[1]", ext], req)
    case("asset_version_1", EXIT_UNSUPPORTED, "asset.version", setp(("asset", "version"), "1.0"))
    case("asset_missing", EXIT_INVALID, "asset", lambda d: d.pop("asset"))

    # -- not glTF at all
    C.raw(B + "/not_json/not_json.gltf", b"this is not JSON {\n")
    C.expect(B + "/not_json/not_json.gltf", EXIT_PARSE, "not valid JSON")
    C.raw(B + "/empty_file/empty_file.gltf", b"")
    C.expect(B + "/empty_file/empty_file.gltf", EXIT_PARSE, "empty_file.gltf")
    C.raw(B + "/json_array/json_array.gltf", b'[{"asset": {"version": "2.0"}}]\n')
    C.expect(B + "/json_array/json_array.gltf", EXIT_PARSE, "top level")
    C.raw(B + "/json_truncated/json_truncated.gltf", to_json(doc0)[:200])
    C.expect(B + "/json_truncated/json_truncated.gltf", EXIT_PARSE, "not valid JSON")
    C.raw(B + "/json_deep_nesting/json_deep_nesting.gltf",
          b'{"asset": {"version": "2.0"}, "extras": ' + b"[" * 100000 + b"]" * 100000 + b"}\n")
    C.expect(B + "/json_deep_nesting/json_deep_nesting.gltf", EXIT_LIMIT, "JSON nested deeper than")

    # -- data URIs and external references
    d = copy.deepcopy(doc0)
    d["buffers"][0]["uri"] = ("data:application/octet-stream;base64," +
                              base64.b64encode(bin0).decode()[:-8] + "!!@@" + "AAAA")
    C.gltf(B, "base64_bad", d, None, png, code=EXIT_PARSE, expect=["buffers[0].uri", "base64"])
    d = copy.deepcopy(doc0)
    d["buffers"][0]["uri"] = ("data:application/octet-stream;base64," +
                              base64.b64encode(bin0[:120]).decode())
    C.gltf(B, "base64_short", d, None, png, code=EXIT_INVALID,
           expect=["buffers[0].uri", "120 bytes of data"])
    d = copy.deepcopy(doc0)
    d["buffers"][0]["uri"] = "data:application/octet-stream," + "A" * 8
    C.gltf(B, "data_uri_not_base64", d, None, png, code=EXIT_INVALID, expect="buffers[0].uri")
    # Found by fuzzing: a comma within 7 bytes of "data:" made the ";base64"
    # test read before the string (a C++ exception, not our message).
    d = copy.deepcopy(doc0)
    d["buffers"][0]["uri"] = "data:,AAAA"
    C.gltf(B, "data_uri_short_header", d, None, png, code=EXIT_INVALID,
           expect=["buffers[0].uri", "data URI is not base64"])
    d = copy.deepcopy(doc0)
    d["buffers"][0]["uri"] = "../../outside.bin"
    rel = C.gltf(B, "uri_outside", d, None, png, code=EXIT_INVALID,
                 expect=["buffers[0].uri", "leaves the scene's folder"])
    C.expect(rel, EXIT_OK, "triangles=%d" % BASE_TRIANGLES, "--allow-external-files")
    for name, uri, code, msg in (
            ("uri_absolute", "/tmp/photonbridge-corpus-absent.bin", EXIT_INVALID, "absolute path"),
            ("uri_http", "http://example.com/scene.bin", EXIT_UNSUPPORTED, "only relative"),
            ("uri_file_scheme", "file:///etc/passwd", EXIT_UNSUPPORTED, "only relative"),
            ("uri_percent_bad", "uri%zzpercent.bin", EXIT_INVALID, "bad percent-encoding"),
            ("uri_percent_nul", "uri%00.bin", EXIT_INVALID, "bad percent-encoding"),
            ("uri_empty", "", EXIT_INVALID, "empty uri"),
            ("uri_directory", "sub", EXIT_IO, "not a regular file")):
        d = copy.deepcopy(doc0)
        d["buffers"][0]["uri"] = uri
        C.gltf(B, name, d, None, png, code=code, expect=["buffers[0].uri", msg])
    C.raw(B + "/uri_directory/sub/placeholder.txt", b"buffers[0].uri names this folder\n")

    # -- deep node chain: 5000 nested nodes
    d = copy.deepcopy(doc0)
    n0 = len(d["nodes"])
    d["nodes"][4]["children"] = [n0]
    chain = 5000
    for i in range(chain):
        d["nodes"].append({"children": [n0 + i + 1]} if i + 1 < chain else {"mesh": 0})
    C.gltf(B, "node_chain_5000", d, bin0, png, code=EXIT_LIMIT, expect=["nodes[", "deeper than"])

    # -- GLB container
    gdoc, gbin = glb_doc(doc0, bin0, png)
    good = make_glb(gdoc, gbin)
    jlen = struct.unpack_from("<I", good, 12)[0]
    bin_off = 20 + jlen  # offset of the BIN chunk header

    def patch(data, off, fmt, *vals):
        b = bytearray(data)
        struct.pack_into(fmt, b, off, *vals)
        return bytes(b)

    C.glb(B, "glb_bad_magic", b"glTX" + good[4:], EXIT_PARSE, "not valid JSON")
    C.glb(B, "glb_version_1", patch(good, 4, "<I", 1), EXIT_UNSUPPORTED, ["GLB header", "version 1"])
    C.glb(B, "glb_length_mismatch", patch(good, 8, "<I", len(good) + 100), EXIT_PARSE,
          ["GLB header", "declared length"])
    C.glb(B, "glb_truncated_header", good[:10], EXIT_PARSE, ["GLB header", "shorter than"])
    C.glb(B, "glb_truncated_file", patch(good[:len(good) - 64], 8, "<I", len(good) - 64), EXIT_PARSE,
          ["GLB chunk 1", "exceeds"])
    C.glb(B, "glb_chunk_past_end", patch(good, 12, "<I", 1 << 31), EXIT_PARSE, ["GLB chunk 0", "exceeds"])
    C.glb(B, "glb_chunk_not_mult4", patch(good, bin_off, "<I", len(good) - bin_off - 8 - 2), EXIT_PARSE,
          ["GLB chunk 1", "multiple of 4"])
    C.glb(B, "glb_first_chunk_bin", patch(good, 16, "<I", 0x004E4942), EXIT_PARSE,
          ["GLB chunk 0", "expected JSON"])
    C.glb(B, "glb_second_chunk_not_bin", patch(good, bin_off + 4, "<I", 0x12345678), EXIT_PARSE,
          ["GLB chunk 1", "expected BIN"])
    C.glb(B, "glb_chunk_header_truncated", patch(good + b"\0\0\0\0", 8, "<I", len(good) + 4), EXIT_PARSE,
          ["GLB chunk 2", "truncated chunk header"])
    C.glb(B, "glb_no_chunks", b"glTF" + struct.pack("<II", 2, 12), EXIT_PARSE, "GLB")
    # The fuzzing finding that made stb_image add an offset to a null pointer
    # (an empty IDAT chunk with a wrong CRC, then garbage): the regression
    # input of fuzz_gltf, byte for byte.
    C.glb(B, "image_png_empty_idat", read_bytes(os.path.join(HERE, "..", "fuzz", "regressions", "gltf",
                                                             "stb_png_idat_null.glb")),
          EXIT_IMAGE, "images[0]: cannot decode: PNG data: invalid chunk checksum")
    short_doc = copy.deepcopy(gdoc)
    short_doc["buffers"][0]["byteLength"] = len(gbin) + 400
    C.glb(B, "glb_bin_short", make_glb(short_doc, gbin), EXIT_INVALID, "buffers[0]")
    C.glb(B, "glb_no_bin", make_glb(gdoc, None), EXIT_INVALID, "buffers[0]")
    C.glb(B, "glb_json_garbage", make_glb(gdoc, gbin)[:20] + b"\xff" * jlen + good[20 + jlen:],
          EXIT_PARSE, "not valid JSON")
    img_doc = copy.deepcopy(gdoc)
    img_doc["bufferViews"][-1]["byteOffset"] = len(gbin) - 4
    C.glb(B, "glb_image_view_past_buffer", make_glb(img_doc, gbin), EXIT_INVALID,
          ["bufferViews[4]", "exceeds buffers[0]"])

    # -- animations: keys in a second, data-URI buffer
    def anim(times, values, comps, path="translation", interp=None, node=1, sampler=0):
        def f(d):
            blob = f32(*times) + b"".join(f32(*v) for v in values)
            d["buffers"].append({"byteLength": len(blob),
                                 "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()})
            nb, nv, na = len(d["buffers"]) - 1, len(d["bufferViews"]), len(d["accessors"])
            d["bufferViews"] += [{"buffer": nb, "byteOffset": 0, "byteLength": 4 * len(times)},
                                 {"buffer": nb, "byteOffset": 4 * len(times), "byteLength": 4 * comps * len(values)}]
            d["accessors"] += [{"bufferView": nv, "componentType": FLOAT, "count": len(times), "type": "SCALAR"},
                               {"bufferView": nv + 1, "componentType": FLOAT, "count": len(values),
                                "type": {3: "VEC3", 4: "VEC4"}[comps]}]
            s = {"input": na, "output": na + 1}
            if interp:
                s["interpolation"] = interp
            d["animations"] = [{"samplers": [s], "channels": [{"sampler": sampler,
                                                               "target": {"node": node, "path": path}}]}]
        return f

    V3 = [(0, 0, 0), (1, 0, 0), (2, 0, 0)]
    case("anim_times_decrease", EXIT_INVALID, "animations[0].samplers[0].input: times decrease at key 2",
         anim([0, 2, 1], V3, 3))
    case("anim_cubic_count", EXIT_INVALID,
         ["animations[0].samplers[0].output (translation)", "CUBICSPLINE with 2 keys needs 6"],
         anim([0, 1], V3[:2], 3, interp="CUBICSPLINE"))
    case("anim_rotation_vec3", EXIT_INVALID, "animations[0].samplers[0].output (rotation) needs 4",
         anim([0, 1, 2], V3, 3, path="rotation"))
    case("anim_node_oob", EXIT_INVALID, "animations[0].channels[0].target.node: 99 does not exist",
         anim([0, 1, 2], V3, 3, node=99))
    case("anim_sampler_oob", EXIT_INVALID, "animations[0].channels[0].sampler: 4 does not exist",
         anim([0, 1, 2], V3, 3, sampler=4))
    case("anim_interpolation_bogus", EXIT_INVALID, "animations[0].samplers[0].interpolation: 'SMOOTH'",
         anim([0, 1, 2], V3, 3, interp="SMOOTH"))
    # Keys of accessors without a bufferView (zeros: finite, non-decreasing)
    # cost the file nothing: 2^31 of them were checked one by one and then
    # allocated (8 GB of times, 24 GB of values): bounded like vertices.
    def anim_no_data(d):
        anim([0, 1, 2], V3, 3)(d)
        for a in d["accessors"][-2:]:
            del a["bufferView"]
            a["count"] = 1 << 31
    case("anim_keys_without_data", EXIT_LIMIT,
         "animations[0].samplers[0].input: 2147483648 keys is over the limit of 201326592", anim_no_data)

    # -- skins (glTF 2.0 3.7.3; src/scene/skin.c): the quad of nodes[1]
    # skinned to joints nodes[5] and nodes[6] (a child of 5).
    def bad_skin(**kw):
        def f(d):
            skinned(d, **kw)
        return f
    case("skin_joint_node_oob", EXIT_INVALID, "skins[0].joints[1]: node 99 does not exist",
         bad_skin(joints=[5, 99]))
    case("skin_joint_twice", EXIT_INVALID, "skins[0].joints[1]: node 5 is already a joint of this skin",
         bad_skin(joints=[5, 5]))
    case("skin_joints_empty", EXIT_INVALID, "skins[0].joints: empty", bad_skin(joints=[]))
    case("skin_joints_missing", EXIT_INVALID, "skins[0].joints: missing", bad_skin(joints=None))
    case("skin_ibm_short", EXIT_INVALID, ["skins[0].inverseBindMatrices", "has 1 matrices, the skin has 2 joints"],
         bad_skin(ibm_count=1))
    case("skin_ibm_vec4", EXIT_INVALID, ["has 4 components", "skins[0].inverseBindMatrices needs 16"],
         bad_skin(ibm_type="VEC4"))
    case("skin_joint_index_oob", EXIT_INVALID,
         ["meshes[0].primitives[0].attributes.JOINTS_0", "element 2 names joint 7, the skin has 2"],
         bad_skin(joints0=[(0, 0, 0, 0), (1, 0, 0, 0), (7, 0, 0, 0), (1, 0, 0, 0)]))
    case("skin_weight_negative", EXIT_INVALID,
         ["meshes[0].primitives[0].attributes.WEIGHTS_0", "element 1 has weight -0.5"],
         bad_skin(weights0=[(1, 0, 0, 0), (-0.5, 1.5, 0, 0), (1, 0, 0, 0), (0, 1, 0, 0)]))
    case("skin_weights_without_joints", EXIT_INVALID,
         "meshes[0].primitives[0].attributes: WEIGHTS_0 without JOINTS_0", bad_skin(drop="JOINTS_0"))
    case("skin_joints_count_mismatch", EXIT_INVALID,
         ["meshes[0].primitives[0].attributes.JOINTS_0", "has 3 elements, POSITION has 4"], bad_skin(joints_count=3))
    case("skin_weights_not_normalized", EXIT_INVALID, "integer WEIGHTS_0 must be normalized",
         bad_skin(weights_ubyte=True, normalized=False))
    case("skin_oob", EXIT_INVALID, "nodes[1].skin: 4 does not exist (1 skins)", bad_skin(node_skin=4))

    # -- morph targets (glTF 2.0 3.7.2.2; src/scene/morph.c): one target on
    # the quad of mesh 0 (corners 2 and 3 lifted).
    def bad_morph(**kw):
        def f(d):
            morphed(d, **kw)
        return f
    case("morph_target_count_mismatch", EXIT_INVALID,
         ["meshes[0].primitives[0].targets[0].POSITION", "has 3 elements, POSITION has 4"], bad_morph(count=3))
    case("morph_target_vec2", EXIT_INVALID, ["has 2 components", "meshes[0].primitives[0].targets[0].POSITION needs 3"],
         bad_morph(type="VEC2"))
    case("morph_target_nan", EXIT_INVALID, ["element 2 is not finite", "targets[0].POSITION"], bad_morph(nan=True))
    case("morph_target_attribute_oob", EXIT_INVALID, "meshes[0].primitives[0].targets[0].NORMAL: accessor 99 does not exist",
         bad_morph(normal=99))
    case("morph_targets_differ", EXIT_INVALID,
         "meshes[0].primitives[1].targets: 0 targets, primitives[0] has 1 (every primitive of a mesh needs the same)",
         bad_morph(second_primitive=True))
    case("morph_mesh_weights_length", EXIT_INVALID, "meshes[0].weights: 2 weights for 1 morph targets",
         bad_morph(mesh_weights=[0.5, 0.5]))
    case("morph_node_weights_length", EXIT_INVALID, "nodes[1].weights: 3 weights for the 1 morph targets of meshes[0]",
         bad_morph(node_weights=[0, 0, 1]))
    case("morph_node_weights_no_mesh", EXIT_INVALID, "nodes[2].weights: the node has no mesh to morph",
         bad_morph(camera_weights=[1]))
    case("morph_weights_not_numbers", EXIT_INVALID, 'meshes[0].weights[0]: "half" is not a number',
         bad_morph(mesh_weights=["half"]))
    case("morph_weights_anim_count", EXIT_INVALID,
         ["animations[0].samplers[0].output (weights)", "3 keys for its node's morph targets needs 3"],
         bad_morph(anim_values=[0, 1]))


def blender_doc():
    """The base scene with the PHOTONBRIDGE_blender extension: a world with an
    environment map (sky.hdr), an opaque film, the lamp as a soft point light
    (replacing its KHR light), and an area light on a node of its own."""
    doc, blob = base()
    doc["extensionsUsed"].append("PHOTONBRIDGE_blender")
    doc["extensions"]["PHOTONBRIDGE_blender"] = {
        "version": 1, "blender": "3.4.1", "render": {"filmTransparent": False},
        "world": {"color": [0.05, 0.05, 0.05], "strength": 1.0,
                  "environment": {"uri": "sky.hdr", "projection": "EQUIRECTANGULAR",
                                  "rotation": [0.0, 0.0, 1.0], "strength": 2.0}}}
    doc["nodes"][3]["extensions"]["PHOTONBRIDGE_blender"] = {
        "light": {"type": "POINT", "power": 100.0, "radius": 0.1, "color": [1.0, 0.9, 0.8]}}
    doc["nodes"].append({"name": "softbox", "translation": [0, 2, 0], "rotation": [-0.70710678, 0, 0, 0.70710678],
                         "extensions": {"PHOTONBRIDGE_blender": {"light": {
                             "type": "AREA", "power": 200.0, "shape": "RECTANGLE", "size": 1.0, "sizeY": 0.5,
                             "spread": 1.2}}}})
    doc["nodes"][0]["children"].append(len(doc["nodes"]) - 1)
    return doc, blob


def blender_cases(C, png):
    """PHOTONBRIDGE_blender's lights and world: what loads, and every bad value
    named by its JSON path (exporters/blender/PHOTONBRIDGE_blender.md)."""
    doc0, bin0 = blender_doc()
    hdr = make_hdr(8, 4)
    X = "PHOTONBRIDGE_blender"
    W = ("extensions", X, "world")
    L = ("nodes", 3, "extensions", X, "light")
    A = ("nodes", 5, "extensions", X, "light")

    def write(group, name, d, code, expect, sky=hdr):
        rel = C.gltf(group, name, d, bin0, png, code=code, expect=expect)
        if sky is not None:
            C.raw(os.path.dirname(rel) + "/sky.hdr", sky)

    def case(name, code, expect, path=None, value=None, sky=hdr, edit=None):
        d = copy.deepcopy(doc0)
        if path is not None:
            o = d
            for k in path[:-1]:
                o = o[k]
            if value is DELETE:
                del o[path[-1]]
            else:
                o[path[-1]] = value
        if edit:
            edit(d)
        write("broken" if code else "valid", name, d, code, expect, sky)

    # Valid: two lights (the KHR lamp replaced, never counted twice), the map.
    case("blender_lights_world", EXIT_OK, ["triangles=%d" % BASE_TRIANGLES, 'has="type": "area"',
                                           'has="map": "sky.hdr"', 'has="radius": 0.1', 'has="film_opaque": true',
                                           'has="blender_units": true'])
    case("blender_film_transparent", EXIT_OK, ['has="film_opaque": false'], W[:-1] + ("render", "filmTransparent"),
         True)
    # Blender's colour management: the display images' defaults (info names
    # the view they use; tests/scene_view.py renders with them).
    CM = W[:-1] + ("colorManagement",)
    case("blender_color_management", EXIT_OK, ['has=sRGB / Standard, look None, exposure 1.5, gamma 1'],
         CM, {"display": "sRGB", "view": "Standard", "look": "None", "exposure": 1.5, "gamma": 1.0})
    case("blender_color_management_exposure", EXIT_INVALID,
         "extensions.PHOTONBRIDGE_blender.colorManagement.exposure: 40 is not in [-32, 32]", CM, {"exposure": 40.0})
    case("blender_color_management_gamma_zero", EXIT_INVALID,
         "extensions.PHOTONBRIDGE_blender.colorManagement.gamma: 0 is not in (0, 5]", CM, {"gamma": 0.0})
    case("blender_color_management_view_number", EXIT_INVALID,
         "extensions.PHOTONBRIDGE_blender.colorManagement.view: not a string", CM, {"view": 3})
    case("blender_color_management_look_long", EXIT_INVALID,
         "extensions.PHOTONBRIDGE_blender.colorManagement.look: a name of 80 bytes (at most 63)", CM,
         {"look": "L" * 80})
    case("blender_color_management_not_object", EXIT_INVALID,
         "extensions.PHOTONBRIDGE_blender.colorManagement: not an object", CM, "Filmic")
    d = copy.deepcopy(doc0)
    d["extensions"][X]["world"]["environment"]["uri"] = "sky.png"
    rel = C.gltf("valid", "blender_world_png", d, bin0, png, code=EXIT_OK, expect=['has="map_width": 4'])
    C.raw(os.path.dirname(rel) + "/sky.png", make_png(4, 2, [[200, 180, 160, 255] * 4, [40, 40, 40, 255] * 4]))
    # A JPEG map (the writer copies a .jpg Environment Texture as it is): the
    # same 4 x 2 picture, written by Pillow 9.4 (quality 95, no chroma
    # subsampling, optimised Huffman tables); it decodes to (201, 180, 161)
    # over (39, 39, 39).
    d["extensions"][X]["world"]["environment"]["uri"] = "sky.jpg"
    rel = C.gltf("valid", "blender_world_jpg", d, bin0, png, code=EXIT_OK, expect=['has="map_width": 4'])
    C.raw(os.path.dirname(rel) + "/sky.jpg", base64.b64decode(
        "/9j/4AAQSkZJRgABAQAAAQABAAD/2wBDAAIBAQEBAQIBAQECAgICAgQDAgICAgUEBAMEBgUGBgYFBgYGBwkIBgcJBwYGCAsICQoKCgoK"
        "BggLDAsKDAkKCgr/2wBDAQICAgICAgUDAwUKBwYHCgoKCgoKCgoKCgoKCgoKCgoKCgoKCgoKCgoKCgoKCgoKCgoKCgoKCgoKCgoKCgoK"
        "Cgr/wAARCAACAAQDAREAAhEBAxEB/8QAFAABAAAAAAAAAAAAAAAAAAAACf/EABsQAAAHAQAAAAAAAAAAAAAAAAAFBwgYWJbT/8QAFAEB"
        "AAAAAAAAAAAAAAAAAAAAA//EABkRAAEFAAAAAAAAAAAAAAAAAAEABBRSkf/aAAwDAQACEQMRAD8AOeZDvLUqRuTDsAjNqDAmkOLnSv/Z"))
    # Broken: the version, the world and its map, each light value.
    case("blender_version_2", EXIT_UNSUPPORTED, "extensions.PHOTONBRIDGE_blender.version: 2",
         ("extensions", X, "version"), 2)
    case("blender_version_missing", EXIT_INVALID, "extensions.PHOTONBRIDGE_blender.version: missing",
         ("extensions", X, "version"), DELETE)
    case("blender_world_hdr_missing", EXIT_IO, ["world.environment.uri", "nothere.hdr"],
         W + ("environment", "uri"), "nothere.hdr")
    case("blender_world_hdr_truncated", EXIT_IMAGE, ["world.environment.uri", "sky.hdr", "scanline"],
         sky=hdr[:len(hdr) - 20])
    case("blender_world_hdr_zero_width", EXIT_IMAGE, ["world.environment.uri", "0 x 4 pixels"],
         sky=make_hdr(0, 4, header_res=b"-Y 4 +X 0"))
    case("blender_world_hdr_not_hdr", EXIT_IMAGE, ["world.environment.uri", "not a Radiance HDR"], sky=b"P6 4 4 255\n")
    case("blender_world_hdr_huge", EXIT_LIMIT, ["world.environment.uri", "exceeds the limit"],
         sky=make_hdr(1, 1, header_res=b"-Y 100000 +X 100000"))
    case("blender_world_hdr_outside", EXIT_INVALID, ["world.environment.uri", "leaves the scene's folder"],
         W + ("environment", "uri"), "../../outside.bin")
    d = copy.deepcopy(doc0)
    d["extensions"][X]["world"]["environment"]["uri"] = "sky.tga"
    rel = C.gltf("broken", "blender_world_map_tga", d, bin0, png, code=EXIT_UNSUPPORTED,
                 expect=["world.environment.uri", "'sky.tga': not a .hdr, .exr, .png or .jpg file"])
    C.raw(os.path.dirname(rel) + "/sky.tga", b"\0\0\2" + b"\0" * 15)
    case("blender_world_projection", EXIT_UNSUPPORTED, "world.environment.projection: 'MIRROR_BALL'",
         W + ("environment", "projection"), "MIRROR_BALL")
    case("blender_world_strength_negative", EXIT_INVALID, "extensions.PHOTONBRIDGE_blender.world.strength: -1",
         W + ("strength",), -1.0)
    case("blender_world_color_string", EXIT_INVALID, "extensions.PHOTONBRIDGE_blender.world.color: not an array",
         W + ("color",), "grey")
    case("blender_world_rotation_short", EXIT_INVALID, "world.environment.rotation: not an array of 3",
         W + ("environment", "rotation"), [0.0, 1.0])
    case("blender_world_not_object", EXIT_INVALID, "extensions.PHOTONBRIDGE_blender.world: not an object", W, [1])
    case("blender_light_type", EXIT_INVALID, "nodes[3].extensions.PHOTONBRIDGE_blender.light.type: 'HEMI'",
         L + ("type",), "HEMI")
    case("blender_light_type_missing", EXIT_INVALID, "nodes[3].extensions.PHOTONBRIDGE_blender.light.type: missing",
         L + ("type",), DELETE)
    case("blender_light_power_negative", EXIT_INVALID, "nodes[3].extensions.PHOTONBRIDGE_blender.light.power: -5",
         L + ("power",), -5.0)
    case("blender_light_power_overflow", EXIT_INVALID,
         "nodes[3].extensions.PHOTONBRIDGE_blender.light.power", L + ("power",), 1e300)
    case("blender_light_color_negative", EXIT_INVALID, "nodes[3].extensions.PHOTONBRIDGE_blender.light.color[1]",
         L + ("color",), [1.0, -0.5, 1.0])
    case("blender_light_radius_bool", EXIT_INVALID, "nodes[3].extensions.PHOTONBRIDGE_blender.light.radius: not a number",
         L + ("radius",), True)
    case("blender_area_zero_size", EXIT_INVALID, ["nodes[5].extensions.PHOTONBRIDGE_blender.light", "zero area"],
         A + ("size",), 0.0)
    case("blender_area_shape", EXIT_INVALID, "nodes[5].extensions.PHOTONBRIDGE_blender.light.shape: 'STAR'",
         A + ("shape",), "STAR")
    case("blender_area_spread_zero", EXIT_INVALID, "nodes[5].extensions.PHOTONBRIDGE_blender.light.spread: 0",
         A + ("spread",), 0.0)
    case("blender_spot_blend", EXIT_INVALID, "nodes[3].extensions.PHOTONBRIDGE_blender.light.spotBlend: 2",
         L + ("spotBlend",), 2.0)
    case("blender_light_model", EXIT_INVALID,
         "nodes[3].extensions.PHOTONBRIDGE_blender.light.model: 'cycles5' is not cycles3 or cycles4", L + ("model",),
         "cycles5")
    case("blender_sun_angle_pi", EXIT_INVALID, "nodes[3].extensions.PHOTONBRIDGE_blender.light.angle",
         L, {"type": "SUN", "angle": 3.5})
    case("blender_light_not_object", EXIT_INVALID, "nodes[3].extensions.PHOTONBRIDGE_blender.light: not an object",
         L, "POINT")
    case("blender_light_cast_shadow_string", EXIT_INVALID,
         "nodes[3].extensions.PHOTONBRIDGE_blender.light.castShadow: not true or false", L + ("castShadow",), "yes")
    # Python's json writes NaN and Infinity, which JSON does not have, and a
    # literal beyond double range is no number either: the error still names
    # the value's path.
    for name, token in (("blender_light_power_nan", "NaN"), ("blender_world_strength_infinity", "-Infinity"),
                        ("blender_light_power_1e999", "1e999")):
        d = copy.deepcopy(doc0)
        key = "power" if "power" in name else "strength"
        (d["nodes"][3]["extensions"][X]["light"] if key == "power" else d["extensions"][X]["world"])[key] = 12345.678
        rel = C.gltf("broken", name, d, bin0, png, code=EXIT_INVALID,
                     expect=[("nodes[3].extensions.PHOTONBRIDGE_blender.light.power" if key == "power" else
                              "extensions.PHOTONBRIDGE_blender.world.strength") + ": " + token, "not a finite number"])
        p = C.path(rel)
        with open(p, "rb") as f:
            text = f.read()
        with open(p, "wb") as f:
            f.write(text.replace(b"12345.678", token.encode()))
        C.raw(os.path.dirname(rel) + "/sky.hdr", hdr)


def valid_cases(C, png):
    V = "valid"
    doc0, bin0 = base()
    C.gltf(V, "base", doc0, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    gdoc, gbin = glb_doc(doc0, bin0, png)
    C.glb(V, "base_glb", make_glb(gdoc, gbin), EXIT_OK, "triangles=%d" % BASE_TRIANGLES)
    for ct, name in ((UBYTE, "u8"), (UINT, "u32")):
        d, b = base(index_type=ct)
        C.gltf(V, "indices_" + name, d, b, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    # Non-indexed: 6 vertices, 2 triangles per quad.
    six = [POSITIONS[i] for i in INDICES]
    d, b = base(positions=six, indexed=False)
    C.gltf(V, "non_indexed", d, b, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    # Strip 0 1 3 2 and fan 0 1 2 3 cover the quad with 2 triangles each.
    d, b = base(indices=[0, 1, 3, 2], mode=5)
    C.gltf(V, "triangle_strip", d, b, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    d, b = base(indices=[0, 1, 2, 3], mode=6)
    C.gltf(V, "triangle_fan", d, b, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    d, b = base(normals=False)
    C.gltf(V, "no_normals", d, b, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    d = copy.deepcopy(doc0)
    d["nodes"][4] = {"name": "quad2", "mesh": 1,
                     "matrix": [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, -1, 1]}
    C.gltf(V, "matrix_node", d, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    d = copy.deepcopy(doc0)
    d["nodes"][4]["scale"] = [-2, 2, 2]
    C.gltf(V, "negative_scale", d, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    d = copy.deepcopy(doc0)
    d["nodes"][0]["children"] = [1, 3]
    del d["nodes"][2]["camera"]
    del d["cameras"]
    C.gltf(V, "no_camera", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, "warn=default camera"])
    d = copy.deepcopy(doc0)
    d["materials"][1]["extensions"] = {"KHR_materials_iridescence": {
        "iridescenceFactor": 1, "iridescenceIor": 1.33, "iridescenceThicknessMaximum": 450}}
    C.gltf(V, "iridescence_plain", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES,
                   "warn=materials[1].extensions.KHR_materials_iridescence: iridescenceFactor 1: thin-film"])
    d = copy.deepcopy(doc0)
    d["meshes"][1]["primitives"].append({"attributes": {"POSITION": 0}, "mode": 0})
    C.gltf(V, "points_and_triangles", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, "warn=meshes[1].primitives[1]: mode 0 (POINTS) skipped"])
    d = copy.deepcopy(doc0)
    d["meshes"][0]["primitives"].append({"attributes": {"POSITION": 0}, "indices": 3, "mode": 1})
    C.gltf(V, "lines_and_triangles", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, "warn=mode 1 (LINES) skipped"])
    d = copy.deepcopy(doc0)
    d["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(bin0).decode()
    C.gltf(V, "data_uri_buffer", d, None, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    d = copy.deepcopy(doc0)
    d["buffers"][0]["uri"] = "percent%2Dencoded.bin"
    C.raw(V + "/percent_uri/percent-encoded.bin", bin0)
    C.gltf(V, "percent_uri", d, None, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    d = copy.deepcopy(doc0)
    d["cameras"][0] = {"type": "orthographic",
                       "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}}
    C.gltf(V, "orthographic_camera", d, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    d = copy.deepcopy(doc0)
    del d["scene"]
    del d["scenes"]
    C.gltf(V, "no_scenes", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, "warn=scenes: none"])
    d = copy.deepcopy(doc0)
    d["accessors"][2].update({"componentType": UBYTE, "normalized": True})
    d["bufferViews"][2]["byteStride"] = 8
    C.gltf(V, "strided_texcoord", d, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    d, b = base(indices=[0, 1, 2, 0, 2, 2])
    C.gltf(V, "degenerate_triangle", d, b, png, code=EXIT_OK,
           expect=["triangles=2", "warn=degenerate triangles"])
    # POSITION without a bufferView reads as zeros: the primitive is all
    # degenerate and skipped with a warning; the rest of the scene loads.
    d = copy.deepcopy(doc0)
    d["accessors"].append({"componentType": FLOAT, "count": 3000, "type": "VEC3"})
    d["meshes"][1]["primitives"].append({"attributes": {"POSITION": len(d["accessors"]) - 1}})
    C.gltf(V, "position_without_bufferview", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, "warn=POSITION has no bufferView (all zeros): primitive skipped"])
    # The material extension: defaults only, a texture link, unknown members
    # (ignored), and the writer's warnings (passed on).
    d = copy.deepcopy(doc0)
    d["extensionsUsed"].append("PHOTONBRIDGE_blender")
    d["materials"][0]["extensions"] = {"PHOTONBRIDGE_blender": {
        "model": "principled", "futureMember": {"x": 1},
        "textures": {"baseColor": {"index": 0, "texCoord": 0}, "roughness": {"index": 0, "channel": "G"}},
        "warnings": ["Mix Shader: only its first input is written"]}}
    d["materials"][1]["extensions"] = {"PHOTONBRIDGE_blender": {"model": "diffuse", "diffuse": {"roughness": 0.5}}}
    C.gltf(V, "blender_materials", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, "warn=the Blender writer says: Mix Shader"])
    # Principled v2: every member, textures on its colour, scalar and coat
    # normal inputs, the Blender version (G2) and the v1 subsurface names
    # read version-neutrally (RANDOM_WALK_SKIN = 3.4's RANDOM_WALK).
    d = copy.deepcopy(doc0)
    d["extensionsUsed"].append("PHOTONBRIDGE_blender")
    d["extensions"] = dict(d.get("extensions", {}), PHOTONBRIDGE_blender={"version": 1, "blender": "4.5.1 LTS"})
    d["materials"][0]["extensions"] = {"PHOTONBRIDGE_blender": {
        "model": "principled2", "principled2": {
            "distribution": "MULTI_GGX", "subsurfaceMethod": "RANDOM_WALK_SKIN", "baseColor": [0.6, 0.3, 0.2, 1.0],
            "metallic": 0.25, "roughness": 0.35, "ior": 1.62, "alpha": 0.9, "diffuseRoughness": 0.2,
            "subsurfaceWeight": 0.0, "subsurfaceRadius": [0.5, 0.25, 0.125], "subsurfaceScale": 0.1,
            "subsurfaceIor": 1.33, "subsurfaceAnisotropy": 0.4, "specularIorLevel": 0.3,
            "specularTint": [0.9, 0.7, 0.5, 1.0], "anisotropic": 0.5, "anisotropicRotation": 0.125,
            "transmissionWeight": 0.2, "coatWeight": 0.4, "coatRoughness": 0.15, "coatIor": 1.7,
            "coatTint": [0.8, 0.9, 1.0, 1.0], "sheenWeight": 0.6, "sheenRoughness": 0.3,
            "sheenTint": [1.0, 0.5, 0.8, 1.0], "emissionColor": [1.0, 0.5, 0.25, 1.0], "emissionStrength": 3.0,
            "thinFilmThickness": 250.0, "thinFilmIor": 1.45},
        "textures": {"coatTint": {"index": 0}, "coatWeight": {"index": 0, "channel": "R"},
                     "coatNormal": {"index": 0, "strength": 0.5}}}}
    d["materials"][1]["extensions"] = {"PHOTONBRIDGE_blender": {
        "model": "principled", "principled": {"subsurfaceMethod": "RANDOM_WALK_SKIN"}}}
    C.gltf(V, "blender_principled2", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, 'has="model": "principled2"'])
    # Mix and Add Shaders of two BSDFs: a Diffuse and a Glossy by a Layer
    # Weight, a Principled v2 and a Metallic BSDF by a texture, an Add Shader.
    d = copy.deepcopy(doc0)
    d["extensionsUsed"].append("PHOTONBRIDGE_blender")
    d["extensions"] = dict(d.get("extensions", {}), PHOTONBRIDGE_blender={"version": 1, "blender": "4.5.1 LTS"})
    d["materials"][0]["extensions"] = {"PHOTONBRIDGE_blender": {
        "model": "diffuse", "diffuse": {"color": [0.8, 0.3, 0.1, 1.0]},
        "mix": {"facFrom": "layerFresnel", "blend": 0.3,
                "shader": {"model": "glossy", "glossy": {"roughness": 0.2, "distribution": "GGX"}}}}}
    d["materials"][1]["extensions"] = {"PHOTONBRIDGE_blender": {
        "model": "principled2", "principled2": {"roughness": 0.7},
        "mix": {"fac": 0.5, "textures": {"fac": {"index": 0, "channel": "G"}},
                "shader": {"model": "metallic", "metallic": {"roughness": 0.25}}}}}
    C.gltf(V, "blender_mix", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, 'has="model": "metallic"'])
    # A Blender texture link is a glTF textureInfo: its uv set and
    # KHR_texture_transform go the glTF textures' way (a second pb_texture
    # for the transformed read of the same image).
    d = copy.deepcopy(doc0)
    d["extensionsUsed"] += ["PHOTONBRIDGE_blender", "KHR_texture_transform"]
    d["materials"][0]["extensions"] = {"PHOTONBRIDGE_blender": {
        "model": "principled",
        "textures": {"roughness": {"index": 0, "texCoord": 1, "channel": "G", "extensions": {
            "KHR_texture_transform": {"offset": [0.5, 0.0], "scale": [2.0, 2.0]}}}}}}
    C.gltf(V, "blender_texture_transform", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, 'has="texcoord": 1', 'has="uv_transform"',
                   "warn=its material reads TEXCOORD_1, which the primitive lacks"])
    # Images as data URIs, PNG and JPEG (the loader decodes them like files).
    d = copy.deepcopy(doc0)
    d["images"][0]["uri"] = "data:image/png;base64," + base64.b64encode(png).decode()
    C.gltf(V, "image_data_uri_png", d, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    d = copy.deepcopy(doc0)
    d["images"][0]["uri"] = "data:image/jpeg;base64," + base64.b64encode(JPEG_2X2).decode()
    C.gltf(V, "image_data_uri_jpeg", d, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    d = copy.deepcopy(doc0)
    d["extensionsUsed"].append("KHR_draco_mesh_compression")
    C.gltf(V, "draco_used_not_required", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, "warn=KHR_draco_mesh_compression"])
    # Three camera nodes that share the name "Camera" (glTF does not require
    # unique names): `--camera Camera` is refused, `--camera 2` picks the
    # third (tests/cli.cmake).
    d = copy.deepcopy(doc0)
    d["nodes"][2]["name"] = "Camera"
    for z in (7, 9):
        d["nodes"].append({"name": "Camera", "camera": 0, "translation": [0, 0, z]})
        d["nodes"][0]["children"].append(len(d["nodes"]) - 1)
    C.gltf(V, "duplicate_camera_names", d, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    # A sparse POSITION (one vertex moved) and a sparse accessor without a
    # bufferView (zeros, then the sparse values) as TEXCOORD_0.
    d = copy.deepcopy(doc0)
    iv, vv = add_buffer(d, struct.pack("<HH", 2, 0), f32(1, 1, 0.5))
    d["accessors"][0]["sparse"] = {"count": 1, "indices": {"bufferView": iv, "componentType": USHORT},
                                   "values": {"bufferView": vv}}
    d["accessors"][0]["max"] = [1, 1, 0.5]
    iv, vv = add_buffer(d, bytes([3, 0, 0, 0]), f32(0.5, 0.5))
    d["accessors"].append({"componentType": FLOAT, "count": 4, "type": "VEC2", "sparse": {
        "count": 1, "indices": {"bufferView": iv, "componentType": UBYTE}, "values": {"bufferView": vv}}})
    d["meshes"][1]["primitives"][0]["attributes"]["TEXCOORD_0"] = len(d["accessors"]) - 1
    C.gltf(V, "sparse_accessors", d, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    # Blender's spot of blend 0: innerConeAngle = outerConeAngle, a hard edge.
    d = copy.deepcopy(doc0)
    d["nodes"][3]["extensions"]["KHR_lights_punctual"]["light"] = 1
    d["extensions"]["KHR_lights_punctual"]["lights"][1]["spot"]["innerConeAngle"] = 0.6
    C.gltf(V, "spot_blend_zero", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES,
                   "warn=lights[1].spot: innerConeAngle = outerConeAngle (0.6, Blender's spot blend 0): a hard-edged spot"])
    # Blender marks KHR_texture_transform required whenever a Mapping node
    # feeds a texture: it loads (texCoord 1 from the extension, without a
    # TEXCOORD_1 in the primitive: warned, read as (0, 0)).
    d = copy.deepcopy(doc0)
    d["extensionsUsed"].append("KHR_texture_transform")
    d["extensionsRequired"] = ["KHR_texture_transform"]
    d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
        "KHR_texture_transform": {"offset": [0.5, 0], "rotation": 0.3, "scale": [2, 2], "texCoord": 1}}
    C.gltf(V, "texture_transform_required", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES,
                   "warn=meshes[0].primitives[0]: its material reads TEXCOORD_1, which the primitive lacks"])
    # KHR_materials_unlit and KHR_materials_variants (the default material
    # shown, warned).
    d = copy.deepcopy(doc0)
    d["extensionsUsed"] += ["KHR_materials_unlit", "KHR_materials_variants"]
    d["materials"][1]["extensions"] = {"KHR_materials_unlit": {}}
    d["extensions"]["KHR_materials_variants"] = {"variants": [{"name": "red"}, {"name": "blue"}]}
    d["meshes"][1]["primitives"][0]["extensions"] = {"KHR_materials_variants": {"mappings": [
        {"material": 0, "variants": [1]}]}}
    C.gltf(V, "unlit_and_variants", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES,
                   "warn=meshes[1].primitives[0]: KHR_materials_variants: 1 variant mapping(s); the default material is shown"])
    # Skins and morph targets that load: the plain ones, an animated weights
    # channel, and the repairs (warned).
    d = copy.deepcopy(doc0)
    skinned(d)
    C.gltf(V, "skin", d, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    d = copy.deepcopy(doc0)
    skinned(d, weights0=[(0.5, 0, 0, 0), (1, 0, 0, 0), (0, 0.5, 0, 0), (0, 1, 0, 0)])
    C.gltf(V, "skin_weights_unnormalized", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES,
                   "warn=skin weights of 2 of 4 vertices do not sum to 1 (worst 0.5); rescaled to 1"])
    d = copy.deepcopy(doc0)
    skinned(d, weights0=[(0, 0, 0, 0), (1, 0, 0, 0), (0, 1, 0, 0), (0, 1, 0, 0)])
    C.gltf(V, "skin_weights_zero", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, "warn=1 of 4 vertices have no skin weight; they follow their mesh node"])
    d = copy.deepcopy(doc0)
    skinned(d, drop="WEIGHTS_0")
    del d["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"]
    C.gltf(V, "skin_without_joints", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, "warn=nodes[1]: skins[0], but meshes[0].primitives[0] has no JOINTS_0"])
    d = copy.deepcopy(doc0)
    morphed(d, mesh_weights=[0.5], anim_values=[0, 1, 0])
    C.gltf(V, "morph_animated", d, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    # A rigid primitive (mesh 0) before a morphed one with TANGENT and a
    # normal map (mesh 1): the loader's tangent table grows at the deformed
    # range, and the rigid vertices before it must read as "no file tangent"
    # (the grown bytes were left uninitialised; valgrind_corpus runs it).
    d = copy.deepcopy(doc0)
    (tv, dv) = add_buffer(d, b"".join(f32(1, 0, 0, 1) for _ in range(4)),
                          b"".join(f32(*v) for v in [(0, 0, 0), (0, 0, 0), (0, 0, 1), (0, 0, 1)]))
    na = len(d["accessors"])
    d["accessors"] += [{"bufferView": tv, "componentType": FLOAT, "count": 4, "type": "VEC4"},
                       {"bufferView": dv, "componentType": FLOAT, "count": 4, "type": "VEC3"}]
    d["meshes"][1]["primitives"][0]["attributes"]["TANGENT"] = na
    d["meshes"][1]["primitives"][0]["targets"] = [{"POSITION": na + 1}]
    d["meshes"][1]["weights"] = [0.5]
    d["materials"][1]["normalTexture"] = {"index": 0}
    C.gltf(V, "morph_tangent_after_rigid", d, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)
    # The same with a zero TANGENT at vertex 1: it cannot be posed, so it is
    # left to the generated tangents (as store_tangent does for a rigid one),
    # not kept as a "file tangent" that was never written.
    (tv2,) = add_buffer(d, b"".join(f32(*v) for v in [(1, 0, 0, 1), (0, 0, 0, 1), (1, 0, 0, 1), (1, 0, 0, 1)]))
    d["accessors"][na]["bufferView"] = tv2
    C.gltf(V, "morph_tangent_zero", d, bin0, png, code=EXIT_OK, expect="triangles=%d" % BASE_TRIANGLES)


def main():
    root = os.path.abspath(sys.argv[1]) if len(sys.argv) > 1 else HERE
    for sub in ("broken", "valid"):
        shutil.rmtree(os.path.join(root, sub), ignore_errors=True)
    C = Corpus(root)
    png = tex_png()
    _, bin0 = base()
    C.raw("outside.bin", bin0)  # reached by broken/uri_outside through ../../
    broken_cases(C, png)
    valid_cases(C, png)
    blender_cases(C, png)
    with open(os.path.join(root, "expected.tsv"), "w", newline="\n") as f:
        f.write("# path\texit\texpect\targs  (written by make_corpus.py; see its docstring)\n")
        for line in C.lines:
            f.write(line + "\n")
    n_broken = sum(1 for l in C.lines if l.split("\t")[1] != "0")
    print("%d cases (%d failures expected) in %s" % (len(C.lines), n_broken, root))


if __name__ == "__main__":
    main()
