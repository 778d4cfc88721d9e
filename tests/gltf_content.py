#!/usr/bin/env python3
"""Compare two glTF 2.0 files by content, or check that glTF files are well formed.

    gltf_content.py A.gltf B.gltf        exit 0 when equal, 1 with a list of differences
    gltf_content.py --check F.gltf|DIR ...
                                         exit 0 when every file (DIR: every .gltf/.glb
                                         below it) is well formed, 1 if not
    gltf_content.py --animated F.gltf NODE KIND PATHS [F.gltf NODE KIND PATHS ...]
                                         exit 0 when each F is an animated sample that
                                         moves node NODE (KIND: light, camera or mesh)
                                         and only it, by the node TRS PATHS
                                         (comma-separated, e.g. translation,rotation),
                                         49 keys from 0 to 2 s; 1 if not

Pure Python (json + struct + hashlib); no numpy, so it runs with any python3.

"Equal by content" means: the same scenes and node trees (names, transforms,
references), the same meshes with the same decoded accessor data for every
attribute, index list and morph target (floats within 1e-6, relative for
values above 1), the same primitive modes and materials, the same materials
(every field, extensions included), textures, samplers, cameras, lights
(KHR_lights_punctual), animations and skins, and the same bytes in every
referenced image.  Animations are compared channel by channel: the target
(node and path), the sampler's interpolation, and its decoded key times and
values (same tolerance), whatever the order of channels and samplers.  Ignored: asset.generator, and how data
is laid out in buffers (buffers, bufferViews, byte offsets and strides,
accessor order and index component type, accessor min/max).

--check (the samples_wellformed test): every file parses as JSON with
asset.version 2.x, every buffer it references exists with at least the
declared byteLength, every accessor lies inside its buffer, every image file
exists, and the file has at least one camera, one KHR_lights_punctual light
(or a PHOTONBRIDGE_blender light or world)
and one mesh.  A .glb is read too (its BIN chunk is buffer 0).

--animated (the samples_animated test): see check_animated.
"""

import base64
import hashlib
import json
import math
import os
import struct
import sys

TOL = 1e-6
MAX_DIFFS_PER_ACCESSOR = 5
MAX_DIFFS = 200

COMPONENT = {  # componentType -> (struct code, size, normalisation divisor)
    5120: ("b", 1, 127.0),
    5121: ("B", 1, 255.0),
    5122: ("h", 2, 32767.0),
    5123: ("H", 2, 65535.0),
    5125: ("I", 4, None),
    5126: ("f", 4, None),
}
NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


class GltfError(Exception):
    pass


# --------------------------------------------------------------------------
# Loading
# --------------------------------------------------------------------------

