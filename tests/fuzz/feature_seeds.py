"""Code-made glTF files for fuzz_gltf's seeds: one small file per feature the
loader reads or will read, so that mutations start next to real structure
(imported by make_seeds.py; every file is a pure function of this module).

Features: skins (JOINTS_0/WEIGHTS_0, inverseBindMatrices, skeleton), morph
targets (POSITION/NORMAL/TANGENT deltas, default weights, a weights
animation), sparse accessors (with and without a base bufferView, every
index type), KHR_texture_transform (optional and required), every KHR
material extension in the registry (specular, transmission, ior,
emissive_strength, volume, clearcoat, sheen, iridescence, anisotropy,
dispersion, unlit, variants, pbrSpecularGlossiness), animation channels
(translation, rotation, scale, weights x STEP, LINEAR, CUBICSPLINE, on
cameras, lights and meshes, two animations), images as data URIs (PNG and
JPEG) and as bufferViews, KHR_lights_punctual, both camera types,
KHR_mesh_quantization attributes, COLOR_0, TEXCOORD_1, TANGENT, non-indexed
and strip/fan/line/point primitives, node matrices, several scenes, and the
PHOTONBRIDGE_blender extension on the root, nodes (every light type),
materials (every model) and cameras (exporters/blender/PHOTONBRIDGE_blender.md).
"""
import base64
import json
import math
import struct
import zlib

FLOAT, BYTE, UBYTE, SHORT, USHORT, UINT = 5126, 5120, 5121, 5122, 5123, 5125
FMT = {FLOAT: "f", BYTE: "b", UBYTE: "B", SHORT: "h", USHORT: "H", UINT: "I"}
NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}

# A real 8x8 baseline JPEG (Pillow 9.4, quality 50).
JPEG_8X8 = bytes.fromhex(
    "ffd8ffe000104a46494600010100000100010000ffdb004300100b0c0e0c0a100e0d0e1211101318281a181616183123251d283a"
    "333d3c3933383740485c4e404457453738506d51575f626768673e4d71797064785c656763ffdb0043011112121815182f1a1a2f"
    "63423842636363636363636363636363636363636363636363636363636363636363636363636363636363636363636363636363"
    "6363ffc00011080008000803012200021101031101ffc4001f000001050101010101010000000000000000010203040506070809"
    "0a0bffc400b5100002010303020403050504040000017d01020300041105122131410613516107227114328191a1082342b1c115"
    "52d1f02433627282090a161718191a25262728292a3435363738393a434445464748494a535455565758595a636465666768696a"
    "737475767778797a838485868788898a92939495969798999aa2a3a4a5a6a7a8a9aab2b3b4b5b6b7b8b9bac2c3c4c5c6c7c8c9ca"
    "d2d3d4d5d6d7d8d9dae1e2e3e4e5e6e7e8e9eaf1f2f3f4f5f6f7f8f9faffc4001f01000301010101010101010100000000000001"
    "02030405060708090a0bffc400b51100020102040403040705040400010277000102031104052131061241510761711322328108"
    "144291a1b1c109233352f0156272d10a162434e125f11718191a262728292a35363738393a434445464748494a53545556575859"
    "5a636465666768696a737475767778797a82838485868788898a92939495969798999aa2a3a4a5a6a7a8a9aab2b3b4b5b6b7b8b9"
    "bac2c3c4c5c6c7c8c9cad2d3d4d5d6d7d8d9dae2e3e4e5e6e7e8e9eaf2f3f4f5f6f7f8f9faffda000c03010002110311003f0083"
    "4fd0ba7c94514573d5c4d4e6dcbc062eafb15a9fffd9")


def png_4x4():
    def chunk(k, d):
        return struct.pack(">I", len(d)) + k + d + struct.pack(">I", zlib.crc32(k + d) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + b"".join(bytes((x * 60, y * 60, 200, 255)) for x in range(4)) for y in range(4))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 4, 4, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


