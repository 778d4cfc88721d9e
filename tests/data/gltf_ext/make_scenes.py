#!/usr/bin/env python3
"""Writes the test scenes for what Blender's glTF exporter writes beyond the
core (tests/unit/test_gltf_ext.c renders them with the GPU pipeline, the
reference and POV-Ray):

    python3 tests/data/gltf_ext/make_scenes.py [OUT_DIR]   (default: this folder)

Every scene looks straight down at the plane y = 0 from a camera on +Y
(image up = -Z, right = +X), and (unless it says otherwise) is lit by a
directional light straight down of E = pi W/m^2 (pi x 683 lx), so that a
Lambertian surface of albedo rho shows radiance rho exactly.

  vertex_colors       three quads side by side (x in [-3,-1], [-1,1], [1,3]),
                      COLOR_0 as float VEC3, normalized UBYTE VEC4, normalized
                      USHORT VEC4, corners red, green, blue, white, times the
                      base colour (0.5, 1, 0.8)
  texture_transform   a quad whose base colour and emissive textures (4x4,
                      NEAREST) go through KHR_texture_transform (offset
                      (0, 1), rotation pi/2, scale 0.5) and its texCoord 1
                      (TEXCOORD_0 is a constant that would show one texel)
  texture_baked       the same quad with the texture baked through that
                      transform (4x4, identity), TEXCOORD_0 only
  unlit_dark          an unlit quad (0.2, 0.5, 0.8) at y = 0.5 over a white
                      diffuse floor, no light: the floor must stay black
  unlit_lit           the same with the sun: the quad still shows its colour
  spot_blend0         a spot of 100 cd straight down from y = 2, inner =
                      outer cone = 0.4 rad (Blender's blend 0), over the floor
  default_blender     a floor without material in a file Blender wrote
  default_gltf        the same file from another generator
  volume_eye          a glass slab (y in [0.4, 0.6], ior 1.5) over an unlit
                      white floor, no light; KHR_materials_volume with
                      attenuation colour 0.5 at distance 0.2 m
  volume_eye_clear    the same slab without the extension
  volume_photons      the slab over a white diffuse floor of its own footprint,
                      lit by a point light of 200 x 683 cd at y = 3 (every
                      ray to the floor crosses the slab: caustics only)
  volume_photons_clear  the same without the extension

The output is a pure function of this script (tests compare it with a fresh
run).
"""
import base64
import json
import math
import os
import struct
import sys
import zlib

FLOAT, UBYTE, USHORT = 5126, 5121, 5123
SUN_LUX = math.pi * 683


def png(w, h, rows):
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