class Gltf:
    def __init__(self, path):
        self.path = path
        self.dir = os.path.dirname(os.path.abspath(path))
        self.glb_bin = None
        with open(path, "rb") as f:
            raw = f.read()
        if raw[:4] == b"glTF":
            self.doc = self._parse_glb(raw)
        else:
            try:
                self.doc = json.loads(raw.decode("utf-8"))
            except (UnicodeDecodeError, ValueError) as e:
                raise GltfError("%s: not JSON: %s" % (path, e))
        if not isinstance(self.doc, dict):
            raise GltfError("%s: top level is not a JSON object" % path)
        self._buffers = {}
        self._accessors = {}

    def _parse_glb(self, raw):
        if len(raw) < 20:
            raise GltfError("%s: truncated GLB header" % self.path)
        _, _, length = struct.unpack_from("<4sII", raw, 0)
        pos, doc = 12, None
        while pos + 8 <= min(length, len(raw)):
            clen, ctype = struct.unpack_from("<II", raw, pos)
            chunk = raw[pos + 8:pos + 8 + clen]
            if ctype == 0x4E4F534A:
                doc = json.loads(chunk.decode("utf-8"))
            elif ctype == 0x004E4942 and self.glb_bin is None:
                self.glb_bin = chunk
            pos += 8 + clen
        if doc is None:
            raise GltfError("%s: GLB without a JSON chunk" % self.path)
        return doc

    def list(self, key):
        v = self.doc.get(key, [])
        if not isinstance(v, list):
            raise GltfError("%s: '%s' is not an array" % (self.path, key))
        return v

    def uri_bytes(self, uri, what):
        if uri.startswith("data:"):
            head, _, data = uri.partition(",")
            if head.endswith(";base64"):
                return base64.b64decode(data)
            from urllib.parse import unquote_to_bytes
            return unquote_to_bytes(data)
        from urllib.parse import unquote
        p = os.path.join(self.dir, unquote(uri))
        if not os.path.isfile(p):
            raise GltfError("%s: %s '%s' not found" % (self.path, what, uri))
        with open(p, "rb") as f:
            return f.read()

    def buffer(self, i):
        if i not in self._buffers:
            bufs = self.list("buffers")
            if not 0 <= i < len(bufs):
                raise GltfError("%s: buffer %d does not exist" % (self.path, i))
            b = bufs[i]
            if "uri" in b:
                data = self.uri_bytes(b["uri"], "buffer")
            elif i == 0 and self.glb_bin is not None:
                data = self.glb_bin
            else:
                raise GltfError("%s: buffer %d has no data" % (self.path, i))
            if len(data) < b.get("byteLength", 0):
                raise GltfError("%s: buffer %d holds %d bytes, byteLength says %d"
                                % (self.path, i, len(data), b.get("byteLength", 0)))
            self._buffers[i] = data
        return self._buffers[i]

    def _view_bytes(self, vi, elem_size):
        views = self.list("bufferViews")
        if not 0 <= vi < len(views):
            raise GltfError("%s: bufferView %d does not exist" % (self.path, vi))
        v = views[vi]
        data = self.buffer(v["buffer"])
        off, length = v.get("byteOffset", 0), v["byteLength"]
        if off + length > len(data):
            raise GltfError("%s: bufferView %d (%d+%d) runs past its buffer (%d)"
                            % (self.path, vi, off, length, len(data)))
        return data[off:off + length], v.get("byteStride") or elem_size

    def _read(self, vi, byte_offset, count, ctype, ncomp, what):
        code, size, _ = COMPONENT[ctype]
        elem = size * ncomp
        data, stride = self._view_bytes(vi, elem)
        if count and byte_offset + stride * (count - 1) + elem > len(data):
            raise GltfError("%s: %s runs past the end of bufferView %d" % (self.path, what, vi))
        fmt = "<%d%s" % (ncomp, code)
        if stride == elem:
            flat = struct.unpack_from("<%d%s" % (ncomp * count, code), data, byte_offset)
            return [flat[k * ncomp:(k + 1) * ncomp] for k in range(count)]
        return [struct.unpack_from(fmt, data, byte_offset + k * stride) for k in range(count)]

    def accessor(self, i):
        """Decoded accessor: list of tuples (normalised integers as floats)."""
        if i in self._accessors:
            return self._accessors[i]
        accs = self.list("accessors")
        if not isinstance(i, int) or not 0 <= i < len(accs):
            raise GltfError("%s: accessor %r does not exist" % (self.path, i))
        a = accs[i]
        ctype, n, count = a["componentType"], NCOMP[a["type"]], a["count"]
        if ctype not in COMPONENT:
            raise GltfError("%s: accessor %d: bad componentType %r" % (self.path, i, ctype))
        what = "accessor %d" % i
        if "bufferView" in a:
            vals = self._read(a["bufferView"], a.get("byteOffset", 0), count, ctype, n, what)
        else:
            vals = [(0,) * n] * count
        sp = a.get("sparse")
        if sp:
            vals = list(vals)
            idx = sp["indices"]
            ii = self._read(idx["bufferView"], idx.get("byteOffset", 0), sp["count"],
                            idx["componentType"], 1, what + " sparse indices")
            vv = sp["values"]
            nv = self._read(vv["bufferView"], vv.get("byteOffset", 0), sp["count"],
                            ctype, n, what + " sparse values")
            for (k,), v in zip(ii, nv):
                vals[k] = v
        div = COMPONENT[ctype][2]
        if a.get("normalized") and div:
            vals = [tuple(max(c / div, -1.0) for c in v) for v in vals]
        vals = [tuple(v) for v in vals]
        self._accessors[i] = vals
        return vals

    def image_bytes(self, img):
        if "uri" in img:
            return self.uri_bytes(img["uri"], "image")
        if "bufferView" in img:
            data, _ = self._view_bytes(img["bufferView"], 1)
            return data
        raise GltfError("%s: image without uri or bufferView" % self.path)