class Doc:
    """A glTF document under construction with one buffer."""

    def __init__(self):
        self.d = {"asset": {"version": "2.0", "generator": "photonbridge feature_seeds"},
                  "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "accessors": [],
                  "bufferViews": [], "buffers": []}
        self.blob = b""

    def view(self, data, target=None, stride=None):
        while len(self.blob) % 4:
            self.blob += b"\x00"
        v = {"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data)}
        if target:
            v["target"] = target
        if stride:
            v["byteStride"] = stride
        self.blob += data
        self.d["bufferViews"].append(v)
        return len(self.d["bufferViews"]) - 1

    def acc(self, values, ctype, atype, normalized=False, minmax=False, target=None):
        n = NCOMP[atype]
        flat = [c for v in values for c in (v if isinstance(v, (list, tuple)) else (v,))]
        data = struct.pack("<%d%s" % (len(flat), FMT[ctype]), *flat)
        a = {"bufferView": self.view(data, target), "componentType": ctype, "count": len(flat) // n,
             "type": atype}
        if normalized:
            a["normalized"] = True
        if minmax:
            a["min"] = [min(flat[i::n]) for i in range(n)]
            a["max"] = [max(flat[i::n]) for i in range(n)]
        self.d["accessors"].append(a)
        return len(self.d["accessors"]) - 1

    def node(self, root=True, **kw):
        self.d["nodes"].append(kw)
        i = len(self.d["nodes"]) - 1
        if root:
            self.d["scenes"][0]["nodes"].append(i)
        return i

    def ext(self, name):
        self.d.setdefault("extensionsUsed", [])
        if name not in self.d["extensionsUsed"]:
            self.d["extensionsUsed"].append(name)

    def quad(self, material=None, extra_attrs=None, mode=None, indexed=True):
        pos = self.acc([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], FLOAT, "VEC3", minmax=True)
        nrm = self.acc([(0, 0, 1)] * 4, FLOAT, "VEC3")
        uv = self.acc([(0, 1), (1, 1), (1, 0), (0, 0)], FLOAT, "VEC2")
        prim = {"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv}}
        if indexed:
            prim["indices"] = self.acc([0, 1, 2, 0, 2, 3], USHORT, "SCALAR")
        if material is not None:
            prim["material"] = material
        if mode is not None:
            prim["mode"] = mode
        prim["attributes"].update(extra_attrs or {})
        self.d["meshes"].append({"primitives": [prim]})
        return len(self.d["meshes"]) - 1

    def image(self, data, as_uri):
        mime = "image/jpeg" if data[:2] == b"\xff\xd8" else "image/png"
        self.d.setdefault("images", [])
        if as_uri:
            self.d["images"].append({"uri": "data:%s;base64,%s" % (mime, base64.b64encode(data).decode())})
        else:
            self.d["images"].append({"bufferView": self.view(data), "mimeType": mime})
        self.d.setdefault("textures", []).append({"source": len(self.d["images"]) - 1, "sampler": 0})
        self.d.setdefault("samplers", [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497,
                                        "wrapT": 33648}])
        return len(self.d["textures"]) - 1

    def camera_light(self):
        self.ext("KHR_lights_punctual")
        self.d["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100,
                                                                     "aspectRatio": 1.5}}]
        self.d.setdefault("extensions", {})["KHR_lights_punctual"] = {"lights": [
            {"type": "point", "intensity": 2000, "color": [1, 0.9, 0.8], "range": 50}]}
        self.node(camera=0, translation=[0, 0, 5])
        self.node(translation=[0, 2, 3], extensions={"KHR_lights_punctual": {"light": 0}})

    def finish(self):
        d = json.loads(json.dumps(self.d))
        d["buffers"] = [{"byteLength": len(self.blob),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(self.blob).decode()}]
        return d


def mat(doc, m):
    doc.d.setdefault("materials", []).append(m)
    return len(doc.d["materials"]) - 1