class Doc:
    def __init__(self, generator="photonbridge tests/data/gltf_ext/make_scenes.py"):
        self.blob = b""
        self.d = {"asset": {"version": "2.0", "generator": generator}, "scene": 0, "scenes": [{"nodes": []}],
                  "nodes": [], "meshes": [], "materials": [], "accessors": [], "bufferViews": [],
                  "extensionsUsed": []}

    def use(self, ext):
        if ext not in self.d["extensionsUsed"]:
            self.d["extensionsUsed"].append(ext)

    def accessor(self, fmt, ct, values, type_, normalized=False, minmax=False):
        data = b"".join(struct.pack("<" + fmt * len(v), *v) for v in values)
        self.blob += b"\x00" * ((4 - len(self.blob) % 4) % 4)
        self.d["bufferViews"].append({"buffer": 0, "byteOffset": len(self.blob), "byteLength": len(data)})
        self.blob += data
        a = {"bufferView": len(self.d["bufferViews"]) - 1, "componentType": ct, "count": len(values), "type": type_}
        if normalized:
            a["normalized"] = True
        if minmax:
            a["min"] = [min(v[k] for v in values) for k in range(3)]
            a["max"] = [max(v[k] for v in values) for k in range(3)]
        self.d["accessors"].append(a)
        return len(self.d["accessors"]) - 1

    def node(self, n, root=True):
        self.d["nodes"].append(n)
        if root:
            self.d["scenes"][0]["nodes"].append(len(self.d["nodes"]) - 1)
        return len(self.d["nodes"]) - 1

    def mesh(self, prims):
        self.d["meshes"].append({"primitives": prims})
        return len(self.d["meshes"]) - 1

    def material(self, m):
        self.d["materials"].append(m)
        return len(self.d["materials"]) - 1

    def quad(self, x0, x1, z0, z1, y=0.0, material=None, extra=None, uv=None):
        """A quad facing +Y (counter-clockwise seen from above), corners
        (x0,z0) (x1,z0) (x1,z1) (x0,z1); uv (u = (x - x0)/(x1 - x0), v = (z -
        z0)/(z1 - z0)) unless given; `extra` adds attributes."""
        pos = [(x0, y, z0), (x0, y, z1), (x1, y, z1), (x1, y, z0)]
        uvs = uv or [(0, 0), (0, 1), (1, 1), (1, 0)]
        attrs = {"POSITION": self.accessor("f", FLOAT, pos, "VEC3", minmax=True),
                 "NORMAL": self.accessor("f", FLOAT, [(0, 1, 0)] * 4, "VEC3"),
                 "TEXCOORD_0": self.accessor("f", FLOAT, uvs, "VEC2")}
        attrs.update(extra or {})
        p = {"attributes": attrs, "indices": self.accessor("H", USHORT, [(0,), (1,), (2,), (0,), (2,), (3,)], "SCALAR")}
        if material is not None:
            p["material"] = material
        return p

    def box(self, x0, x1, y0, y1, z0, z1, material):
        """A closed box, faces outward, flat normals."""
        faces = [((x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0), (0, 1, 0)),
                 ((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1), (0, -1, 0)),
                 ((x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1), (0, 0, 1)),
                 ((x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0), (0, 0, -1)),
                 ((x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1), (1, 0, 0)),
                 ((x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0), (-1, 0, 0))]
        pos, nrm, idx = [], [], []
        for f in faces:
            b = len(pos)
            pos += list(f[:4])
            nrm += [f[4]] * 4
            idx += [(b,), (b + 1,), (b + 2,), (b,), (b + 2,), (b + 3,)]
        return {"attributes": {"POSITION": self.accessor("f", FLOAT, pos, "VEC3", minmax=True),
                               "NORMAL": self.accessor("f", FLOAT, nrm, "VEC3")},
                "indices": self.accessor("H", USHORT, idx, "SCALAR"), "material": material}

    def camera(self, height, yfov, aspect):
        self.d["cameras"] = [{"type": "perspective", "perspective": {"yfov": yfov, "aspectRatio": aspect,
                                                                    "znear": 0.01, "zfar": 100}}]
        s = math.sqrt(0.5)
        self.node({"name": "camera", "camera": 0, "translation": [0, height, 0], "rotation": [-s, 0, 0, s]})

    def light(self, light, translation=(0, 0, 0), down=True):
        self.use("KHR_lights_punctual")
        ls = self.d.setdefault("extensions", {}).setdefault("KHR_lights_punctual", {}).setdefault("lights", [])
        ls.append(light)
        s = math.sqrt(0.5)
        n = {"name": light["name"], "translation": list(translation),
             "extensions": {"KHR_lights_punctual": {"light": len(ls) - 1}}}
        if down:
            n["rotation"] = [-s, 0, 0, s]
        self.node(n)

    def sun(self):
        self.light({"name": "sun", "type": "directional", "intensity": SUN_LUX})

    def write(self, folder, name, images=()):
        for img_name, data in images:
            with open(os.path.join(folder, img_name), "wb") as f:
                f.write(data)
        d = dict(self.d)
        d["buffers"] = [{"byteLength": len(self.blob),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(self.blob).decode()}]
        for k in [k for k, v in d.items() if v == []]:
            del d[k]
        with open(os.path.join(folder, name + ".gltf"), "w", newline="\n") as f:
            f.write(json.dumps(d, indent=1) + "\n")