# --------------------------------------------------------------------------
# Canonical content
# --------------------------------------------------------------------------

class Accessor:
    """Marks decoded accessor data inside the canonical tree."""

    def __init__(self, values, type_):
        self.values = values
        self.type = type_


class Image:
    def __init__(self, sha256, size):
        self.sha256 = sha256
        self.size = size


def canonical(g):
    d = g.doc
    out = {}
    asset = dict(d.get("asset", {}))
    asset.pop("generator", None)
    out["asset"] = asset
    for key in ("extensionsUsed", "extensionsRequired"):
        out[key] = sorted(d.get(key, []))
    out["scene"] = d.get("scene")
    out["scenes"] = d.get("scenes", [])
    out["nodes"] = [canonical_node(n) for n in d.get("nodes", [])]

    def acc(i):
        return Accessor(g.accessor(i), d["accessors"][i]["type"])

    meshes = []
    for m in g.list("meshes"):
        cm = {k: v for k, v in m.items() if k != "primitives"}
        prims = []
        for p in m.get("primitives", []):
            cp = {k: v for k, v in p.items()
                  if k not in ("attributes", "indices", "targets", "mode", "extensions")}
            cp["mode"] = p.get("mode", 4)
            cp["attributes"] = {k: acc(v) for k, v in p.get("attributes", {}).items()}
            cp["indices"] = acc(p["indices"]) if "indices" in p else None
            if "targets" in p:
                cp["targets"] = [{k: acc(v) for k, v in t.items()} for t in p["targets"]]
            if "extensions" in p:
                cp["extensions"] = p["extensions"]
            prims.append(cp)
        cm["primitives"] = prims
        meshes.append(cm)
    out["meshes"] = meshes

    images = []
    for img in g.list("images"):
        data = g.image_bytes(img)
        ci = {k: v for k, v in img.items() if k not in ("bufferView",)}
        ci["data"] = Image(hashlib.sha256(data).hexdigest(), len(data))
        images.append(ci)
    out["images"] = images
    out["textures"] = d.get("textures", [])
    out["samplers"] = d.get("samplers", [])
    out["materials"] = d.get("materials", [])
    out["cameras"] = d.get("cameras", [])
    out["extensions"] = d.get("extensions", {})

    out["animations"] = [canonical_animation(g, a, acc) for a in g.list("animations")]
    skins = []
    for s in g.list("skins"):
        cs = dict(s)
        if "inverseBindMatrices" in s:
            cs["inverseBindMatrices"] = acc(s["inverseBindMatrices"])
        skins.append(cs)
    out["skins"] = skins
    out["extras"] = d.get("extras")
    return out


def canonical_animation(g, a, acc):
    """An animation as a list of channels, each with its target (node index
    and name, path) and its sampler inlined: interpolation, key times (input)
    and values (output), decoded.  Channels are ordered by (node, path), so
    only what moves and how it moves matters, not the order of channels and
    samplers in the file."""
    nodes = g.list("nodes")
    samplers = a.get("samplers", [])
    ca = {k: v for k, v in a.items() if k not in ("samplers", "channels")}
    channels = []
    for ch in a.get("channels", []):
        t = ch.get("target", {})
        node = t.get("node")
        name = nodes[node].get("name") if isinstance(node, int) and 0 <= node < len(nodes) else None
        si = ch.get("sampler")
        if not isinstance(si, int) or not 0 <= si < len(samplers):
            raise GltfError("%s: animation %r: channel refers to sampler %r"
                            % (g.path, a.get("name"), si))
        s = samplers[si]
        cc = {k: v for k, v in ch.items() if k not in ("sampler", "target")}
        cc["target"] = dict(t, node_name=name)
        cc["interpolation"] = s.get("interpolation", "LINEAR")
        cc["input"] = acc(s["input"])
        cc["output"] = acc(s["output"])
        channels.append(cc)
    channels.sort(key=lambda c: (str(c["target"].get("node")), str(c["target"].get("path"))))
    ca["channels"] = channels
    return ca


def canonical_node(n):
    c = dict(n)
    if "matrix" not in c:
        c.setdefault("translation", [0.0, 0.0, 0.0])
        c.setdefault("rotation", [0.0, 0.0, 0.0, 1.0])
        c.setdefault("scale", [1.0, 1.0, 1.0])
    return c


