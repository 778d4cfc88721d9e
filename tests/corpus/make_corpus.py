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
`info --json -`: 'triangles=N' or 'warn=SUBSTRING'. ARGS are extra options,
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

# Result codes (src/core/result.h).
EXIT_OK, EXIT_IO, EXIT_PARSE, EXIT_INVALID, EXIT_UNSUPPORTED = 0, 3, 4, 5, 6
EXIT_IMAGE, EXIT_LIMIT = 8, 10

FLOAT, UBYTE, USHORT, UINT = 5126, 5121, 5123, 5125


# ---- byte builders ------------------------------------------------------------

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
    case("sparse_accessor", EXIT_UNSUPPORTED, ["accessors[0]", "sparse"],
         setp(("accessors", 0, "sparse"), {
             "count": 1, "indices": {"bufferView": 3, "componentType": USHORT},
             "values": {"bufferView": 0}}))
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
    case("blender_model_bogus", EXIT_INVALID, X + ".model: 'toon' is not principled, diffuse, emission or holdout",
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
    case("blender_diffuse_roughness_range", EXIT_INVALID, X + ".diffuse.roughness: -1 is outside [0, 1]",
         blender({"model": "diffuse", "diffuse": {"roughness": -1}}))
    case("blender_emission_color_type", EXIT_INVALID, X + ".emission.color: an object, expected an array",
         blender({"model": "emission", "emission": {"color": {"r": 1}}}))
    case("blender_texture_oob", EXIT_INVALID, X + ".textures.baseColor.index: texture 7 does not exist",
         blender({"model": "principled", "textures": {"baseColor": {"index": 7}}}))
    case("blender_texture_index_float", EXIT_INVALID, X + ".textures.roughness.index: the number is not a texture index",
         blender({"model": "principled", "textures": {"roughness": {"index": 0.5}}}))
    case("blender_texture_index_missing", EXIT_INVALID, X + ".textures.roughness.index: missing",
         blender({"model": "principled", "textures": {"roughness": {"channel": "G"}}}))
    case("blender_texture_channel_bogus", EXIT_INVALID, X + ".textures.roughness.channel: 'X' is not R, G, B, A or RGB",
         blender({"model": "principled", "textures": {"roughness": {"index": 0, "channel": "X"}}}))
    case("blender_warnings_not_strings", EXIT_INVALID, X + ".warnings[0]: a number, expected a string",
         blender({"model": "principled", "warnings": [1]}))
    case("texture_sampler_oob", EXIT_INVALID, "textures[0].sampler", setp(("textures", 0, "sampler"), 3))
    case("sampler_wrap_bogus", EXIT_INVALID, "samplers[0].wrapS", setp(("samplers", 0, "wrapS"), 12345))
    case("image_not_png", EXIT_UNSUPPORTED, ["images[0]", "not a PNG or JPEG"],
         png_data=b"GIF89a\x02\x00\x02\x00\x80\x00\x00\xff\x00\x00\xff\xff\xff!\xf9\x04\x00"
                  b"\x00\x00\x00\x00,\x00\x00\x00\x00\x02\x00\x02\x00\x00\x02\x02\x84\x51\x00;")
    case("image_huge_header", EXIT_LIMIT, ["images[0]", "100000x100000"], png_data=huge_png())
    case("image_truncated", EXIT_IMAGE, "images[0]", png_data=png[:len(png) - 30])
    case("image_missing", EXIT_IO, "images[0].uri", setp(("images", 0, "uri"), "nothere.png"))
    case("image_uri_outside", EXIT_INVALID, ["images[0].uri", "leaves the scene's folder"],
         setp(("images", 0, "uri"), "../image_not_png/tex.png"))
    case("image_data_uri", EXIT_UNSUPPORTED, "images[0].uri",
         setp(("images", 0, "uri"), "data:image/png;base64," + base64.b64encode(png).decode()))
    case("image_bufferview_oob", EXIT_INVALID, "images[0].bufferView",
         setp(("images", 0), {"bufferView": 9, "mimeType": "image/png"}))
    case("image_data_uri_empty", EXIT_UNSUPPORTED, "images[0].uri",
         setp(("images", 0, "uri"), "data:image/png;base64,"))
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

    # -- animations (issue 6): keys in a second, data-URI buffer
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
    C.gltf(V, "orthographic_camera", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, "warn=cameras[0]: type 'orthographic' skipped"])
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
    d = copy.deepcopy(doc0)
    d["extensionsUsed"].append("KHR_draco_mesh_compression")
    C.gltf(V, "draco_used_not_required", d, bin0, png, code=EXIT_OK,
           expect=["triangles=%d" % BASE_TRIANGLES, "warn=KHR_draco_mesh_compression"])


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.abspath(sys.argv[1]) if len(sys.argv) > 1 else here
    for sub in ("broken", "valid"):
        shutil.rmtree(os.path.join(root, sub), ignore_errors=True)
    C = Corpus(root)
    png = tex_png()
    _, bin0 = base()
    C.raw("outside.bin", bin0)  # reached by broken/uri_outside through ../../
    broken_cases(C, png)
    valid_cases(C, png)
    with open(os.path.join(root, "expected.tsv"), "w", newline="\n") as f:
        f.write("# path\texit\texpect\targs  (written by make_corpus.py; see its docstring)\n")
        for line in C.lines:
            f.write(line + "\n")
    n_broken = sum(1 for l in C.lines if l.split("\t")[1] != "0")
    print("%d cases (%d failures expected) in %s" % (len(C.lines), n_broken, root))


if __name__ == "__main__":
    main()