def lambert(color, name="lambert", **extra):
    m = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": list(color) + [1], "metallicFactor": 0,
                                                 "roughnessFactor": 1},
         "extensions": {"KHR_materials_specular": {"specularFactor": 0}}}
    m.update(extra)
    return m


def vertex_colors(out):
    g = Doc()
    g.use("KHR_materials_specular")
    m = g.material(lambert((0.5, 1, 0.8), "tinted"))
    corners = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)]
    cf = g.accessor("f", FLOAT, corners, "VEC3")
    cb = g.accessor("B", UBYTE, [tuple(int(255 * c) for c in v) + (255,) for v in corners], "VEC4", normalized=True)
    cs = g.accessor("H", USHORT, [tuple(int(65535 * c) for c in v) + (65535,) for v in corners], "VEC4",
                    normalized=True)
    prims = [g.quad(x0, x0 + 2, -1, 1, material=m, extra={"COLOR_0": c}) for x0, c in ((-3, cf), (-1, cb), (1, cs))]
    g.node({"name": "quads", "mesh": g.mesh(prims)})
    g.camera(6, 2 * math.atan(1.2 / 6), 3)
    g.sun()
    g.write(out, "vertex_colors")


# The 4x4 texture A (row y = 0 at the top): every texel its own colour.
def tex_a():
    return [[(40 + 60 * x, 30 + 70 * y, 200 - 40 * x - 20 * y, 255) for x in range(4)] for y in range(4)]


def rows(t):
    return [[c for px in row for c in px] for row in t]