# --------------------------------------------------------------------------
# Comparison
# --------------------------------------------------------------------------

def close(a, b):
    return abs(a - b) <= TOL * max(1.0, abs(a), abs(b))


def is_num(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def fmt(x):
    s = json.dumps(x, sort_keys=True, default=str) if not isinstance(x, float) else repr(x)
    return s if len(s) <= 120 else s[:117] + "..."


def label(seq, i):
    """'[3](Floor)' for named objects."""
    item = seq[i]
    if isinstance(item, dict) and isinstance(item.get("name"), str):
        return "[%d](%s)" % (i, item["name"])
    if isinstance(item, dict) and isinstance(item.get("target"), dict):
        t = item["target"]
        return "[%d](%s.%s)" % (i, t.get("node_name", t.get("node")), t.get("path"))
    return "[%d]" % i


def compare(a, b, path, diffs):
    if len(diffs) >= MAX_DIFFS:
        return
    if isinstance(a, Accessor) or isinstance(b, Accessor):
        if not (isinstance(a, Accessor) and isinstance(b, Accessor)):
            diffs.append("%s: %s != %s" % (path, describe(a), describe(b)))
        else:
            compare_accessor(a, b, path, diffs)
        return
    if isinstance(a, Image) or isinstance(b, Image):
        if not (isinstance(a, Image) and isinstance(b, Image)) or a.sha256 != b.sha256:
            diffs.append("%s: image bytes differ (%s != %s)" % (path, describe(a), describe(b)))
        return
    if is_num(a) and is_num(b):
        if not close(float(a), float(b)):
            diffs.append("%s: %s != %s" % (path, fmt(a), fmt(b)))
        return
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b), key=str):
            sub = "%s.%s" % (path, k) if path else str(k)
            if k not in a:
                diffs.append("%s: missing in A (B has %s)" % (sub, describe(b[k])))
            elif k not in b:
                diffs.append("%s: missing in B (A has %s)" % (sub, describe(a[k])))
            else:
                compare(a[k], b[k], sub, diffs)
        return
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            diffs.append("%s: %d items != %d items" % (path, len(a), len(b)))
        for i in range(min(len(a), len(b))):
            compare(a[i], b[i], path + label(a, i), diffs)
        return
    if a != b:
        diffs.append("%s: %s != %s" % (path, describe(a), describe(b)))


def describe(x):
    if isinstance(x, Accessor):
        return "accessor %s x %d" % (x.type, len(x.values))
    if isinstance(x, Image):
        return "%d bytes sha256 %s" % (x.size, x.sha256[:16])
    if isinstance(x, (dict, list)):
        return fmt(json.loads(json.dumps(x, default=describe)))
    return fmt(x)


def compare_accessor(a, b, path, diffs):
    if a.type != b.type:
        diffs.append("%s: type %s != %s" % (path, a.type, b.type))
        return
    if len(a.values) != len(b.values):
        diffs.append("%s: count %d != %d" % (path, len(a.values), len(b.values)))
        return
    bad = 0
    for k, (va, vb) in enumerate(zip(a.values, b.values)):
        if all(close(float(x), float(y)) for x, y in zip(va, vb)):
            continue
        if bad < MAX_DIFFS_PER_ACCESSOR:
            diffs.append("%s[%d]: %s != %s" % (path, k, fmt(list(va)), fmt(list(vb))))
        bad += 1
    if bad > MAX_DIFFS_PER_ACCESSOR:
        diffs.append("%s: ... %d of %d elements differ" % (path, bad, len(a.values)))


def content_diff(path_a, path_b):
    ca = canonical(Gltf(path_a))
    cb = canonical(Gltf(path_b))
    diffs = []
    compare(ca, cb, "", diffs)
    return diffs


# --------------------------------------------------------------------------
# Well-formedness (samples_wellformed)
# --------------------------------------------------------------------------