def skin():
    g = Doc()
    mesh = g.quad()
    prim = g.d["meshes"][mesh]["primitives"][0]
    prim["attributes"]["JOINTS_0"] = g.acc([(0, 1, 0, 0)] * 4, UBYTE, "VEC4")
    prim["attributes"]["WEIGHTS_0"] = g.acc([(0.75, 0.25, 0, 0)] * 4, FLOAT, "VEC4")
    j0 = g.node(root=False, name="root", translation=[0, -1, 0])
    j1 = g.node(root=False, name="tip", translation=[0, 1, 0], rotation=[0, 0, 0.3826834, 0.9238795])
    g.d["nodes"][j0]["children"] = [j1]
    ibm = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1]
    ibm2 = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1]
    g.d["skins"] = [{"joints": [j0, j1], "skeleton": j0, "inverseBindMatrices": g.acc([ibm, ibm2], FLOAT, "MAT4")}]
    g.node(name="rig", children=[j0])
    g.node(mesh=mesh, skin=0)
    g.camera_light()
    t = g.acc([0, 0.5, 1], FLOAT, "SCALAR", minmax=True)
    r = g.acc([(0, 0, 0, 1), (0, 0, 0.38268, 0.92388), (0, 0, 0, 1)], FLOAT, "VEC4")
    g.d["animations"] = [{"name": "bend", "samplers": [{"input": t, "output": r, "interpolation": "LINEAR"}],
                          "channels": [{"sampler": 0, "target": {"node": j1, "path": "rotation"}}]}]
    return g


def morph():
    g = Doc()
    mesh = g.quad()
    prim = g.d["meshes"][mesh]["primitives"][0]
    d1 = g.acc([(0, 0, 0.5)] * 4, FLOAT, "VEC3", minmax=True)
    d2 = g.acc([(0.2, 0, 0), (0, 0.2, 0), (-0.2, 0, 0), (0, -0.2, 0)], FLOAT, "VEC3", minmax=True)
    n1 = g.acc([(0, 0.1, -0.1)] * 4, FLOAT, "VEC3")
    prim["attributes"]["TANGENT"] = g.acc([(1, 0, 0, 1)] * 4, FLOAT, "VEC4")
    prim["targets"] = [{"POSITION": d1, "NORMAL": n1}, {"POSITION": d2, "TANGENT": g.acc([(0, 0.1, 0)] * 4, FLOAT, "VEC3")}]
    g.d["meshes"][mesh]["weights"] = [0.5, 0.25]
    g.d["meshes"][mesh]["extras"] = {"targetNames": ["up", "twist"]}
    node = g.node(mesh=mesh, weights=[0.1, 0.9])
    g.camera_light()
    t = g.acc([0, 1, 2], FLOAT, "SCALAR", minmax=True)
    w = g.acc([0, 1, 1, 0, 0.5, 0.5], FLOAT, "SCALAR")
    ts = g.acc([0, 1], FLOAT, "SCALAR", minmax=True)
    wc = g.acc([0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1], FLOAT, "SCALAR")  # CUBICSPLINE: in, value, out per key
    g.d["animations"] = [
        {"name": "breathe", "samplers": [{"input": t, "output": w, "interpolation": "LINEAR"}],
         "channels": [{"sampler": 0, "target": {"node": node, "path": "weights"}}]},
        {"name": "cubic", "samplers": [{"input": ts, "output": wc, "interpolation": "CUBICSPLINE"}],
         "channels": [{"sampler": 0, "target": {"node": node, "path": "weights"}}]}]
    return g


def sparse():
    """Sparse POSITION accessors over the quad's (UBYTE indices), over zeros
    (no bufferView, USHORT) and as a morph target (UINT)."""
    g = Doc()
    mesh = g.quad()
    prim = g.d["meshes"][mesh]["primitives"][0]
    base_view = g.d["accessors"][prim["attributes"]["POSITION"]]["bufferView"]
    made = []
    for itype, with_view in ((UBYTE, True), (USHORT, False), (UINT, True)):
        idx = g.view(struct.pack("<2%s" % FMT[itype], 1, 3))
        val = g.view(struct.pack("<6f", 1.5, -1, 0.25, -1.5, 1, -0.25))
        a = {"componentType": FLOAT, "count": 4, "type": "VEC3", "min": [-1.5, -1, -0.25], "max": [1.5, 1, 0.25],
             "sparse": {"count": 2, "indices": {"bufferView": idx, "componentType": itype},
                        "values": {"bufferView": val}}}
        if with_view:
            a["bufferView"] = base_view
        g.d["accessors"].append(a)
        made.append(len(g.d["accessors"]) - 1)
    prim["attributes"]["POSITION"] = made[0]
    prim["targets"] = [{"POSITION": made[2]}]
    m2 = g.quad()
    g.d["meshes"][m2]["primitives"][0]["attributes"]["POSITION"] = made[1]
    g.node(mesh=mesh)
    g.node(mesh=m2, translation=[3, 0, 0])
    g.camera_light()
    return g


