"""The JSON of a glTF or GLB file, and the facts about it that decide what
two renderers may show differently by design (validate.py's report notes).
Standard library only: validate.py imports it, and so does cycles_gltf.py
inside Blender."""
import json
import struct

# What validation's Cycles glTF path models (cycles_gltf.py); extensions
# outside this set are ignored by it.
CYCLES_EXTENSIONS = {"KHR_lights_punctual", "KHR_materials_specular", "KHR_materials_ior",
                     "KHR_materials_transmission", "KHR_materials_emissive_strength", "KHR_texture_transform"}


class GltfError(Exception):
    """The file is not glTF JSON or a GLB container; str() is one line."""


def read(path):
    """The JSON of a .gltf, or the JSON chunk of a .glb, as a dict."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise GltfError("cannot read: %s" % e.strerror)
    if data[:4] == b"glTF":
        if len(data) < 20:
            raise GltfError("GLB header: file too short")
        n, kind = struct.unpack_from("<II", data, 12)
        if kind != 0x4E4F534A:
            raise GltfError("GLB: the first chunk is not JSON")
        data = data[20:20 + n]
    try:
        doc = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as e:
        raise GltfError("not valid JSON: %s" % e)
    if not isinstance(doc, dict):
        raise GltfError("the JSON is not an object")
    return doc


def _texture_infos(m):
    """(JSON path suffix, textureInfo) of a material dict."""
    pbr = m.get("pbrMetallicRoughness") or {}
    out = [("pbrMetallicRoughness." + k, pbr.get(k)) for k in ("baseColorTexture", "metallicRoughnessTexture")]
    out += [(k, m.get(k)) for k in ("normalTexture", "emissiveTexture", "occlusionTexture")]
    for ext, keys in (("KHR_materials_specular", ("specularTexture", "specularColorTexture")),
                      ("KHR_materials_transmission", ("transmissionTexture",))):
        e = (m.get("extensions") or {}).get(ext) or {}
        out += [("extensions.%s.%s" % (ext, k), e.get(k)) for k in keys]
    return [(k, v) for k, v in out if isinstance(v, dict)]


def facts(doc):
    """What the file uses that the renderers treat differently: lists of
    JSON paths (or names) per feature."""
    f = {"alpha": [], "color0": [], "texture_transform": [], "texcoord1": [], "extension_textures": [],
         "occlusion": [], "rough_transmission": [], "light_range": [], "unmodelled_extensions": []}
    for i, m in enumerate(doc.get("materials") or []):
        if not isinstance(m, dict):
            continue
        w = "materials[%d]" % i
        # A PHOTONBRIDGE_blender material is rendered from the extension
        # (Blender's shader, its Alpha as Cycles does): what photonbridge
        # skips of the plain glTF form does not apply to it.
        blender = "PHOTONBRIDGE_blender" in (m.get("extensions") or {})
        if m.get("alphaMode") in ("MASK", "BLEND") and not blender:
            f["alpha"].append("%s (%s)" % (w, m["alphaMode"]))
        for k, t in _texture_infos(m):
            if k == "occlusionTexture":
                f["occlusion"].append("%s.%s" % (w, k))
                continue
            if "KHR_texture_transform" in (t.get("extensions") or {}):
                f["texture_transform"].append("%s.%s" % (w, k))
            if t.get("texCoord", 0) != 0:
                f["texcoord1"].append("%s.%s" % (w, k))
            if k.startswith("extensions.") and not blender:
                f["extension_textures"].append("%s.%s" % (w, k))
        tr = (m.get("extensions") or {}).get("KHR_materials_transmission") or {}
        pbr = m.get("pbrMetallicRoughness") or {}
        if not blender and tr.get("transmissionFactor", 0) > 0 and (pbr.get("roughnessFactor", 1.0) >= 0.02 or
                                                    "metallicRoughnessTexture" in pbr):
            f["rough_transmission"].append(w)
    for i, me in enumerate(doc.get("meshes") or []):
        for j, p in enumerate((me or {}).get("primitives") or []):
            if "COLOR_0" in ((p or {}).get("attributes") or {}):
                f["color0"].append("meshes[%d].primitives[%d]" % (i, j))
    lights = ((doc.get("extensions") or {}).get("KHR_lights_punctual") or {}).get("lights") or []
    for i, l in enumerate(lights):
        if isinstance(l, dict) and l.get("range") not in (None, 0):
            f["light_range"].append("KHR_lights_punctual.lights[%d]" % i)
    f["unmodelled_extensions"] = sorted(set(e for e in doc.get("extensionsUsed") or [] if isinstance(e, str))
                                        - CYCLES_EXTENSIONS)
    return f