def check(path):
    """Problems found in one file, as a list of strings."""
    problems = []
    try:
        g = Gltf(path)
        d = g.doc
        version = str(d.get("asset", {}).get("version", ""))
        if not version.startswith("2."):
            problems.append("asset.version is %r, not 2.x" % version)
        buffers_ok = True
        for i in range(len(g.list("buffers"))):
            try:
                g.buffer(i)
            except GltfError as e:
                problems.append(str(e))
                buffers_ok = False
        for i in range(len(g.list("accessors")) if buffers_ok else 0):
            try:
                g.accessor(i)
            except (GltfError, KeyError, struct.error) as e:
                problems.append("accessor %d: %s" % (i, e))
        for i, img in enumerate(g.list("images")):
            try:
                g.image_bytes(img)
            except GltfError as e:
                problems.append("image %d: %s" % (i, e))
        for m in g.list("meshes"):
            for p in m.get("primitives", []):
                for k, v in list(p.get("attributes", {}).items()) + [("indices", p.get("indices"))]:
                    if v is not None and not 0 <= v < len(g.list("accessors")):
                        problems.append("mesh %r: %s refers to accessor %r" % (m.get("name"), k, v))
        lights = d.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
        # The render engine's hand-off (samples/blender/*/handoff) may be lit
        # by its extension alone: Blender's area lights and world.
        pb = d.get("extensions", {}).get("PHOTONBRIDGE_blender", {})
        if not g.list("cameras"):
            problems.append("no camera")
        if not lights and not pb.get("lights") and not pb.get("world"):
            problems.append("no KHR_lights_punctual light (nor a PHOTONBRIDGE_blender light or world)")
        if not g.list("meshes"):
            problems.append("no mesh")
    except (GltfError, OSError, KeyError, ValueError) as e:
        problems.append(str(e))
    prefix = path + ": "
    return [p if p.startswith(prefix) else prefix + p.replace(prefix, "")
            for p in problems]


ANIM_KEYS = 49              # 2 s at 24 fps, both ends included
ANIM_T0, ANIM_T1 = 0.0, 2.0
ANIM_TOL = 1e-5
NODE_KIND = {  # --animated KIND -> what the node must carry
    "light": lambda n: "KHR_lights_punctual" in n.get("extensions", {}),
    "camera": lambda n: "camera" in n,
    "mesh": lambda n: "mesh" in n,
}


def check_animated(path, node_name, kind, paths):
    """Problems with one animated sample: it must have at least one
    animation; every channel must move node `node_name` (which must be a
    `kind` node) by node TRS (translation / rotation / scale), and together
    they must cover `paths`; every channel has ANIM_KEYS keys evenly spaced
    from ANIM_T0 to ANIM_T1 s, really moves the node, and starts from the
    node's static TRS (the file's static pose is the first frame's pose);
    rotation keys are unit quaternions without sign flips between
    consecutive keys."""
    problems = []
    g = Gltf(path)
    d = g.doc
    nodes = g.list("nodes")
    named = [n for n in nodes if n.get("name") == node_name]
    if len(named) != 1:
        return ["%d nodes named %r, expected 1" % (len(named), node_name)]
    if not NODE_KIND[kind](named[0]):
        problems.append("node %r is not a %s node" % (node_name, kind))
    static = canonical_node(named[0])
    anims = g.list("animations")
    if not anims:
        problems.append("no animations")
    if g.list("skins"):
        problems.append("has skins; the samples animate node TRS only")

    def acc(i):
        return Accessor(g.accessor(i), d["accessors"][i]["type"])

    seen = set()
    step = (ANIM_T1 - ANIM_T0) / (ANIM_KEYS - 1)
    for a in anims:
        ca = canonical_animation(g, a, acc)
        if not ca["channels"]:
            problems.append("animation %r has no channels" % a.get("name"))
        for ch in ca["channels"]:
            t = ch["target"]
            tp = t.get("path")
            who = "animation %r, channel %s.%s" % (a.get("name"), t.get("node_name"), tp)
            if t.get("node_name") != node_name:
                problems.append("%s: moves node %r, expected only %r"
                                % (who, t.get("node_name"), node_name))
                continue
            if tp not in ("translation", "rotation", "scale"):
                problems.append("%s: not a node TRS path" % who)
                continue
            seen.add(tp)
            times = [v[0] for v in ch["input"].values]
            if len(times) != ANIM_KEYS:
                problems.append("%s: %d keys, expected %d" % (who, len(times), ANIM_KEYS))
            if not times:
                continue
            if abs(times[0] - ANIM_T0) > ANIM_TOL or abs(times[-1] - ANIM_T1) > ANIM_TOL:
                problems.append("%s: keys from %.6g to %.6g s, expected %g to %g s"
                                % (who, times[0], times[-1], ANIM_T0, ANIM_T1))
            if len(times) == ANIM_KEYS and any(abs(b - a_ - step) > ANIM_TOL
                                               for a_, b in zip(times, times[1:])):
                problems.append("%s: keys not %.6g s apart" % (who, step))
            cubic = ch["interpolation"] == "CUBICSPLINE"
            vals = ch["output"].values
            if len(vals) != len(times) * (3 if cubic else 1):
                problems.append("%s: %d values for %d keys (%s)"
                                % (who, len(vals), len(times), ch["interpolation"]))
                continue
            keys = vals[1::3] if cubic else vals
            first = keys[0]
            if any(abs(x - y) > ANIM_TOL for x, y in zip(first, static[tp])):
                problems.append("%s: first key %s is not the node's static %s %s"
                                % (who, fmt(list(first)), tp, fmt(static[tp])))
            span = max(abs(x - y) for k in keys for x, y in zip(k, first))
            if span < 1e-3:
                problems.append("%s: does not move (largest change %.3g)" % (who, span))
            if tp == "rotation":
                if any(abs(sum(c * c for c in q) - 1.0) > 1e-4 for q in keys):
                    problems.append("%s: rotation keys are not unit quaternions" % who)
                flips = sum(1 for p, q in zip(keys, keys[1:])
                            if sum(x * y for x, y in zip(p, q)) < 0.0)
                if flips:
                    problems.append("%s: %d quaternion sign flips between keys" % (who, flips))
    missing = sorted(set(paths) - seen)
    if anims and missing:
        problems.append("node %r: no %s channel" % (node_name, ", ".join(missing)))
    return ["%s: %s" % (path, p) for p in problems]


