"""A glTF or GLB file as a Cycles scene whose materials evaluate glTF's
metallic-roughness model the way photonbridge's reference does, for
validate (run inside Blender; run_cycles.py --gltf uses it).

Blender's own importer (io_scene_gltf2) reads the file: meshes, normals, uv
sets, COLOR_0, images, node transforms, lights. Its materials are not kept:
it maps glTF onto the Principled BSDF, whose diffuse (Disney, retro-
reflective) and specular (Fresnel rising to 1 at grazing even at Specular 0)
are not glTF's; a Principled Cornell box renders 16.7 % brighter in Cycles 3.4
than with Diffuse BSDFs (shared/VALIDATION.md). Each glTF material is instead
rebuilt from Cycles closures and math nodes (build_material), so that per
shading point, with c = |n . wo| (n the shading normal) and m5 = (1 - c)^5:

  base  = baseColorFactor x baseColorTexture x COLOR_0 (rgb; alpha likewise)
  m, r  = metallicFactor x B, roughnessFactor x G of metallicRoughnessTexture
  s, sc = KHR_materials_specular factor x specularTexture.a, colour factor x
          specularColorTexture; a layer whose colour factor is 0 is dropped
          whole (s = 0), as photonbridge's loader does for Blender's
          "Specular 0" export (scene.h)
  t     = KHR_materials_transmission factor x transmissionTexture.r
  F0    = min(((ior - 1) / (ior + 1))^2 x sc, 1)          (KHR_materials_ior)
  Fd    = s (F0 + (1 - F0) m5)      dielectric Schlick, F90 = s
  Fm    = base + (1 - base) m5      metal Schlick (glTF Appendix B)
  Diffuse BSDF  (Lambert)  base x (1-m)(1-t) x clamp(1 - s max_rgb(F0 + (1-F0) m5))
  mirrors (r < 0.02): sharp Glossy BSDF  m Fm + (1-m)(1-t) Fd + (1-m) t Fg
  rough:  Principled BSDF at Metallic 1 (one GGX lobe, F on the half vector)
          of weight w = m + k and colour (m base + k F0) / w, k = (1-m)(1-t) s
  glass:  sharp Refraction BSDF  (1-m) t (1 - Fg) base  (Fg: the exact
          dielectric Fresnel of ior at n . wo, the Fresnel node), or a GGX
          Glass BSDF of colour base and weight (1-m) t when rough
  Emission  emissiveFactor x emissiveTexture x emissive_strength, front side
          only unless doubleSided
  alpha   MASK / BLEND mix with a Transparent BSDF (the reference is opaque)

which is src/ref/bsdf.c term by term: the diffuse weight there is also
1 - max(F(n . wo)) (not the specification's per-direction fresnel_mix), the
glass lobe uses the exact Fresnel equations, and roughness under 0.02
(PB_SPECULAR_ROUGHNESS) is a perfect mirror on both sides. For mirrors the
Fresnel weight at n . wo is exact (h = n). What Cycles 3.4's nodes cannot say
exactly (NOTES): a rough lobe needs its Fresnel per direction pair, which
node colours cannot give (one value per shading point; at n . wo a rough
dielectric wall seen at grazing angles came out 2x too glossy), and the only
3.4 closure that evaluates a coloured Fresnel on wo . h is the Principled
BSDF's specular lobe, whose F = c + (1 - c) FH uses the normalised dielectric
Fresnel FH of ior 1.5 instead of Schlick's (1 - wo . h)^5 (at most 0.037
apart, see build_material); Cycles 3.4's GGX has the separable Smith
G1(wo) G1(wi) (kernel/closure/bsdf_microfacet.h), the reference the
height-correlated G2 (Heitz 2014), which leaves a rough lobe's directional
albedo equal at normal view and lower at grazing view (measured by
integration: roughness 0.35: -0.4 % at cos 0.2; 0.6: -0.7 / -3.7 % at cos 0.5
/ 0.2; 0.9: -5.8 / -14.7 %; 1.0: -9.3 / -20.5 %); rough transmission is rough
here, as the specification says, and smooth in the reference.

Textures: every image is converted to a linear float image first (sRGB
decoded per texel with the exact IEC 61966-2-1 curve, like
pb_texture_sample), because Cycles keeps 8-bit sRGB images as bytes and
filters them before decoding (NODE_IMAGE_COMPRESS_AS_SRGB), which the
reference does not. Image nodes repeat; a CLAMP_TO_EDGE axis is clamped to the
outer texel centres and a MIRRORED_REPEAT axis ping-ponged first, which is
what bilinear filtering with those wrap modes gives. magFilter NEAREST is
Closest, anything else Linear (the reference has no mipmaps either).
KHR_texture_transform and texCoord through the importer's own conversion
(texture_transform_gltf_to_blender) and its uv map names.

Lights: the importer's watt convention (W = cd x 4 pi / 683, sun W/m^2 = lx /
683; COMPAT mode for files in Blender's "Unitless" units) is photonbridge's;
radii and sun angles are set to 0 (glTF lights are punctual). Cycles 3.4's
spot is P/(4 pi) x cos(alpha) x smoothstep(blend) inside its cone
(kernel/light spot_attenuation, measured in cycles_calib); here blend is 0
and the light's node tree multiplies by smoothstep((cos alpha - cos outer) /
(cos inner - cos outer)) / cos alpha, glTF's profile exactly.
"""
import math