def texture_pair(out):
    A = tex_a()
    # The transform: u' = 0.5 v, v' = 1 - 0.5 u (rotation pi/2, scale 0.5,
    # offset (0, 1)). Texel (x, y) of the baked B, centre (u, v) = ((x +
    # 0.5) / 4, (y + 0.5) / 4), reads A at (0.5 v, 1 - 0.5 u): column
    # floor(2 v), row floor(4 - 2 u) = 3 - x // 2.
    B = [[A[3 - x // 2][y // 2] for x in range(4)] for y in range(4)]
    xf = {"offset": [0, 1], "rotation": math.pi / 2, "scale": [0.5, 0.5], "texCoord": 1}
    for name, texture, transform in (("texture_transform", A, xf), ("texture_baked", B, None)):
        g = Doc()
        g.use("KHR_materials_specular")
        g.d["samplers"] = [{"magFilter": 9728, "minFilter": 9728, "wrapS": 33071, "wrapT": 33071}]
        g.d["images"] = [{"name": name, "uri": name + ".png"}]
        g.d["textures"] = [{"source": 0, "sampler": 0}]
        info = {"index": 0}
        if transform:
            g.use("KHR_texture_transform")
            g.d.setdefault("extensionsRequired", []).append("KHR_texture_transform")
            info["extensions"] = {"KHR_texture_transform": transform}
        m = lambert((1, 1, 1), "textured", emissiveTexture=dict(info), emissiveFactor=[0.25, 0.25, 0.25])
        m["pbrMetallicRoughness"]["baseColorTexture"] = dict(info)
        m = g.material(m)
        uv = [(0, 0), (0, 1), (1, 1), (1, 0)]
        if transform:  # TEXCOORD_0 a constant, the real uvs in TEXCOORD_1
            p = g.quad(-1, 1, -1, 1, material=m, uv=[(0.9, 0.9)] * 4,
                       extra={"TEXCOORD_1": g.accessor("f", FLOAT, uv, "VEC2")})
        else:
            p = g.quad(-1, 1, -1, 1, material=m, uv=uv)
        g.node({"name": "quad", "mesh": g.mesh([p])})
        g.camera(3, 2 * math.atan(1.1 / 3), 1)
        g.sun()
        g.write(out, name, images=[(name + ".png", png(4, 4, rows(texture)))])


def unlit(out):
    for name, lit in (("unlit_dark", False), ("unlit_lit", True)):
        g = Doc()
        g.use("KHR_materials_specular")
        g.use("KHR_materials_unlit")
        floor = g.material(lambert((1, 1, 1), "floor"))
        u = g.material({"name": "unlit", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.5, 0.8, 1]},
                        "extensions": {"KHR_materials_unlit": {}}})
        g.node({"name": "floor", "mesh": g.mesh([g.quad(-2, 2, -2, 2, material=floor)])})
        g.node({"name": "card", "mesh": g.mesh([g.quad(-0.5, 0.5, -0.5, 0.5, y=0.5, material=u)])})
        g.camera(4, 2 * math.atan(2.1 / 4), 1)
        if lit:
            g.sun()
        g.write(out, name)


def spot(out):
    g = Doc()
    g.use("KHR_materials_specular")
    m = g.material(lambert((0.8, 0.8, 0.8), "floor"))
    g.node({"name": "floor", "mesh": g.mesh([g.quad(-2, 2, -2, 2, material=m)])})
    g.camera(4, 2 * math.atan(1.5 / 4), 1)
    g.light({"name": "spot", "type": "spot", "intensity": 100 * 683,
             "spot": {"innerConeAngle": 0.4, "outerConeAngle": 0.4}}, translation=(0, 2, 0))
    g.write(out, "spot_blend0")


def default_material(out):
    for name, gen in (("default_blender", "Khronos glTF Blender I/O v3.4.50"), ("default_gltf", "some other exporter")):
        g = Doc(gen)
        g.node({"name": "floor", "mesh": g.mesh([g.quad(-2, 2, -2, 2)])})
        g.camera(4, 2 * math.atan(1.5 / 4), 1)
        g.sun()
        g.write(out, name)


def volume(out):
    for name, absorb, photons in (("volume_eye", True, False), ("volume_eye_clear", False, False),
                                  ("volume_photons", True, True), ("volume_photons_clear", False, True)):
        g = Doc()
        g.use("KHR_materials_specular")
        g.use("KHR_materials_transmission")
        glass = {"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0,
                                                           "roughnessFactor": 0},
                 "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}}}
        if absorb:
            g.use("KHR_materials_volume")
            glass["extensions"]["KHR_materials_volume"] = {"thicknessFactor": 0.2, "attenuationDistance": 0.2,
                                                           "attenuationColor": [0.5, 0.5, 0.5]}
        gm = g.material(glass)
        if photons:
            fm = g.material(lambert((1, 1, 1), "floor"))
        else:
            g.use("KHR_materials_unlit")
            fm = g.material({"name": "backdrop", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1]},
                             "extensions": {"KHR_materials_unlit": {}}})
        # Under the photons the floor is the slab's footprint: all its light
        # then comes through the slab (caustic photons only).
        e = 1 if photons else 3
        g.node({"name": "floor", "mesh": g.mesh([g.quad(-e, e, -e, e, material=fm)])})
        g.node({"name": "slab", "mesh": g.mesh([g.box(-1, 1, 0.4, 0.6, -1, 1, gm)])})
        g.camera(4, 2 * math.atan(1.2 / 4), 1)
        if photons:
            g.light({"name": "bulb", "type": "point", "intensity": 200 * 683}, translation=(0, 3, 0), down=False)
        g.write(out, name)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = os.path.abspath(sys.argv[1]) if len(sys.argv) > 1 else here
    os.makedirs(out, exist_ok=True)
    vertex_colors(out)
    texture_pair(out)
    unlit(out)
    spot(out)
    default_material(out)
    volume(out)


if __name__ == "__main__":
    main()