def triangles(path):
    g = Gltf(path)
    n = 0
    for m in g.list("meshes"):
        for p in m.get("primitives", []):
            if p.get("mode", 4) == 4:
                acc = p["indices"] if "indices" in p else p["attributes"]["POSITION"]
                n += g.doc["accessors"][acc]["count"] // 3
    return n


def main(argv):
    if len(argv) >= 2 and argv[0] == "--check":
        problems, files = [], []
        for p in argv[1:]:
            if os.path.isdir(p):
                found = sorted(os.path.join(r, f) for r, _, fs in os.walk(p) for f in fs
                               if f.endswith((".gltf", ".glb")))
                if not found:
                    problems.append("%s: no .gltf or .glb files" % p)
                files += found
            else:
                files.append(p)
        for p in files:
            found = check(p)
            problems += found
            if not found:
                print("ok: %s (%d triangles)" % (p, triangles(p)))
        for p in problems:
            print("FAIL: " + p)
        return 1 if problems else 0
    if len(argv) >= 5 and argv[0] == "--animated" and (len(argv) - 1) % 4 == 0:
        problems = []
        for k in range(1, len(argv), 4):
            path, node, kind, paths = argv[k:k + 4]
            if kind not in NODE_KIND:
                print("error: node kind %r is not one of %s" % (kind, sorted(NODE_KIND)),
                      file=sys.stderr)
                return 2
            try:
                found = check_animated(path, node, kind, paths.split(","))
            except (GltfError, OSError, KeyError, ValueError) as e:
                found = ["%s: %s" % (path, e)]
            problems += found
            if not found:
                print("ok: %s: %s (%s) animated (%s), %d keys over %g .. %g s"
                      % (path, node, kind, paths, ANIM_KEYS, ANIM_T0, ANIM_T1))
        for p in problems:
            print("FAIL: " + p)
        return 1 if problems else 0
    if len(argv) != 2 or argv[0].startswith("-"):
        print(__doc__.strip().split("\n\n")[1], file=sys.stderr)
        return 2
    try:
        diffs = content_diff(argv[0], argv[1])
    except (GltfError, OSError, KeyError, ValueError) as e:
        print("error: %s" % e, file=sys.stderr)
        return 2
    if diffs:
        print("%s and %s differ in content:" % (argv[0], argv[1]))
        for line in diffs:
            print("  " + line)
        if len(diffs) >= MAX_DIFFS:
            print("  ... (stopped after %d differences)" % MAX_DIFFS)
        return 1
    print("same content: %s %s" % (argv[0], argv[1]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