import bpy
from mathutils import Matrix, Vector

import gltf_json  # validation/ is on sys.path (run_cycles.py)

# Roughness below which both sides render a perfect mirror (scene.h).
SPECULAR_ROUGHNESS = 0.02

WRAP_REPEAT, WRAP_CLAMP, WRAP_MIRROR = 10497, 33071, 33648
FILTER_NEAREST = 9728


class ImportFailed(Exception):
    """The importer could not read the file; str() is one line."""


def one_line(text):
    """The last meaningful line of an error message (a traceback's last line)."""
    lines = [l.strip() for l in str(text).splitlines() if l.strip()]
    return lines[-1] if lines else "unknown error"


class _SkipAnimations:
    """An importer user extension: no animation is imported, so every node
    keeps its own TRS, the rest pose photonbridge renders for one picture."""

    def gather_import_animations(self, *args):
        args[-1].data.animations = None  # io_scene_gltf2 passes (animations, options, gltf)


def import_gltf(path, light_units="standard"):
    """Blender's glTF importer on `path`, in the current (empty) scene.
    Returns the importer object (its .data holds the parsed file). Raises
    ImportFailed with a one-line reason ("Blender's glTF importer: ..." for
    what the importer itself refuses)."""
    try:
        import numpy
        if not hasattr(numpy, "bool"):  # removed from Debian's numpy, still used by the add-on
            numpy.bool = bool
        from io_scene_gltf2.io.imp.gltf2_io_gltf import glTFImporter
        try:
            from io_scene_gltf2.blender.imp.gltf2_blender_gltf import BlenderGlTF
        except ImportError:  # Blender 4.3 and later dropped the gltf2_ prefixes
            from io_scene_gltf2.blender.imp.blender_gltf import BlenderGlTF
    except ImportError as e:
        raise ImportFailed("Blender's glTF importer is not available: %s" % one_line(e))
    # The operator's own defaults, as bpy.ops.import_scene.gltf would pass them.
    settings = {}
    for p in bpy.ops.import_scene.gltf.get_rna_type().properties:
        if p.identifier in ("rna_type", "filepath", "files", "filter_glob", "directory"):
            continue
        if hasattr(p, "default") and not getattr(p, "is_array", False):
            settings[p.identifier] = p.default
    settings["convert_lighting_mode"] = "COMPAT" if light_units == "unitless" else "SPEC"
    settings["import_user_extensions"] = [_SkipAnimations()]
    settings["import_pack_images"] = True
    try:
        gltf = glTFImporter(path, settings)
        gltf.read()
        gltf.checks()
        BlenderGlTF.create(gltf)
    except Exception as e:  # the importer raises ImportError, and whatever its code hits
        raise ImportFailed("Blender's glTF importer: " + one_line(e))
    if any(ob.animation_data and ob.animation_data.action for ob in bpy.data.objects):
        raise ImportFailed("Blender's glTF importer kept the file's animation (its user-extension hook changed), "
                           "so the rest pose photonbridge renders cannot be shown")
    return gltf


# ---------------------------------------------------------------------------
# Node graphs with constants folded: a value is a float, an RGB 3-tuple or an
# output socket; nodes are made only where a socket is involved, so a
# material without textures becomes a handful of closures with exact
# constants.

def linear_colorspace(image):
    """Scene-linear Rec.709: "Linear" in Blender 3.x, "Linear Rec.709" from
    Blender 4.0."""
    names = image.colorspace_settings.bl_rna.properties["name"].enum_items.keys()
    return "Linear" if "Linear" in names else "Linear Rec.709"


def _sharp(node):
    """A delta lobe: Blender 3.x's SHARP distribution; Blender 4.0 removed it,
    and its GGX at roughness 0 is the same singular lobe."""
    if "SHARP" in node.bl_rna.properties["distribution"].enum_items.keys():
        node.distribution = "SHARP"
    else:
        node.distribution = "GGX"
        node.inputs["Roughness"].default_value = 0.0


def _is_sock(v):
    return not isinstance(v, (int, float, tuple))