def texture_transform(required):
    g = Doc()
    g.ext("KHR_texture_transform")
    if required:
        g.d["extensionsRequired"] = ["KHR_texture_transform"]
    tex = g.image(png_4x4(), as_uri=False)
    tt = {"offset": [0.25, -0.5], "rotation": 0.7853982, "scale": [2, 0.5], "texCoord": 1}
    m = mat(g, {"pbrMetallicRoughness": {"baseColorTexture": {"index": tex, "texCoord": 0,
                                                              "extensions": {"KHR_texture_transform": tt}},
                                         "metallicRoughnessTexture": {"index": tex, "extensions": {
                                             "KHR_texture_transform": {"scale": [4, 4]}}}},
                "normalTexture": {"index": tex, "scale": 0.5,
                                  "extensions": {"KHR_texture_transform": {"rotation": -1.0}}}})
    mesh = g.quad(m, {"TEXCOORD_1": g.acc([(0, 0), (2, 0), (2, 2), (0, 2)], FLOAT, "VEC2")})
    g.node(mesh=mesh)
    g.camera_light()
    return g


def materials():
    g = Doc()
    png = g.image(png_4x4(), as_uri=True)
    jpg = g.image(JPEG_8X8, as_uri=True)
    glb_png = g.image(png_4x4(), as_uri=False)
    T = lambda i, **kw: dict({"index": i}, **kw)
    exts = {
        "KHR_materials_specular": {"specularFactor": 0.7, "specularColorFactor": [1, 0.9, 0.8],
                                   "specularTexture": T(png), "specularColorTexture": T(jpg)},
        "KHR_materials_transmission": {"transmissionFactor": 0.9, "transmissionTexture": T(png)},
        "KHR_materials_ior": {"ior": 1.52},
        "KHR_materials_emissive_strength": {"emissiveStrength": 25},
        "KHR_materials_volume": {"thicknessFactor": 0.3, "thicknessTexture": T(glb_png),
                                 "attenuationDistance": 2.5, "attenuationColor": [0.9, 0.5, 0.2]},
        "KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.1,
                                    "clearcoatTexture": T(png), "clearcoatNormalTexture": T(png, scale=0.8)},
        "KHR_materials_sheen": {"sheenColorFactor": [0.5, 0.2, 0.9], "sheenRoughnessFactor": 0.4,
                                "sheenColorTexture": T(jpg)},
        "KHR_materials_iridescence": {"iridescenceFactor": 1, "iridescenceIor": 1.3,
                                      "iridescenceThicknessMinimum": 100, "iridescenceThicknessMaximum": 400},
        "KHR_materials_anisotropy": {"anisotropyStrength": 0.6, "anisotropyRotation": 1.2},
        "KHR_materials_dispersion": {"dispersion": 0.1},
    }
    ms = []
    for name, e in exts.items():
        g.ext(name)
        ms.append(mat(g, {"name": name, "extensions": {name: e},
                          "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.7, 0.6, 1], "roughnessFactor": 0.3,
                                                   "baseColorTexture": T(png)},
                          "emissiveFactor": [1, 0.5, 0] if "emissive" in name else [0, 0, 0]}))
    g.ext("KHR_materials_unlit")
    ms.append(mat(g, {"name": "unlit", "extensions": {"KHR_materials_unlit": {}},
                      "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}}))
    g.ext("KHR_materials_pbrSpecularGlossiness")
    ms.append(mat(g, {"name": "specgloss", "extensions": {"KHR_materials_pbrSpecularGlossiness": {
        "diffuseFactor": [0.5, 0.5, 0.5, 1], "specularFactor": [0.1, 0.1, 0.1], "glossinessFactor": 0.6,
        "diffuseTexture": T(jpg)}}}))
    ms.append(mat(g, {"name": "all", "alphaMode": "MASK", "alphaCutoff": 0.4, "doubleSided": True,
                      "occlusionTexture": T(png, strength=0.5), "emissiveTexture": T(jpg),
                      "emissiveFactor": [1, 1, 1], "normalTexture": T(glb_png, scale=1.5),
                      "extensions": {k: v for k, v in exts.items() if "dispersion" not in k}}))
    ms.append(mat(g, {"name": "blend", "alphaMode": "BLEND", "pbrMetallicRoughness": {
        "baseColorFactor": [1, 1, 1, 0.3], "metallicFactor": 1, "metallicRoughnessTexture": T(glb_png)}}))
    g.ext("KHR_materials_variants")
    g.d.setdefault("extensions", {})["KHR_materials_variants"] = {"variants": [{"name": "red"}, {"name": "glass"}]}
    for k, m in enumerate(ms):
        mesh = g.quad(m)
        if k == 0:
            g.d["meshes"][mesh]["primitives"][0]["extensions"] = {"KHR_materials_variants": {"mappings": [
                {"material": ms[-4], "variants": [0]}, {"material": ms[1], "variants": [1]}]}}
        g.node(mesh=mesh, translation=[2.5 * (k % 4), 2.5 * (k // 4), 0])
    g.camera_light()
    return g


def animation():
    g = Doc()
    mesh = g.quad()
    g.camera_light()
    cam_node, light_node = 0, 1
    n = g.node(mesh=mesh)
    t2 = g.acc([0, 1], FLOAT, "SCALAR", minmax=True)
    t3 = g.acc([0, 0.5, 2], FLOAT, "SCALAR", minmax=True)
    v3 = g.acc([(0, 0, 0), (1, 0, 0), (1, 2, 0)], FLOAT, "VEC3")
    q3 = g.acc([(0, 0, 0, 1), (0, 0.7071068, 0, 0.7071068), (0, 1, 0, 0)], FLOAT, "VEC4")
    qs = g.acc([(0, 0, 0, 32767), (0, 0, 23170, 23170)], SHORT, "VEC4", normalized=True)  # x / 32767
    s2 = g.acc([(1, 1, 1), (2, 0.5, 1)], FLOAT, "VEC3")
    cs = g.acc([(0, 0, 0), (0, 0, 0), (1, 1, 1), (0, 1, 0), (2, 2, 2), (0, 0, 0)], FLOAT, "VEC3")
    g.d["animations"] = [
        {"name": "move", "samplers": [
            {"input": t3, "output": v3, "interpolation": "LINEAR"},
            {"input": t3, "output": q3, "interpolation": "STEP"},
            {"input": t2, "output": s2},
            {"input": t2, "output": cs, "interpolation": "CUBICSPLINE"}],
         "channels": [{"sampler": 0, "target": {"node": n, "path": "translation"}},
                      {"sampler": 1, "target": {"node": n, "path": "rotation"}},
                      {"sampler": 2, "target": {"node": n, "path": "scale"}},
                      {"sampler": 3, "target": {"node": cam_node, "path": "translation"}}]},
        {"name": "spin", "samplers": [{"input": t2, "output": qs, "interpolation": "LINEAR"},
                                      {"input": t3, "output": v3, "interpolation": "STEP"}],
         "channels": [{"sampler": 0, "target": {"node": light_node, "path": "rotation"}},
                      {"sampler": 1, "target": {"node": light_node, "path": "translation"}}]}]
    return g


def primitives():
    g = Doc()
    g.ext("KHR_mesh_quantization")
    pos = g.acc([(-100, -100, 0), (100, -100, 0), (100, 100, 0), (-100, 100, 0)], SHORT, "VEC3", minmax=True)
    nrm = g.acc([(0, 0, 127, 0)] * 4, BYTE, "VEC4", normalized=True)
    uv = g.acc([(0, 65535), (65535, 65535), (65535, 0), (0, 0)], USHORT, "VEC2", normalized=True)
    col = g.acc([(255, 0, 0, 255), (0, 255, 0, 255), (0, 0, 255, 255), (255, 255, 255, 128)], UBYTE, "VEC4",
                normalized=True)
    g.d["meshes"].append({"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv,
                                                         "COLOR_0": col}, "indices": g.acc([0, 1, 2, 0, 2, 3], UBYTE,
                                                                                           "SCALAR")}]})
    g.node(mesh=0, scale=[0.01, 0.01, 0.01])
    for mode, indexed in ((5, True), (6, False), (1, True), (0, False), (4, False), (3, True), (2, False)):
        m = g.quad(mode=mode, indexed=indexed)
        g.node(mesh=m, matrix=[1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 3.0 * m, 0, 0, 1])
    inter = g.view(struct.pack("<20f", *[c for p in ((-1, -1, 0, 0, 1), (1, -1, 0, 1, 1), (1, 1, 0, 1, 0),
                                                        (-1, 1, 0, 0, 0)) for c in p]), target=34962, stride=20)
    g.d["accessors"] += [{"bufferView": inter, "byteOffset": 0, "componentType": FLOAT, "count": 4, "type": "VEC3",
                          "min": [-1, -1, 0], "max": [1, 1, 0]},
                         {"bufferView": inter, "byteOffset": 12, "componentType": FLOAT, "count": 4, "type": "VEC2"}]
    na = len(g.d["accessors"])
    g.d["meshes"].append({"primitives": [{"attributes": {"POSITION": na - 2, "TEXCOORD_0": na - 1},
                                          "indices": g.acc([0, 1, 2, 2, 3, 0], UINT, "SCALAR")}]})
    g.node(mesh=len(g.d["meshes"]) - 1, translation=[0, 5, 0])
    g.d["cameras"] = [{"type": "orthographic", "orthographic": {"xmag": 4, "ymag": 3, "znear": 0.01, "zfar": 50}},
                      {"type": "perspective", "perspective": {"yfov": 1.2, "znear": 0.05}}]
    g.node(camera=0, translation=[0, 0, 10])
    g.node(camera=1, translation=[1, 1, 10], rotation=[0, 0.0871557, 0, 0.9961947])
    g.d["scenes"].append({"name": "second", "nodes": [1]})
    g.ext("KHR_lights_punctual")
    g.d["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "spot", "intensity": 500, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
        {"type": "directional", "intensity": 3, "color": [1, 0.95, 0.9]},
        {"type": "point", "intensity": 10}]}}
    for i in range(3):
        g.node(translation=[i, 3, 2], extensions={"KHR_lights_punctual": {"light": i}})
    return g


def photonbridge_blender():
    g = Doc()
    E = "PHOTONBRIDGE_blender"
    g.ext(E)
    g.ext("KHR_lights_punctual")
    tex = g.image(png_4x4(), as_uri=True)
    g.d["extensions"] = {E: {
        "version": 1, "blender": "3.4.1", "scene": "Scene", "viewLayer": "ViewLayer",
        "frame": {"current": 1, "start": 1, "end": 48, "step": 1, "fps": 24, "fpsBase": 1.0},
        "render": {"resolution": [320, 180], "pixelAspect": [1.0, 1.0], "border": [0.1, 0.1, 0.9, 0.8],
                   "crop": False, "filmTransparent": True,
                   "bounces": {"max": 12, "diffuse": 4, "glossy": 4, "transmission": 12, "transparent": 8},
                   "filterWidth": 1.5},
        "colorManagement": {"display": "sRGB", "view": "Filmic", "look": "None", "exposure": 0.0, "gamma": 1.0},
        "world": {"color": [0.050876, 0.050876, 0.050876], "strength": 1.0,
                  "environment": {"uri": "world.hdr", "projection": "EQUIRECTANGULAR", "rotation": [0, 0, 1.57],
                                  "strength": 2.0},
                  "visibleToCamera": False}},
        "KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 54.35}, {"type": "spot", "intensity": 5,
                                            "spot": {"outerConeAngle": 0.5}}, {"type": "directional"}]}}
    models = [
        {"model": "principled", "principled": {
            "distribution": "MULTI_GGX", "subsurfaceMethod": "RANDOM_WALK", "baseColor": [0.8, 0.2, 0.1, 1.0],
            "subsurface": 0.1, "subsurfaceColor": [0.8, 0.8, 0.8, 1.0], "subsurfaceRadius": [1.0, 0.2, 0.1],
            "metallic": 0.2, "specular": 0.5, "specularTint": 0.1, "roughness": 0.4, "anisotropic": 0.3,
            "anisotropicRotation": 0.25, "sheen": 0.2, "sheenTint": 0.5, "clearcoat": 0.4,
            "clearcoatRoughness": 0.03, "ior": 1.45, "transmission": 0.5, "transmissionRoughness": 0.1,
            "emission": [0.1, 0.0, 0.0, 1.0], "emissionStrength": 2.0, "alpha": 0.9},
         "textures": {"baseColor": {"index": tex, "texCoord": 0, "channel": "RGB"},
                      "roughness": {"index": tex, "texCoord": 0, "channel": "G"},
                      "normal": {"index": tex, "texCoord": 0, "strength": 0.5}},
         "blendMethod": "HASHED", "alphaThreshold": 0.5, "backfaceCulling": True,
         "warnings": ["Mix Shader: only its first input is written"]},
        {"model": "diffuse", "diffuse": {"color": [0.8, 0.8, 0.8, 1.0], "roughness": 0.3}},
        {"model": "emission", "emission": {"color": [1, 0.9, 0.7, 1], "strength": 30.0}},
        {"model": "holdout"}]
    for k, ext in enumerate(models):
        m = mat(g, {"name": ext["model"], "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1]},
                    "extensions": {E: ext}})
        g.node(mesh=g.quad(m), translation=[2.5 * k, 0, 0])
    lights = [
        {"type": "POINT", "name": "Point", "color": [1, 1, 1], "power": 1000.0, "radius": 0.1,
         "castShadow": True, "useMIS": True},
        {"type": "SPOT", "name": "Spot", "power": 200.0, "radius": 0.0, "spotSize": 0.785398, "spotBlend": 0.15},
        {"type": "SUN", "name": "Sun", "strength": 3.0, "angle": 0.00918043},
        {"type": "AREA", "name": "Area", "power": 50.0, "shape": "RECTANGLE", "size": 1.0, "sizeY": 0.5,
         "spread": 3.14159265},
        {"type": "AREA", "name": "Disk", "power": 20.0, "shape": "DISK", "size": 0.3, "spread": 1.0}]
    for k, li in enumerate(lights):
        ext = {E: {"light": li}}
        if k < 3:
            ext["KHR_lights_punctual"] = {"light": k}
        g.node(translation=[k, 3, 1], rotation=[-0.7071068, 0, 0, 0.7071068], extensions=ext)
    g.d["cameras"] = [
        {"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.1, "zfar": 100, "aspectRatio": 1.7778},
         "extensions": {E: {"type": "PERSP", "lens": 50.0, "sensorFit": "AUTO", "sensorWidth": 36.0,
                            "sensorHeight": 24.0, "shiftX": 0.1, "shiftY": -0.05, "clipStart": 0.1,
                            "clipEnd": 100.0, "aspect": 1.7778}}},
        {"type": "orthographic", "orthographic": {"xmag": 3.6, "ymag": 2.0, "znear": 0.1, "zfar": 50},
         "extensions": {E: {"type": "ORTHO", "orthoScale": 7.31, "sensorFit": "HORIZONTAL", "aspect": 1.8}}}]
    g.node(camera=0, translation=[0, 0, 8])
    g.node(camera=1, translation=[0, 0, 9])
    return g


def all_docs():
    """[(name, glTF dict with its buffer as a data URI)]."""
    return [("skin", skin().finish()), ("morph", morph().finish()), ("sparse", sparse().finish()),
            ("texture_transform", texture_transform(False).finish()),
            ("texture_transform_required", texture_transform(True).finish()),
            ("materials", materials().finish()), ("animation", animation().finish()),
            ("primitives", primitives().finish()), ("photonbridge_blender", photonbridge_blender().finish())]