class Graph:
    def __init__(self, nt):
        self.nt = nt
        self.count = 0

    def node(self, kind, **props):
        n = self.nt.nodes.new(kind)
        for k, v in props.items():
            setattr(n, k, v)
        self.count += 1
        n.location = (-200 * (self.count % 12), -180 * (self.count // 12))
        return n

    def link(self, sock, value):
        """Sets input `sock` to `value` (constant or output socket)."""
        if _is_sock(value):
            self.nt.links.new(value, sock)
        elif isinstance(value, tuple):
            dv = sock.default_value
            if len(dv) == 4:
                sock.default_value = (value[0], value[1], value[2], 1.0)
            else:
                sock.default_value = value[:len(dv)]
        else:
            dv = sock.default_value
            if isinstance(dv, float):
                sock.default_value = float(value)
            else:
                sock.default_value = tuple(float(value) for _ in range(len(dv)))

    # scalars
    def math(self, op, a, b=0.0, fold=None):
        if fold and not _is_sock(a) and not _is_sock(b):
            return fold(a, b)
        n = self.node("ShaderNodeMath", operation=op)
        self.link(n.inputs[0], a)
        self.link(n.inputs[1], b)
        return n.outputs[0]

    def mul(self, a, b):
        for x, y in ((a, b), (b, a)):
            if not _is_sock(x) and x == 1.0:
                return y
            if not _is_sock(x) and x == 0.0:
                return 0.0
        return self.math("MULTIPLY", a, b, lambda x, y: x * y)

    def sub(self, a, b):
        if not _is_sock(b) and b == 0.0:
            return a
        return self.math("SUBTRACT", a, b, lambda x, y: x - y)

    def one_minus(self, a):
        return self.sub(1.0, a)

    def clamp01(self, a):
        if not _is_sock(a):
            return min(max(a, 0.0), 1.0)
        n = self.node("ShaderNodeClamp")
        self.link(n.inputs["Value"], a)
        return n.outputs[0]

    def maximum(self, a, b):
        return self.math("MAXIMUM", a, b, max)

    # colours (as vectors)
    def vmath(self, op, a, b, fold):
        if not _is_sock(a) and not _is_sock(b):
            return fold(_rgb(a), _rgb(b))
        n = self.node("ShaderNodeVectorMath", operation=op)
        self.link(n.inputs[0], a if _is_sock(a) else _rgb(a))
        self.link(n.inputs[1], b if _is_sock(b) else _rgb(b))
        return n.outputs[0]

    def cmul(self, a, b):
        """Per channel product; either may be a scalar."""
        for x, y in ((a, b), (b, a)):
            if not _is_sock(x) and _rgb(x) == (1.0, 1.0, 1.0):
                return y
            if not _is_sock(x) and _rgb(x) == (0.0, 0.0, 0.0):
                return (0.0, 0.0, 0.0)
        return self.vmath("MULTIPLY", a, b, lambda x, y: tuple(p * q for p, q in zip(x, y)))

    def cadd(self, a, b):
        for x, y in ((a, b), (b, a)):
            if not _is_sock(x) and _rgb(x) == (0.0, 0.0, 0.0):
                return y
        return self.vmath("ADD", a, b, lambda x, y: tuple(p + q for p, q in zip(x, y)))

    def cmix_white(self, c, f):
        """c + (1 - c) f: Schlick's interpolation towards white."""
        if not _is_sock(f) and f == 0.0:
            return c
        return self.cadd(c, self.cmul(self.vmath("SUBTRACT", 1.0, c, lambda x, y: tuple(p - q for p, q in zip(x, y))),
                                      f))

    def cmin1(self, c):
        return self.vmath("MINIMUM", c, 1.0, lambda x, y: tuple(min(p, q) for p, q in zip(x, y)))

    def cclamp01(self, c):
        if not _is_sock(c):
            return tuple(min(max(p, 0.0), 1.0) for p in _rgb(c))
        return self.vmath("MAXIMUM", self.cmin1(c), 0.0, None)

    def cmax_channel(self, c):
        if not _is_sock(c):
            return max(_rgb(c))
        n = self.node("ShaderNodeSeparateXYZ")
        self.link(n.inputs[0], c)
        return self.maximum(self.maximum(n.outputs[0], n.outputs[1]), n.outputs[2])

    def is_zero(self, v):
        return not _is_sock(v) and (v == 0.0 if not isinstance(v, tuple) else max(v) == 0.0)


def _rgb(v):
    return v if isinstance(v, tuple) else (float(v),) * 3


# ---------------------------------------------------------------------------
# Textures

def _srgb_to_linear_lut():
    out = []
    for b in range(256):
        v = b / 255.0
        out.append(v / 12.92 if v <= 0.04045 else ((v + 0.055) / 1.055) ** 2.4)
    return out


def linear_float_image(img, srgb):
    """A float copy of a Blender image holding linear values (sRGB decoded
    per texel when `srgb`, alpha linear), colour space Linear and channels
    packed (no premultiplication), so that Cycles filters linear texels as the
    reference does. None when the image has no pixels."""
    import numpy
    n = len(img.pixels)  # loads the image
    w, h = img.size
    if n == 0 or w * h * 4 != n:
        return None
    px = numpy.empty(n, dtype=numpy.float32)
    if img.is_float:
        # Float images (e.g. 16-bit PNG) are decoded to linear by Blender when
        # their colour space is sRGB; data images stay raw.
        img.colorspace_settings.name = "sRGB" if srgb else "Non-Color"
        img.pixels.foreach_get(px)
        lin = px
    else:
        img.pixels.foreach_get(px)  # byte / 255, undecoded
        b = numpy.clip(numpy.rint(px * 255.0), 0, 255).astype(numpy.int32)
        if srgb:
            lin = numpy.array(_srgb_to_linear_lut(), dtype=numpy.float32)[b]
            lin[3::4] = b[3::4] / 255.0
        else:
            lin = b.astype(numpy.float32) / 255.0
    out = bpy.data.images.new("%s (linear)" % img.name, w, h, alpha=True, float_buffer=True)
    out.colorspace_settings.name = linear_colorspace(out)
    out.alpha_mode = "CHANNEL_PACKED"
    out.pixels.foreach_set(lin)
    return out


class Textures:
    """Image nodes for glTF textureInfo objects, with their sampler, uv set
    and KHR_texture_transform (see the module comment)."""

    def __init__(self, gltf, doc, notes):
        self.gltf = gltf
        self.doc = doc
        self.notes = notes
        self.images = {}  # (image index, srgb) -> linear float bpy image

    def image(self, src, srgb):
        key = (src, srgb)
        if key not in self.images:
            try:
                from io_scene_gltf2.blender.imp.gltf2_blender_image import BlenderImage
            except ImportError:  # Blender 4.3 and later
                from io_scene_gltf2.blender.imp.image import BlenderImage
            BlenderImage.create(self.gltf, src)
            name = self.gltf.data.images[src].blender_image_name
            img = bpy.data.images.get(name) if name else None
            lin = linear_float_image(img, srgb) if img else None
            if lin is None:
                uri = (self.doc.get("images") or [{}] * (src + 1))[src].get("uri", "")
                raise ImportFailed("images[%d]: Blender cannot read the image%s" %
                                   (src, " " + uri if uri and not uri.startswith("data:") else ""))
            self.images[key] = lin
        return self.images[key]

    def sample(self, G, info, srgb, what):
        """(color socket, alpha socket) for a textureInfo dict, or None."""
        if not isinstance(info, dict) or not isinstance(info.get("index"), int):
            return None
        textures = self.doc.get("textures") or []
        ti = info["index"]
        if not 0 <= ti < len(textures):
            raise ImportFailed("%s.index: %d is not a texture" % (what, ti))
        tex = textures[ti]
        src = tex.get("source")
        if not isinstance(src, int):
            self.notes.append("%s: textures[%d] has no PNG/JPEG source; ignored" % (what, ti))
            return None
        samplers = self.doc.get("samplers") or []
        smp = samplers[tex["sampler"]] if isinstance(tex.get("sampler"), int) and 0 <= tex["sampler"] < len(samplers) \
            else {}
        img = self.image(src, srgb)
        w, h = img.size
        node = G.node("ShaderNodeTexImage", image=img, extension="REPEAT",
                      interpolation="Closest" if smp.get("magFilter") == FILTER_NEAREST else "Linear")
        # uv set and KHR_texture_transform, as the importer names and converts them.
        ext = (info.get("extensions") or {}).get("KHR_texture_transform")
        texcoord = info.get("texCoord", 0)
        if isinstance(ext, dict) and isinstance(ext.get("texCoord"), int):
            texcoord = ext["texCoord"]
        uv = G.node("ShaderNodeUVMap", uv_map="UVMap" if texcoord == 0 else "UVMap.%03d" % texcoord).outputs[0]
        if isinstance(ext, dict):
            try:
                from io_scene_gltf2.blender.com.gltf2_blender_conversion import texture_transform_gltf_to_blender
            except ImportError:  # Blender 4.3 and later
                from io_scene_gltf2.blender.com.conversion import texture_transform_gltf_to_blender
            t = texture_transform_gltf_to_blender(ext)
            m = G.node("ShaderNodeMapping", vector_type="POINT")
            G.link(m.inputs["Vector"], uv)
            m.inputs["Location"].default_value = (t["offset"][0], t["offset"][1], 0.0)
            m.inputs["Rotation"].default_value = (0.0, 0.0, t["rotation"])
            m.inputs["Scale"].default_value = (t["scale"][0], t["scale"][1], 1.0)
            uv = m.outputs[0]
        wraps = (smp.get("wrapS", WRAP_REPEAT), smp.get("wrapT", WRAP_REPEAT))
        if wraps != (WRAP_REPEAT, WRAP_REPEAT):
            # Blender's v is 1 - glTF's v; clamping to the outer texel centres
            # and ping-ponging are symmetric under that flip.
            sep = G.node("ShaderNodeSeparateXYZ")
            G.link(sep.inputs[0], uv)
            comb = G.node("ShaderNodeCombineXYZ")
            for axis, (wrap, size) in enumerate(zip(wraps, (w, h))):
                c = sep.outputs[axis]
                if wrap == WRAP_MIRROR:
                    c = G.math("PINGPONG", c, 1.0)
                if wrap in (WRAP_MIRROR, WRAP_CLAMP):
                    cl = G.node("ShaderNodeClamp")
                    G.link(cl.inputs["Value"], c)
                    cl.inputs["Min"].default_value = 0.5 / size
                    cl.inputs["Max"].default_value = 1.0 - 0.5 / size
                    c = cl.outputs[0]
                G.link(comb.inputs[axis], c)
            uv = comb.outputs[0]
        G.link(node.inputs["Vector"], uv)
        return node.outputs["Color"], node.outputs["Alpha"]


# ---------------------------------------------------------------------------
# Materials

def _factor(d, key, default):
    v = d.get(key, default) if isinstance(d, dict) else default
    return v


def build_material(mat, gmat, textures, vertex_color, what, used):
    """Replaces `mat`'s node tree by the glTF metallic-roughness model of the
    module comment for the glTF material dict `gmat` (None: glTF's default
    material). vertex_color: the primitive has COLOR_0 (importer: 'Col').
    used[kind] collects `what` for the approximate parts it builds ('rough',
    'rough glass', 'normal map')."""
    gmat = gmat or {}
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    G = Graph(nt)
    exts = gmat.get("extensions") or {}
    pbr = gmat.get("pbrMetallicRoughness") or {}

    bcf = _factor(pbr, "baseColorFactor", [1.0, 1.0, 1.0, 1.0])
    base, alpha = tuple(float(x) for x in bcf[:3]), float(bcf[3])
    t = textures.sample(G, pbr.get("baseColorTexture"), True, what + ".pbrMetallicRoughness.baseColorTexture")
    if t:
        base, alpha = G.cmul(base, t[0]), G.mul(alpha, t[1])
    if vertex_color:
        vc = G.node("ShaderNodeVertexColor", layer_name="Col")
        base, alpha = G.cmul(base, vc.outputs["Color"]), G.mul(alpha, vc.outputs["Alpha"])
    base = G.cclamp01(base)

    metal = float(_factor(pbr, "metallicFactor", 1.0))
    rough = float(_factor(pbr, "roughnessFactor", 1.0))
    t = textures.sample(G, pbr.get("metallicRoughnessTexture"), False,
                        what + ".pbrMetallicRoughness.metallicRoughnessTexture")
    if t:
        sep = G.node("ShaderNodeSeparateXYZ")
        G.link(sep.inputs[0], t[0])
        rough, metal = G.mul(rough, sep.outputs[1]), G.mul(metal, sep.outputs[2])
    metal, rough = G.clamp01(metal), G.clamp01(rough)

    spec_ext = exts.get("KHR_materials_specular")
    spec, spec_color = 1.0, (1.0, 1.0, 1.0)
    if isinstance(spec_ext, dict):
        spec = float(spec_ext.get("specularFactor", 1.0))
        spec_color = tuple(float(x) for x in spec_ext.get("specularColorFactor", [1.0, 1.0, 1.0]))
        t = textures.sample(G, spec_ext.get("specularTexture"), False,
                            what + ".extensions.KHR_materials_specular.specularTexture")
        if t:
            spec = G.mul(spec, t[1])
        if max(spec_color) <= 0.0:
            spec = 0.0  # photonbridge's reading of Blender's "Specular 0" (scene.h)
        else:
            t = textures.sample(G, spec_ext.get("specularColorTexture"), True,
                                what + ".extensions.KHR_materials_specular.specularColorTexture")
            if t:
                spec_color = G.cmul(spec_color, t[0])
    spec = G.clamp01(spec)
    ior_ext = exts.get("KHR_materials_ior")
    ior = float(ior_ext.get("ior", 1.5)) if isinstance(ior_ext, dict) else 1.5
    ior = 1e3 if ior == 0 else ior  # the spec's "infinite" index, as the loader reads it
    tr_ext = exts.get("KHR_materials_transmission")
    trans = 0.0
    if isinstance(tr_ext, dict):
        trans = float(tr_ext.get("transmissionFactor", 0.0))
        t = textures.sample(G, tr_ext.get("transmissionTexture"), False,
                            what + ".extensions.KHR_materials_transmission.transmissionTexture")
        if t:
            sep = G.node("ShaderNodeSeparateXYZ")
            G.link(sep.inputs[0], t[0])
            trans = G.mul(trans, sep.outputs[0])
    trans = G.clamp01(trans)

    # Normal map: n = normalize(TBN ((2 rgb - 1) (scale, scale, 1))); Cycles'
    # Normal Map node does TBN (2 rgb - 1) with Strength 1, so the scale is
    # applied to the colour first.
    normal = None
    ninfo = gmat.get("normalTexture")
    t = textures.sample(G, ninfo, False, what + ".normalTexture")
    if t:
        col = t[0]
        scale = float(ninfo.get("scale", 1.0))
        if scale != 1.0:  # ((2 c - 1) (s, s, 1) + 1) / 2 = c (s, s, 1) + (1 - s) (0.5, 0.5, 0)
            ma = G.node("ShaderNodeVectorMath", operation="MULTIPLY_ADD")
            G.link(ma.inputs[0], col)
            ma.inputs[1].default_value = (scale, scale, 1.0)
            ma.inputs[2].default_value = (0.5 - 0.5 * scale, 0.5 - 0.5 * scale, 0.0)
            col = ma.outputs[0]
        texcoord = ninfo.get("texCoord", 0)
        nm = G.node("ShaderNodeNormalMap", space="TANGENT",
                    uv_map="UVMap" if texcoord == 0 else "UVMap.%03d" % texcoord)
        G.link(nm.inputs["Color"], col)
        nm.inputs["Strength"].default_value = 1.0
        normal = nm.outputs["Normal"]
        used.setdefault("normal map", []).append(what)

    # m5 = (1 - |n . wo|)^5 from Layer Weight's Facing (blend 0.5: 1 - |N . I|).
    lw = G.node("ShaderNodeLayerWeight")
    lw.inputs["Blend"].default_value = 0.5
    if normal is not None:
        G.link(lw.inputs["Normal"], normal)
    m5 = G.math("POWER", lw.outputs["Facing"], 5.0)

    nonmetal = G.one_minus(metal)
    dielectric = G.mul(nonmetal, G.one_minus(trans))  # (1-m)(1-t)
    glassw = G.mul(nonmetal, trans)                   # (1-m) t
    k = G.mul(dielectric, spec)                       # the dielectric specular layer's weight
    r0 = ((ior - 1.0) / (ior + 1.0)) ** 2
    f0 = G.cmin1(G.cmul(r0, spec_color))
    fd_unit = G.cmix_white(f0, m5)                    # F0 + (1 - F0) m5
    kd = G.mul(dielectric, G.clamp01(G.one_minus(G.mul(spec, G.cmax_channel(fd_unit)))))
    # 1 where the surface is a perfect mirror (roughness < PB_SPECULAR_ROUGHNESS).
    if _is_sock(rough):
        delta = G.math("LESS_THAN", rough, SPECULAR_ROUGHNESS)
    else:
        delta = 1.0 if rough < SPECULAR_ROUGHNESS else 0.0
    glossy_w = G.one_minus(delta)

    closures = []

    def closure(kind, color=None, weight=1.0, **inputs):
        """A BSDF node (colour, inputs, the normal map), scaled by `weight`
        through a Mix Shader with an empty input when it is not 1."""
        if G.is_zero(weight):
            return None
        n = G.node(kind)
        if color is not None:
            G.link(n.inputs["Color"], color)
        for name, v in inputs.items():
            G.link(n.inputs[name.replace("_", " ")], v)
        if normal is not None:
            G.link(n.inputs["Normal"], normal)
        out = n.outputs[0]
        if _is_sock(weight) or weight != 1.0:
            mix = G.node("ShaderNodeMixShader")
            G.link(mix.inputs["Fac"], weight)
            nt.links.new(out, mix.inputs[2])
            out = mix.outputs[0]
        closures.append(out)
        return n

    if not G.is_zero(base):
        closure("ShaderNodeBsdfDiffuse", G.cmul(base, kd), weight=1.0 if not G.is_zero(kd) else 0.0, Roughness=0.0)
    # Perfect mirrors: a sharp Glossy BSDF whose colour is the Fresnel
    # weight at n . wo = h . wo, the reference's exactly; with glass, the
    # exact dielectric Fresnel Fg of its reflection (refraction below).
    mirror = G.cadd(G.cmul(k, fd_unit), G.cmul(metal, G.cmix_white(base, m5)))
    fg = None
    if not G.is_zero(glassw):
        fr = G.node("ShaderNodeFresnel")
        fr.inputs["IOR"].default_value = ior
        if normal is not None:
            G.link(fr.inputs["Normal"], normal)
        fg = fr.outputs[0]
        mirror = G.cadd(mirror, G.mul(glassw, fg))
    gl = closure("ShaderNodeBsdfGlossy", mirror, weight=delta)
    if gl:
        _sharp(gl)
    # Rough specular: Fresnel on the half vector needs a closure that
    # evaluates it per direction pair. Cycles 3.4's Principled BSDF at
    # Metallic 1 is one GGX lobe with F = c + (1 - c) FH(wo . h), FH the
    # dielectric Fresnel of ior 2 / (1 - sqrt(0.08 Specular)) - 1 normalised
    # to [0, 1] (bsdf_microfacet.h, interpolate_fresnel_color); at Specular
    # 0.5 (ior 1.5) FH is within 0.037 of Schlick's (1 - wo . h)^5 over the
    # whole hemisphere (cosine-weighted mean +0.006; ior 1.2 and 2 do worse).
    # The metal and dielectric layers, m (base + (1-base) F) + k (F0 + (1-F0) F),
    # are one such lobe of weight w = m + k and c = (m base + k F0) / w.
    w = G.math("ADD", metal, k, lambda x, y: x + y)
    if not G.is_zero(w):
        c = G.vmath("DIVIDE", G.cadd(G.cmul(metal, base), G.cmul(k, f0)), w,
                    lambda x, y: tuple(p / q if q else 0.0 for p, q in zip(x, y)))
        p = closure("ShaderNodeBsdfPrincipled", weight=G.mul(w, glossy_w), Base_Color=c, Metallic=1.0,
                    Specular=0.5, Specular_Tint=0.0, Roughness=rough, Anisotropic=0.0, Sheen=0.0, Clearcoat=0.0,
                    Transmission=0.0, Subsurface=0.0, Emission=(0.0, 0.0, 0.0), Emission_Strength=0.0)
        if p:
            p.distribution = "GGX"  # single scattering, as the reference
            used.setdefault("rough", []).append(what)
    if fg is not None:
        refr = closure("ShaderNodeBsdfRefraction", G.cmul(base, G.mul(glassw, G.one_minus(fg))), weight=delta,
                       IOR=ior)
        if refr:
            _sharp(refr)
        # Rough glass: Cycles' GGX Glass BSDF (Fresnel on the half vector),
        # as the specification says; its colour also tints the reflection.
        gb = closure("ShaderNodeBsdfGlass", base, weight=G.mul(glassw, glossy_w), Roughness=rough, IOR=ior)
        if gb:
            gb.distribution = "GGX"
            used.setdefault("rough glass", []).append(what)

    emissive = tuple(float(x) for x in gmat.get("emissiveFactor", [0.0, 0.0, 0.0]))
    es = exts.get("KHR_materials_emissive_strength")
    if isinstance(es, dict):
        emissive = tuple(x * float(es.get("emissiveStrength", 1.0)) for x in emissive)
    if max(emissive) > 0.0:
        t = textures.sample(G, gmat.get("emissiveTexture"), True, what + ".emissiveTexture")
        if t:
            emissive = G.cmul(emissive, t[0])
        if not gmat.get("doubleSided", False):
            geo = G.node("ShaderNodeNewGeometry")
            emissive = G.cmul(emissive, G.one_minus(geo.outputs["Backfacing"]))
        em = G.node("ShaderNodeEmission")
        G.link(em.inputs["Color"], emissive)
        em.inputs["Strength"].default_value = 1.0
        closures.append(em.outputs[0])

    if not closures:  # black: a Diffuse BSDF of colour 0 keeps the surface opaque
        closure("ShaderNodeBsdfDiffuse", (0.0, 0.0, 0.0))
    shader = closures[0]
    for c in closures[1:]:
        add = G.node("ShaderNodeAddShader")
        nt.links.new(shader, add.inputs[0])
        nt.links.new(c, add.inputs[1])
        shader = add.outputs[0]

    mode = gmat.get("alphaMode", "OPAQUE")
    if mode in ("MASK", "BLEND"):
        cover = alpha
        if mode == "MASK":
            cutoff = float(gmat.get("alphaCutoff", 0.5))
            cover = G.math("GREATER_THAN", alpha, cutoff - 1e-7, lambda a, c: 1.0 if a > c else 0.0)
        if not (not _is_sock(cover) and cover >= 1.0):
            mix = G.node("ShaderNodeMixShader")
            G.link(mix.inputs["Fac"], cover)
            tr = G.node("ShaderNodeBsdfTransparent")
            nt.links.new(tr.outputs[0], mix.inputs[1])
            nt.links.new(shader, mix.inputs[2])
            shader = mix.outputs[0]
        mat.blend_method = "BLEND" if mode == "BLEND" else "CLIP"
    out = G.node("ShaderNodeOutputMaterial", target="CYCLES")
    nt.links.new(shader, out.inputs["Surface"])



def rebuild_materials(gltf, doc, notes):
    """Every material the importer made, rebuilt with build_material; mesh
    slots without a material get glTF's default material. Returns the number
    of Blender materials built."""
    textures = Textures(gltf, doc, notes)
    gmats = doc.get("materials") or []
    built = 0
    used = {}
    for i, pym in enumerate(gltf.data.materials or []):
        for vcol, name in (pym.blender_material or {}).items():
            mat = bpy.data.materials.get(name)
            if mat is None:
                continue
            build_material(mat, gmats[i] if i < len(gmats) else None, textures, vcol == "COLOR_0",
                           "materials[%d]" % i, used)
            built += 1
    default = None
    for ob in bpy.data.objects:
        if ob.type != "MESH":
            continue
        me = ob.data
        if len(me.materials) == 0 or any(m is None for m in me.materials):
            if default is None:
                default = bpy.data.materials.new("glTF default material")
                build_material(default, None, textures, False, "(default material)", used)
                built += 1
            if len(me.materials) == 0:
                me.materials.append(default)
            for k, m in enumerate(me.materials):
                if m is None:
                    me.materials[k] = default
    for kind, text in USED_NOTES:
        if used.get(kind):
            whats = sorted(set(used[kind]))
            notes.append("%s (%s%s)" % (text, ", ".join(whats[:4]), " and %d more" % (len(whats) - 4)
                                        if len(whats) > 4 else ""))
    return built


# What the approximate parts of build_material leave different from the
# reference, for the report (derivations in the module comment).
USED_NOTES = (
    ("rough", "rough specular lobes as Cycles 3.4's Principled metallic lobe: Fresnel c + (1 - c) FH(wo . h) with "
              "the dielectric FH of ior 1.5 (within 0.037 of Schlick's) and the separable Smith G, where the "
              "reference has the height-correlated G: the lobe's directional albedo equal at normal view, lower "
              "at grazing view (roughness 0.6: -3.7 %, 0.9: -14.7 % at cos 0.2)"),
    ("rough glass", "rough transmission as a GGX Glass BSDF (the reference refracts it smoothly; the Glass "
                    "BSDF's colour tints its reflection too)"),
    ("normal map", "normal maps with Blender's MikkTSpace tangents from the uvs (the reference: the file's "
                   "TANGENT, else its own from the uvs; the same frame on flat faces)"),
)


# ---------------------------------------------------------------------------
# Lights and camera

def _spot_profile(light, axis_world, inner, outer):
    """Light nodes that turn Cycles 3.4's spot (cos alpha inside a hard cone
    when spot_blend is 0) into glTF's: x smoothstep((cos alpha - cos outer) /
    (cos inner - cos outer)) / cos alpha. In a light's shader the Normal is
    the direction from the light to the point being lit (Cycles sets
    Ng = -D for point-like lights)."""
    light.use_nodes = True
    nt = light.node_tree
    nt.nodes.clear()
    G = Graph(nt)
    geo = G.node("ShaderNodeNewGeometry")
    dot = G.node("ShaderNodeVectorMath", operation="DOT_PRODUCT")
    G.link(dot.inputs[0], geo.outputs["Normal"])
    dot.inputs[1].default_value = tuple(axis_world)
    cos_a = dot.outputs["Value"]
    co, ci = math.cos(outer), math.cos(inner)
    x = G.clamp01(G.math("DIVIDE", G.sub(cos_a, co), ci - co))
    smooth = G.mul(G.mul(x, x), G.sub(3.0, G.mul(2.0, x)))
    strength = G.math("DIVIDE", smooth, G.maximum(cos_a, 1e-4))
    em = G.node("ShaderNodeEmission")
    em.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    G.link(em.inputs["Strength"], strength)
    out = G.node("ShaderNodeOutputLight")
    nt.links.new(em.outputs[0], out.inputs["Surface"])


def convert_lights():
    """Punctual lights as photonbridge has them (module comment). Also for
    Blender-built scenes: a Blender spot's glTF export is outer = spot_size /
    2, inner = outer (1 - spot_blend), the inverse of the importer's."""
    for ob in bpy.data.objects:
        if ob.type != "LIGHT":
            continue
        L = ob.data
        if L.type in ("POINT", "SPOT"):
            L.shadow_soft_size = 0.0
        if L.type == "SUN":
            L.angle = 0.0
        if L.type == "SPOT":
            outer = L.spot_size / 2.0
            inner = outer * (1.0 - L.spot_blend)  # the importer wrote blend = 1 - inner / outer
            L.spot_blend = 0.0
            axis = ob.matrix_world.to_3x3() @ Vector((0.0, 0.0, -1.0))
            axis.normalize()
            _spot_profile(L, axis, inner, outer)


def camera_from_info(info, name=None):
    """A Blender camera equal to the one photonbridge renders: `info` is
    `photonbridge info --json` (glTF coordinates, relative to its origin)."""
    cams = info.get("cameras") or []
    cam = next((c for c in cams if c.get("name") == name), None) if name else (cams[0] if cams else None)
    if cam is None:
        raise ImportFailed("photonbridge reports no camera%s" % (" named '%s'" % name if name else ""))
    org = info.get("origin") or [0.0, 0.0, 0.0]

    def to_blender(v):  # glTF +Y up -> Blender +Z up: (x, y, z) -> (x, -z, y)
        return Vector((v[0], -v[2], v[1]))

    pos = to_blender([p + o for p, o in zip(cam["position"], org)])
    fwd = to_blender(cam["forward"]).normalized()
    up = to_blender(cam["up"]).normalized()
    right = fwd.cross(up).normalized()
    up = right.cross(fwd)
    data = bpy.data.cameras.new("photonbridge camera")
    data.type = "PERSP"
    data.lens_unit = "FOV"
    data.sensor_fit = "VERTICAL"
    data.angle_y = cam["yfov"]
    scale = max(max(abs(a - b) for a, b in zip(info.get("bounds_max", [1] * 3), info.get("bounds_min", [0] * 3))),
                1e-6)
    data.clip_start = min(1e-3, 1e-5 * scale)  # the reference does not clip near the camera
    data.clip_end = 1e4 * scale + 1e4
    ob = bpy.data.objects.new("photonbridge camera", data)
    bpy.context.scene.collection.objects.link(ob)
    m = Matrix.Identity(4)
    for r in range(3):  # columns: camera +X right, +Y up, +Z backwards
        m[r][0], m[r][1], m[r][2], m[r][3] = right[r], up[r], -fwd[r], pos[r]
    ob.matrix_world = m
    bpy.context.scene.camera = ob
    return cam


def image_size(cam, width, height):
    """pb_camera_image_size (src/scene/scene.c), in float32 as there."""
    import numpy
    aspect = numpy.float32(cam.get("aspect") or 0.0)
    if not aspect > 0:
        aspect = numpy.float32(4.0) / numpy.float32(3.0)
    if width and height:
        return width, height
    if width:
        return width, max(1, int(numpy.floor(numpy.float32(width) / aspect + numpy.float32(0.5))))
    if height:
        return max(1, int(numpy.floor(numpy.float32(height) * aspect + numpy.float32(0.5)))), height
    return 640, max(1, int(numpy.floor(numpy.float32(640.0) / aspect + numpy.float32(0.5))))


def setup(path, info, materials="gltf", camera=None):
    """The whole Cycles scene for `path` in the current empty scene.
    materials: 'gltf' (rebuilt, the module comment) or 'principled' (the
    importer's own). Returns (camera dict, notes). Raises ImportFailed."""
    try:
        doc = gltf_json.read(path)
    except gltf_json.GltfError as e:
        raise ImportFailed(str(e))
    gltf = import_gltf(path, info.get("light_units", "standard"))
    notes = []
    if materials == "gltf":
        rebuild_materials(gltf, doc, notes)
    convert_lights()
    for ob in list(bpy.data.objects):
        if ob.type == "CAMERA":
            bpy.data.objects.remove(ob)
    cam = camera_from_info(info, camera)
    return cam, notes
