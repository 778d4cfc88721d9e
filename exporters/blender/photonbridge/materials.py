"""Blender materials to glTF materials plus their PHOTONBRIDGE_blender
extension (exporters/blender/PHOTONBRIDGE_blender.md).

The surface shader reached from the active Material Output is read as it is:
a Principled BSDF (every input of Blender 3.4's Principled v1), a Diffuse
BSDF, an Emission shader or a Holdout. Image Texture nodes linked to an input
(directly, through Separate RGB/Color for one channel, or through a Normal
Map node) become glTF textures; a Color Attribute node (or a Geometry
Attribute node's Color) on the base colour becomes the primitives' COLOR_0
and the extension's "vertexColor". Node groups are read through (a socket
inside a group that a Group Input drives takes the group node's input, linked
or not) and so are reroutes. Whatever else the tree holds is a warning
naming the material and the node, and the input keeps its own value: a
material is never refused.

The plain glTF approximation follows Blender 3.4's own exporter
(io_scene_gltf2/blender/exp/gltf2_blender_gather_materials*.py, read on this
machine) so that other viewers and photonbridge before the extension see
the same material Blender's exporter would write:
- baseColorFactor: Base Color (clamped to [0, 1]) and Alpha, white where a
  texture drives it; metallic/roughness factors, 1 where textured;
- KHR_materials_specular only when Specular != 0.5 or Specular Tint != 0,
  specularColorFactor = (1 - T) 0.08 S tint / F0(ior) + T tint with
  tint = (1 - St) + St base / luminance(base) (the exporter's conversion;
  [0, 0, 0] at Specular 0);
- KHR_materials_transmission when Transmission > 0; KHR_materials_ior when
  IOR != 1.5 and a specular or transmission extension is written;
- emissiveFactor = Emission x Strength, split into a unit factor and
  KHR_materials_emissive_strength when above 1;
- doubleSided unless backface culling; alphaMode MASK for CLIP, BLEND for
  BLEND/HASHED.
A Diffuse BSDF is written as a dielectric with Specular 0 (Blender's
exporter, which reads only Principled nodes, writes such a material as
white metal), an Emission shader as black with its emission."""

import math

GLTF_IOR = 1.5
BLENDER_SPECULAR = 0.5

# Principled BSDF inputs (Blender 3.4 socket names) -> extension members.
PRINCIPLED_INPUTS = [
    ("Base Color", "baseColor"), ("Subsurface", "subsurface"), ("Subsurface Radius", "subsurfaceRadius"),
    ("Subsurface Color", "subsurfaceColor"), ("Metallic", "metallic"), ("Specular", "specular"),
    ("Specular Tint", "specularTint"), ("Roughness", "roughness"), ("Anisotropic", "anisotropic"),
    ("Anisotropic Rotation", "anisotropicRotation"), ("Sheen", "sheen"), ("Sheen Tint", "sheenTint"),
    ("Clearcoat", "clearcoat"), ("Clearcoat Roughness", "clearcoatRoughness"), ("IOR", "ior"),
    ("Transmission", "transmission"), ("Transmission Roughness", "transmissionRoughness"),
    ("Emission", "emission"), ("Emission Strength", "emissionStrength"), ("Alpha", "alpha"),
]
COLOR_INPUTS = {"baseColor", "subsurfaceColor", "emission"}

# Principled BSDF v2 inputs (Blender 4.0+ socket names) -> the extension's
# "principled2" members; each is read only where the node has the socket
# (Thin Film from 4.2, Diffuse Roughness from 4.3).
PRINCIPLED2_INPUTS = [
    ("Base Color", "baseColor"), ("Metallic", "metallic"), ("Roughness", "roughness"), ("IOR", "ior"),
    ("Alpha", "alpha"), ("Diffuse Roughness", "diffuseRoughness"), ("Subsurface Weight", "subsurfaceWeight"),
    ("Subsurface Radius", "subsurfaceRadius"), ("Subsurface Scale", "subsurfaceScale"),
    ("Subsurface IOR", "subsurfaceIor"), ("Subsurface Anisotropy", "subsurfaceAnisotropy"),
    ("Specular IOR Level", "specularIorLevel"), ("Specular Tint", "specularTint"), ("Anisotropic", "anisotropic"),
    ("Anisotropic Rotation", "anisotropicRotation"), ("Transmission Weight", "transmissionWeight"),
    ("Coat Weight", "coatWeight"), ("Coat Roughness", "coatRoughness"), ("Coat IOR", "coatIor"),
    ("Coat Tint", "coatTint"), ("Sheen Weight", "sheenWeight"), ("Sheen Roughness", "sheenRoughness"),
    ("Sheen Tint", "sheenTint"), ("Emission Color", "emissionColor"), ("Emission Strength", "emissionStrength"),
    ("Thin Film Thickness", "thinFilmThickness"), ("Thin Film IOR", "thinFilmIor"),
]
COLOR2_INPUTS = {"baseColor", "specularTint", "coatTint", "sheenTint", "emissionColor"}
# Inputs a texture cannot drive in the extension (a vector): a link is a warning.
UNTEXTURED2 = {"subsurfaceRadius"}
BLENDER_COAT_ROUGHNESS = 0.03
# Blender 4.x's Principled BSDF defaults (a new node in 4.5; the loader's too).
PRINCIPLED2_DEFAULTS = {
    "baseColor": [0.8, 0.8, 0.8, 1.0], "metallic": 0.0, "roughness": 0.5, "ior": 1.5, "alpha": 1.0,
    "diffuseRoughness": 0.0, "subsurfaceWeight": 0.0, "subsurfaceRadius": [1.0, 0.2, 0.1], "subsurfaceScale": 0.05,
    "subsurfaceIor": 1.4, "subsurfaceAnisotropy": 0.0, "specularIorLevel": 0.5, "specularTint": [1.0, 1.0, 1.0, 1.0],
    "anisotropic": 0.0, "anisotropicRotation": 0.0, "transmissionWeight": 0.0, "coatWeight": 0.0,
    "coatRoughness": 0.03, "coatIor": 1.5, "coatTint": [1.0, 1.0, 1.0, 1.0], "sheenWeight": 0.0,
    "sheenRoughness": 0.5, "sheenTint": [1.0, 1.0, 1.0, 1.0], "emissionColor": [1.0, 1.0, 1.0, 1.0],
    "emissionStrength": 0.0, "thinFilmThickness": 0.0, "thinFilmIor": 1.33,
}

# subsurface_method, version-neutral: Blender 3.4's RANDOM_WALK (automatic
# radius) is 4.x's RANDOM_WALK_SKIN; 3.4's RANDOM_WALK_FIXED_RADIUS is 4.x's
# RANDOM_WALK. The principled2 model names the method by what it does.
SUBSURFACE_METHOD_V2 = {"BURLEY": "BURLEY", "RANDOM_WALK": "RANDOM_WALK_FIXED_RADIUS",
                        "RANDOM_WALK_SKIN": "RANDOM_WALK_SKIN"}


def is_principled_v2(node):
    """A Principled BSDF of Blender 4.0 or later (Principled v2)."""
    return "Specular IOR Level" in node.inputs


def _blender_version():
    """The running Blender's version; (0, 0, 0) outside Blender."""
    try:
        import bpy
        return tuple(bpy.app.version)
    except ImportError:
        return (0, 0, 0)


def _alpha_used(ext):
    """Does the written material have an Alpha below 1 or a texture on it?"""
    inputs = ext.get(ext.get("model"))
    alpha = inputs.get("alpha", 1.0) if isinstance(inputs, dict) else 1.0
    return "alpha" in ext.get("textures", {}) or (isinstance(alpha, (int, float)) and alpha < 1.0)


def _blender_4():
    """Does the running Blender have Principled v2 (4.0 or later)?"""
    try:
        import bpy
        return bpy.app.version >= (4, 0, 0)
    except (ImportError, AttributeError):
        return False

# glTF sampler constants.
NEAREST, LINEAR, LINEAR_MIPMAP_LINEAR = 9728, 9729, 9987
REPEAT, CLAMP, MIRROR = 10497, 33071, 33648


# Group nodes entered while the current material is read (innermost last):
# a Group Input inside a group tree stands for the input of the group node it
# was entered through. Reset per material (reset_groups); the same group used
# twice in one material with different inputs reads the last one entered.
_GROUPS = []


def reset_groups():
    del _GROUPS[:]


def _outer_input(group_input_socket):
    """The group node input a Group Input node's output stands for, or None."""
    tree = group_input_socket.id_data
    for g in reversed(_GROUPS):
        if g.node_tree == tree:
            for s in g.inputs:
                if s.identifier == group_input_socket.identifier:
                    return s
    return None


def _follow(socket):
    """(output socket feeding `socket`, value socket): through reroutes,
    into group nodes (to their Group Output's input) and out through Group
    Input nodes (to the group node's input). The output is None when
    nothing drives it; the value socket holds its default_value then (the
    group node's input for an unlinked exposed input)."""
    value = socket
    for _ in range(256):  # bounded: a malformed tree never hangs the writer
        if not socket.is_linked:
            return None, value
        link = socket.links[0]
        if link.is_muted:
            return None, value
        node = link.from_node
        if node.type == 'REROUTE':
            socket = node.inputs[0]
            continue
        if node.type == 'GROUP' and node.node_tree is not None and not node.mute:
            out = next((n for n in node.node_tree.nodes if n.type == 'GROUP_OUTPUT' and n.is_active_output), None) \
                or next((n for n in node.node_tree.nodes if n.type == 'GROUP_OUTPUT'), None)
            inner = next((i for i in out.inputs if i.identifier == link.from_socket.identifier), None) if out else None
            if inner is None:
                return None, value
            _GROUPS.append(node)
            socket = value = inner
            continue
        if node.type == 'GROUP_INPUT':
            outer = _outer_input(link.from_socket)
            if outer is None:
                return None, value
            socket = value = outer
            continue
        return link.from_socket, value
    return None, value


def _value(socket):
    v = _follow(socket)[1].default_value
    try:
        return [float(x) for x in v]
    except TypeError:
        return float(v)


def _source(socket):
    """The output socket feeding `socket`, through reroutes and node groups
    (None when unlinked or muted)."""
    return _follow(socket)[0]


def active_output(tree):
    """The active Material/World/Light Output for Cycles (or ALL)."""
    outputs = [n for n in tree.nodes if n.type in ('OUTPUT_MATERIAL', 'OUTPUT_WORLD', 'OUTPUT_LIGHT')]
    for n in outputs:
        if n.is_active_output and getattr(n, "target", 'ALL') in ('ALL', 'CYCLES'):
            return n
    for n in outputs:
        if getattr(n, "target", 'ALL') in ('ALL', 'CYCLES'):
            return n
    # Only EEVEE (or other) targets: Cycles uses none of them
    # (ntreeShaderOutputNode(SHD_OUTPUT_CYCLES) is NULL) and renders the
    # surface black, the world black, the light dark; so does the export.
    return None


def luminance(c):
    return 0.3 * c[0] + 0.6 * c[1] + 0.1 * c[2]


class MaterialWriter:
    """Adds materials (and their textures) to a glTF document under
    construction: doc.add_texture(uri, sampler) -> texture index."""

    def __init__(self, doc, images, warn):
        self.doc = doc
        self.images = images
        self.warn = warn
        self.cache = {}
        self.uses_normal_map = set()  # glTF material indices needing TANGENT
        self._xf_cache = {}  # Mapping node -> KHR_texture_transform (or None)
        # glTF material index -> the colour attribute its base colour reads
        # ('' for the mesh's render colour attribute), written as COLOR_0.
        self.vertex_color = {}

    # ---- textures ----------------------------------------------------------------

    def _sampler(self, node):
        f = NEAREST if node.interpolation == 'Closest' else LINEAR
        wrap = {'REPEAT': REPEAT, 'EXTEND': CLAMP, 'MIRROR': MIRROR}.get(node.extension, REPEAT)
        if node.extension == 'CLIP':
            self._warn_node(node, "extension Clip is written as clamp to edge")
            wrap = CLAMP
        return {"magFilter": f, "minFilter": LINEAR_MIPMAP_LINEAR if f == LINEAR else NEAREST,
                "wrapS": wrap, "wrapT": wrap}

    def _warn_node(self, node, what):
        self.warn_material("node '%s' (%s): %s" % (node.name, node.bl_label, what))

    def warn_material(self, text):
        """A warning about the material being written: in Blender's report
        (naming the material) and in the extension's "warnings"."""
        if text in self._mat_warnings:
            return  # the same node met again (a Mix Shader's inputs are looked at more than once)
        self._mat_warnings.append(text)
        self.warn("material '%s': %s" % (self.mat_name, text))

    def _image_node(self, node):
        """A usable Image Texture node, or None (with a warning)."""
        if node.image is None:
            self._warn_node(node, "no image; the input keeps its value")
            return None
        if node.projection != 'FLAT':
            self._warn_node(node, "projection %s is written as flat" % node.projection)
        vec = _source(node.inputs["Vector"])
        if vec is not None and vec.node.type == 'MAPPING':
            pass  # _uv_transform
        elif vec is not None and vec.node.type not in ('UVMAP', 'TEX_COORD'):
            self._warn_node(vec.node, "texture coordinates are not translated; the UV map is used")
        elif vec is not None and vec.node.type == 'TEX_COORD' and vec.name != 'UV':
            self._warn_node(vec.node, "texture coordinate '%s' is not translated; the UV map is used" % vec.name)
        return node

    def _texture_link(self, socket, name):
        """What drives a scalar or colour input: None (its value), or
        (image node, channel) with channel 'RGB', 'R', 'G', 'B' or 'A'."""
        src = _source(socket)
        if src is None:
            return None
        node = src.node
        if node.type == 'TEX_IMAGE':
            node = self._image_node(node)
            return (node, "A" if src.name == "Alpha" else "RGB") if node else None
        if node.type in ('SEPRGB', 'SEPARATE_COLOR'):
            mode = getattr(node, "mode", 'RGB')
            inner = _source(node.inputs[0])
            if mode == 'RGB' and inner is not None and inner.node.type == 'TEX_IMAGE' and inner.name == "Color":
                img = self._image_node(inner.node)
                chan = {"R": "R", "Red": "R", "G": "G", "Green": "G", "B": "B", "Blue": "B"}.get(src.name)
                return (img, chan) if img and chan else None
        self._warn_node(node, "drives %s and is not translated; its value %s is written"
                        % (name, _fmt(_value(socket))))
        return None

    def _vertex_color_link(self, socket):
        """The colour attribute a Color Attribute node (or an Attribute node
        of type Geometry, its Color output) feeding `socket` reads: its name,
        '' for the mesh's render colour attribute; None when none does."""
        src = _source(socket)
        if src is None or src.name != "Color":
            return None
        node = src.node
        if node.type == 'VERTEX_COLOR':
            return node.layer_name
        if node.type == 'ATTRIBUTE' and node.attribute_type == 'GEOMETRY':
            return node.attribute_name
        return None

    def _uv_transform(self, node):
        """KHR_texture_transform for a Mapping node (Point or Vector, constant
        inputs, fed by the UV map) in front of Image Texture `node`, or None.
        Blender maps uv_b' = L + Rz(theta) S uv_b with v up; glTF's v runs
        down (v_g = 1 - v_b, D = diag(1, -1)), so uv_g' = D Rz S D uv_g + b
        with D Rz(theta) D = Rz(-theta), the extension's rotation matrix for
        rotation theta, and b = D L + D Rz S (0, 1) + (0, 1) =
        (Lx - sin(theta) Sy, 1 - Ly - cos(theta) Sy)."""
        vec = _source(node.inputs["Vector"])
        if vec is None or vec.node.type != 'MAPPING':
            return None
        m = vec.node
        key = m.as_pointer()
        if key in self._xf_cache:
            return self._xf_cache[key]
        self._xf_cache[key] = None
        if m.vector_type not in ('POINT', 'VECTOR'):
            self._warn_node(m, "type %s is not translated; the UV map is used as it is" % m.vector_type)
            return None
        names = ("Location", "Rotation", "Scale") if m.vector_type == 'POINT' else ("Rotation", "Scale")
        if any(_source(m.inputs[n]) is not None for n in names):
            self._warn_node(m, "a linked Location, Rotation or Scale is not translated; the UV map is used as it is")
            return None
        inner = _source(m.inputs["Vector"])
        if inner is None or not (inner.node.type == 'UVMAP' or (inner.node.type == 'TEX_COORD' and inner.name == 'UV')):
            self._warn_node(m, "its Vector is not the UV map; the UV map is used as it is")
            return None
        loc = _value(m.inputs["Location"]) if m.vector_type == 'POINT' else [0.0, 0.0, 0.0]
        rot, scale = _value(m.inputs["Rotation"]), _value(m.inputs["Scale"])
        if abs(rot[0]) > 1e-6 or abs(rot[1]) > 1e-6:
            self._warn_node(m, "rotation about X and Y is not translated (Z only)")
        th, sx, sy = rot[2], scale[0], scale[1]
        xf = {"offset": [loc[0] - math.sin(th) * sy, 1.0 - loc[1] - math.cos(th) * sy], "rotation": th,
              "scale": [sx, sy]}
        self._xf_cache[key] = xf
        return xf

    def _texture_info(self, index, img_node, **extra):
        """A glTF textureInfo of texture `index` read through img_node's
        Mapping node, if any."""
        info = dict({"index": index}, **extra)
        xf = self._uv_transform(img_node) if img_node is not None else None
        if xf is not None:
            info["extensions"] = {"KHR_texture_transform": xf}
            self.doc.used.add("KHR_texture_transform")
        return info

    def _texture_entry(self, link, color):
        """The extension's texture entry (and glTF texture index) for a link."""
        node, channel = link
        if color and channel != "RGB":
            # The contract's colour inputs take a texture's RGB only (the
            # loader refuses a channel there): the socket keeps its value.
            self._warn_node(node, "its %s output drives a colour input and is not translated" % channel)
            return None, None
        image = node.image
        uri = self.images.texture_image(image, color=color and channel == "RGB", user=node.image_user)
        if uri is None:
            return None, None
        index = self.doc.add_texture(uri, self._sampler(node), self.images.float_image(image))
        entry = self._texture_info(index, node, texCoord=0, channel=channel)
        if color and self.images.linear(image):
            entry["colorSpace"] = "Non-Color"
        return entry, index

    # ---- materials -----------------------------------------------------------------

    def material(self, mat, holdout=False):
        """glTF material index of Blender material `mat` (None: a default
        grey), as a holdout when the object is one."""
        key = (mat.name if mat else None, holdout)
        if key in self.cache:
            return self.cache[key]
        self.mat_name = mat.name if mat else "(none)"
        self._mat_warnings = []
        reset_groups()
        self._vcol = None
        gm, ext = self._translate(mat, holdout)
        first_vcol = ext.pop("_vcolFirst", True)
        if self._vcol is not None and first_vcol:
            ext["vertexColor"] = "baseColor" if ext.get("model") in ("principled", "principled2") else "color"
        if self._mat_warnings:
            ext["warnings"] = self._mat_warnings
        gm["name"] = mat.name if mat else "default"
        if mat is not None:
            ext["blendMethod"] = mat.blend_method
            ext["alphaThreshold"] = mat.alpha_threshold
            ext["backfaceCulling"] = mat.use_backface_culling
            # Material > Settings > Bump Map Correction (Blender 4.2+): off,
            # Cycles neither smooths diffuse light on a mapped normal nor
            # lifts a specular normal that reflects below the surface.
            cyc = getattr(mat, "cycles", None)
            if cyc is not None and not getattr(cyc, "use_bump_map_correction", True):
                ext["bumpMapCorrection"] = False
            if not mat.use_backface_culling:
                gm["doubleSided"] = True
            if _blender_version() >= (4, 2, 0):
                # EEVEE's Render Method replaced the Blend Mode (4.2):
                # blend_method now reads HASHED for every Dithered material.
                # The glTF's alphaMode comes from the tree, as Blender's own
                # exporter does: BLEND where the Alpha is below 1 or driven.
                if _alpha_used(ext):
                    gm["alphaMode"] = "BLEND"
            elif mat.blend_method == 'CLIP':
                gm["alphaMode"] = "MASK"
                gm["alphaCutoff"] = mat.alpha_threshold
            elif mat.blend_method in ('BLEND', 'HASHED'):
                gm["alphaMode"] = "BLEND"
        gm.setdefault("extensions", {})["PHOTONBRIDGE_blender"] = ext
        index = self.doc.add_material(gm)
        if "normal" in ext.get("textures", {}):
            self.uses_normal_map.add(index)
        if self._vcol is not None:
            self.vertex_color[index] = self._vcol
        self.cache[key] = index
        return index

    def _translate(self, mat, holdout):
        if holdout:
            return self._plain_black(), {"model": "holdout"}
        # Cycles 3.4 renders an empty slot (or no slot) with its default
        # surface, a Diffuse BSDF of 0.8 grey (ShaderManager::add_default),
        # and a material without nodes as a Diffuse BSDF of its viewport
        # colour (blender/shader.cpp sync_materials): its metallic,
        # roughness, specular and alpha are the viewport's only. Written as
        # a Principled BSDF they had rendered glossy (and half transparent).
        # Cycles 5.0 made the default surface a Principled BSDF at its
        # defaults (Cycles 43bf8e6c9); a material without nodes stays the
        # viewport colour's Diffuse.
        if mat is None:
            if _blender_version() >= (5, 0, 0):
                return self._principled_defaults()
            return self._diffuse_constant([0.8, 0.8, 0.8, 1.0])
        if not mat.use_nodes or mat.node_tree is None:
            return self._diffuse_constant(list(mat.diffuse_color)[:3] + [1.0])
        out = active_output(mat.node_tree)
        if out is None:
            self.warn_material("no Material Output for Cycles (target All or Cycles); written as black, as Cycles "
                               "renders it")
            return self._black_diffuse()
        # What photonbridge does not render is said, not dropped silently.
        for sock, what in (("Volume", "a volume shader"), ("Displacement", "displacement")):
            s = out.inputs.get(sock)
            if s is not None and _source(s) is not None:
                self.warn_material("%s on the Material Output is not rendered" % what)
        shader = _source(out.inputs["Surface"])
        node, extra = self._peel(shader.node if shader else None)
        if node is None and extra["alpha"] == 0.0 and extra["alpha_link"] is None:
            # A Transparent BSDF alone: the surface lets every ray through.
            return self._principled_defaults(alpha=0.0)
        if extra["alpha"] != 1.0 or extra["alpha_link"] is not None or extra["emission"] is not None:
            if node is not None and node.type == 'BSDF_PRINCIPLED':
                return self._principled2(node, extra) if is_principled_v2(node) else self._principled(node, extra)
            self._warn_node(node if node is not None else out,
                            "a Transparent or Emission shader mixed or added to it is written only with a "
                            "Principled BSDF; left out")
        if node is None:
            self.warn_material("nothing is connected to the Material Output's Surface; written as black")
            return self._black_diffuse()
        mix = extra.get("mix")
        if mix is None:
            return self._one_shader(node)
        # A Mix Shader of two BSDFs (_mix): the first's model with the
        # second's under "mix"; the plain glTF is the larger shader's.
        gm, ext = self._one_shader(node)
        first_vcol, self._vcol = self._vcol, None
        gm2, ext2 = self._one_shader(mix["shader"])
        if self._vcol is not None:
            ext2["vertexColor"] = "baseColor" if ext2.get("model") in ("principled", "principled2") else "color"
            if first_vcol is not None and first_vcol != self._vcol:
                self._warn_node(mix["node"], "its shaders read different colour attributes; the first's is written")
        ext["_vcolFirst"] = first_vcol is not None
        self._vcol = first_vcol if first_vcol is not None else self._vcol
        for t in ("normal", "coatNormal", "clearcoatNormal"):
            ext2.get("textures", {}).pop(t, None)
        if "textures" in ext2 and not ext2["textures"]:
            del ext2["textures"]
        ext["mix"] = dict(mix["fac"], shader=ext2)
        if mix["fac"].get("facFrom", "value") == "value" and "textures" not in mix["fac"] and mix["fac"]["fac"] > 0.5:
            gm = gm2
        return gm, ext

    def _one_shader(self, node):
        """One BSDF, Emission or Holdout node's (plain glTF, extension)."""
        if node.type == 'BSDF_PRINCIPLED':
            gm, ext = self._principled2(node) if is_principled_v2(node) else self._principled(node)
        elif node.type == 'BSDF_DIFFUSE':
            gm, ext = self._diffuse(node)
        elif node.type == 'EMISSION':
            gm, ext = self._emission(node)
        elif node.type == 'HOLDOUT':
            gm, ext = self._plain_black(), {"model": "holdout"}
        elif node.type in ('BSDF_GLASS', 'BSDF_GLOSSY', 'BSDF_REFRACTION', 'BSDF_ANISOTROPIC') and \
                (_blender_version() >= (4, 0, 0) or node.distribution != 'MULTI_GGX'):
            gm, ext = self._bsdf_node(node)
        elif node.type in ('BSDF_GLASS', 'BSDF_GLOSSY', 'BSDF_REFRACTION', 'BSDF_ANISOTROPIC'):
            gm, ext = self._like_principled(node)
        elif node.type == 'BSDF_METALLIC':
            gm, ext = self._metallic(node)
        elif node.type in ('BSDF_SHEEN', 'BSDF_VELVET'):
            gm, ext = self._sheen(node)
        else:
            self._warn_node(node, "shader not translated; written as a grey Principled BSDF")
            gm, ext = self._principled_defaults()
        return gm, ext

    # ---- Mix Shader ------------------------------------------------------------------

    MIXABLE = ('BSDF_PRINCIPLED', 'BSDF_DIFFUSE', 'BSDF_GLOSSY', 'BSDF_ANISOTROPIC', 'BSDF_GLASS', 'BSDF_REFRACTION',
               'BSDF_METALLIC', 'BSDF_SHEEN', 'BSDF_VELVET')

    def _closure_kinds(self, node):
        """The kinds of closure a BSDF node can make, as the loader counts them
        (scene.c pb_blender_closures): a Mix Shader renders only shaders of
        different kinds."""
        def on(sock_name):
            s = node.inputs.get(sock_name)
            return s is not None and (_source(s) is not None or float(_value(s)) > 0.0)
        t = node.type
        multi3 = _blender_version() < (4, 0, 0) and getattr(node, "distribution", "") == 'MULTI_GGX'
        if t == 'BSDF_DIFFUSE':
            return {"diffuse"}
        if t in ('BSDF_SHEEN', 'BSDF_VELVET'):
            return {"sheen"}
        if t == 'BSDF_METALLIC':
            return {"reflection"}
        if t in ('BSDF_GLOSSY', 'BSDF_ANISOTROPIC') and not multi3:
            return {"reflection"}
        if t == 'BSDF_REFRACTION' and not multi3:
            return {"refraction"}
        if t == 'BSDF_GLASS' and not multi3:
            return {"refraction"} if _blender_version() >= (4, 0, 0) else {"reflection", "refraction"}
        if t != 'BSDF_PRINCIPLED':  # 3.x Multiscatter GGX: written as a v1 Principled BSDF
            return {"diffuse", "specular", "reflection", "refraction"}
        kinds = {"diffuse", "specular"}
        if is_principled_v2(node):
            pairs = (("Sheen Weight", "sheen"), ("Coat Weight", "coat"), ("Metallic", "reflection"),
                     ("Transmission Weight", "refraction"))
        else:
            pairs = (("Sheen", "sheen"), ("Clearcoat", "coat"), ("Transmission", "reflection"),
                     ("Transmission", "refraction"))
        for sock_name, kind in pairs:
            if on(sock_name):
                kinds.add(kind)
        return kinds

    def _emits_or_clear(self, node):
        """Does a Principled BSDF emit or let light through (Alpha)?"""
        if node.type != 'BSDF_PRINCIPLED':
            return False
        a = node.inputs.get("Alpha")
        if a is not None and (_source(a) is not None or float(_value(a)) < 1.0):
            return True
        color = node.inputs.get("Emission Color") or node.inputs.get("Emission")
        strength = node.inputs.get("Emission Strength")
        lit = _source(color) is not None or max(_value(color)[:3]) > 0.0
        return lit and (strength is None or _source(strength) is not None or float(_value(strength)) > 0.0)

    def _mix_fac(self, node):
        """The extension's factor of a Mix Shader ({"facFrom", value, textures}),
        or None where it is not translated: its Fac unlinked, an image
        texture, a Fresnel node or a Layer Weight node (their IOR or Blend
        and Normal unlinked)."""
        sock = node.inputs[0]
        src = _source(sock)
        if src is None:
            return {"fac": min(max(float(_value(sock)), 0.0), 1.0)}
        n = src.node
        if n.type in ('FRESNEL', 'LAYER_WEIGHT'):
            param = n.inputs["IOR" if n.type == 'FRESNEL' else "Blend"]
            normal = n.inputs.get("Normal")
            if _source(param) is not None or (normal is not None and _source(normal) is not None):
                return None
            if n.type == 'FRESNEL':
                return {"facFrom": "fresnel", "ior": min(max(float(_value(param)), 0.0), 1000.0)}
            return {"facFrom": "layerFresnel" if src.name == "Fresnel" else "layerFacing",
                    "blend": min(max(float(_value(param)), 0.0), 1.0)}
        if n.type in ('TEX_IMAGE', 'SEPRGB', 'SEPARATE_COLOR'):
            link = self._texture_link(sock, "Fac")
            entry = self._texture_entry(link, False)[0] if link is not None else None
            if entry is not None:
                return {"fac": min(max(float(_value(sock)), 0.0), 1.0), "textures": {"fac": entry}}
        return None

    def _mix(self, node, a, b, fac=None):
        """A Mix Shader (or, fac {"facFrom": "add"}, an Add Shader) of two BSDFs
        that photonbridge renders as Cycles does: {"node", "shader" (the
        second), "fac"}; None (with the reason) where it does not."""
        if a is None or b is None or a.type not in self.MIXABLE or b.type not in self.MIXABLE:
            return None, "it mixes a shader other than a BSDF"
        if self._emits_or_clear(a) or self._emits_or_clear(b):
            return None, "a mixed Principled BSDF emits or has an Alpha below 1"
        shared = self._closure_kinds(a) & self._closure_kinds(b)
        if shared:
            return None, "both its shaders make %s closures" % sorted(shared)[0]
        fac = fac if fac is not None else self._mix_fac(node)
        if fac is None:
            return None, "its Fac is driven by a node that is not translated"
        na, nb = _source(a.inputs["Normal"]) if "Normal" in a.inputs else None, \
            _source(b.inputs["Normal"]) if "Normal" in b.inputs else None
        if nb is not None and (na is None or na.node != nb.node):
            self._warn_node(b, "its Normal is not translated in a Mix Shader; it takes the first shader's")
        return {"node": node, "shader": b, "fac": fac}, None

    def _shader_node(self, socket):
        src = _source(socket)
        return src.node if src is not None else None

    def _transparent(self, node):
        """A Transparent BSDF that lets all light through (white colour)."""
        if node is None or node.type != 'BSDF_TRANSPARENT':
            return False
        c = _value(node.inputs["Color"])
        if _source(node.inputs["Color"]) is not None or min(c[:3]) < 0.999:
            self._warn_node(node, "a tinted or textured Transparent BSDF is written as clear")
        return True

    def _peel(self, node):
        """The BSDF under Mix and Add Shaders, and what they add to it exactly:
        Mix(Transparent, X, fac) is X with alpha x fac (and Mix(X,
        Transparent, fac) with alpha x (1 - fac) for a constant fac), as the
        Principled BSDF's Alpha is defined in Cycles; Add(Emission, X) is X
        with that emission. Returns (node, {"alpha", "alpha_link",
        "emission"}); node None with alpha 0 is a Transparent BSDF alone.
        Anything else keeps the larger shader of a Mix (the first when Fac
        is linked), with a warning."""
        extra = {"alpha": 1.0, "alpha_link": None, "emission": None}
        for _ in range(32):
            if node is None:
                return None, extra
            if self._transparent(node):
                extra["alpha"] = 0.0
                return None, extra
            if node.type == 'MIX_SHADER':
                a, b = self._shader_node(node.inputs[1]), self._shader_node(node.inputs[2])
                fac_link, fac = _source(node.inputs[0]), float(_value(node.inputs[0]))
                if self._transparent(a) and b is not None and not self._transparent(b):
                    if fac_link is not None:
                        link = self._texture_link(node.inputs[0], "Fac")
                        if link is not None and extra["alpha_link"] is None and extra["alpha"] == 1.0:
                            extra["alpha_link"] = link
                        else:
                            self._warn_node(node, "its Fac is not translated; the mix is written opaque")
                    else:
                        extra["alpha"] *= fac
                    node = b
                    continue
                if self._transparent(b) and a is not None and not self._transparent(a):
                    if fac_link is not None:
                        self._warn_node(node, "a linked Fac with the Transparent BSDF second is not translated; "
                                        "written opaque")
                    else:
                        extra["alpha"] *= 1.0 - fac
                    node = a
                    continue
                if fac_link is None and (fac <= 0.0 or fac >= 1.0):
                    node = b if fac >= 1.0 else a  # the other shader weighs nothing
                    continue
                why = "a Transparent or Emission shader is mixed in too"
                if extra["alpha"] == 1.0 and extra["alpha_link"] is None and extra["emission"] is None:
                    mix, why = self._mix(node, a, b)
                    if mix is not None:
                        extra["mix"] = mix
                        return a, extra
                pick = b if fac_link is None and fac > 0.5 else a
                self._warn_node(node, "only its %s shader input is written (%s)"
                                % ("second" if pick is b else "first", why))
                node = pick
                continue
            if node.type == 'ADD_SHADER':
                a, b = self._shader_node(node.inputs[0]), self._shader_node(node.inputs[1])
                for e, other in ((a, b), (b, a)):
                    if e is not None and e.type == 'EMISSION' and extra["emission"] is None and other is not None \
                            and other.type != 'EMISSION' and _source(e.inputs["Color"]) is None \
                            and _source(e.inputs["Strength"]) is None:
                        extra["emission"] = (_value(e.inputs["Color"]), float(_value(e.inputs["Strength"])))
                        node = other
                        break
                else:
                    why = "a Transparent or Emission shader is mixed in too"
                    if extra["alpha"] == 1.0 and extra["alpha_link"] is None and extra["emission"] is None:
                        mix, why = self._mix(node, a, b, {"facFrom": "add"})
                        if mix is not None:
                            extra["mix"] = mix
                            return a, extra
                    self._warn_node(node, "only its first shader input is written (%s)" % why)
                    node = a
                continue
            return node, extra
        return node, extra

    def _plain_black(self):
        return {"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0,
                                         "roughnessFactor": 1.0},
                "extensions": {"KHR_materials_specular": {"specularColorFactor": [0.0, 0.0, 0.0]}}}

    def _principled_defaults(self, alpha=1.0):
        if _blender_4():
            # Blender 4.x's Principled BSDF at its defaults (v2).
            p = {"alpha": alpha}
            return self._principled2_plain(dict(PRINCIPLED2_DEFAULTS, alpha=alpha), {}), \
                {"model": "principled2", "principled2": p}
        p = {"baseColor": [0.8, 0.8, 0.8, 1.0], "metallic": 0.0, "roughness": 0.5, "specular": BLENDER_SPECULAR,
             "specularTint": 0.0, "ior": 1.45, "transmission": 0.0, "emission": [0, 0, 0, 1],
             "emissionStrength": 1.0, "alpha": alpha}
        return self._principled_plain(p, {}), {"model": "principled", "principled": dict(p)}

    def _principled(self, node, extra=None):
        p, links = {}, {}
        for sock_name, member in PRINCIPLED_INPUTS:
            sock = node.inputs.get(sock_name)
            if sock is None:
                continue
            p[member] = _value(sock)
            if member == "baseColor":
                vcol = self._vertex_color_link(sock)
                if vcol is not None:
                    # Cycles: the linked socket's value is the attribute's;
                    # glTF: baseColorFactor x COLOR_0, so a white factor.
                    self._vcol = vcol
                    p[member] = [1.0, 1.0, 1.0, 1.0]
                    continue
            link = self._texture_link(sock, sock_name)
            if link is not None:
                links[member] = link
        if extra is not None:
            # What Mix/Add Shaders around the BSDF add (_peel).
            if extra["alpha_link"] is not None:
                if "alpha" in links or p["alpha"] < 1.0:
                    self._warn_node(node, "its own Alpha and a mixed-in Transparent BSDF's Fac: the Fac is written")
                links["alpha"] = extra["alpha_link"]
                p["alpha"] = 1.0
            if extra["alpha"] != 1.0:
                if "alpha" in links:
                    self._warn_node(node, "a textured Alpha mixed with a Transparent BSDF: the factor %s is "
                                    "not applied" % _fmt(extra["alpha"]))
                else:
                    p["alpha"] = p["alpha"] * extra["alpha"]
            if extra["emission"] is not None:
                color, strength = extra["emission"]
                if "emission" in links or max(p["emission"][:3]) * p["emissionStrength"] > 0:
                    self._warn_node(node, "its own Emission and an added Emission shader: the added one is written")
                    links.pop("emission", None)
                p["emission"], p["emissionStrength"] = list(color), strength
        p["distribution"] = node.distribution
        p["subsurfaceMethod"] = node.subsurface_method
        normal_links = []
        for sock_name, member in (("Normal", "normal"), ("Clearcoat Normal", "clearcoatNormal")):
            s = node.inputs.get(sock_name)
            nl = self._normal_link(s) if s is not None else None
            if nl is not None:
                normal_links.append((member, nl))
        s = node.inputs.get("Tangent")
        if s is not None and _source(s) is not None:
            self._warn_node(_source(s).node, "drives Tangent and is not translated")
        textures, tex_index = {}, {}
        for member, link in links.items():
            entry, index = self._texture_entry(link, member in COLOR_INPUTS)
            if entry is not None:
                textures[member] = entry
                tex_index[member] = (index, link)
        for member, (img_node, strength) in normal_links:
            entry, index = self._texture_entry((img_node, "RGB"), False)
            if entry is not None:
                entry.pop("channel", None)
                entry["strength"] = strength
                textures[member] = entry
                if member == "normal":  # the plain glTF's normalTexture
                    tex_index[member] = (index, (img_node, strength))
        ext = {"model": "principled", "principled": p}
        if textures:
            ext["textures"] = textures
        return self._principled_plain(p, tex_index), ext

    def _principled2(self, node, extra=None):
        """A Principled BSDF v2 (Blender 4.0+): every input the node has, as
        the extension's "principled2" model, and its plain glTF per Blender
        4.5's exporter."""
        p, links = {}, {}
        for sock_name, member in PRINCIPLED2_INPUTS:
            sock = node.inputs.get(sock_name)
            if sock is None:
                continue
            p[member] = _value(sock)
            if member == "baseColor":
                vcol = self._vertex_color_link(sock)
                if vcol is not None:
                    self._vcol = vcol
                    p[member] = [1.0, 1.0, 1.0, 1.0]
                    continue
            if member in UNTEXTURED2:
                src = _source(sock)
                if src is not None:
                    self._warn_node(src.node, "drives %s and is not translated; its value %s is written"
                                    % (sock_name, _fmt(p[member])))
                continue
            link = self._texture_link(sock, sock_name)
            if link is not None:
                links[member] = link
        if extra is not None:
            if extra["alpha_link"] is not None:
                if "alpha" in links or p.get("alpha", 1.0) < 1.0:
                    self._warn_node(node, "its own Alpha and a mixed-in Transparent BSDF's Fac: the Fac is written")
                links["alpha"] = extra["alpha_link"]
                p["alpha"] = 1.0
            if extra["alpha"] != 1.0:
                if "alpha" in links:
                    self._warn_node(node, "a textured Alpha mixed with a Transparent BSDF: the factor %s is "
                                    "not applied" % _fmt(extra["alpha"]))
                else:
                    p["alpha"] = p.get("alpha", 1.0) * extra["alpha"]
            if extra["emission"] is not None:
                color, strength = extra["emission"]
                own = max(p.get("emissionColor", [1.0] * 3)[:3]) * p.get("emissionStrength", 0.0)
                if "emissionColor" in links or "emissionStrength" in links or own > 0:
                    self._warn_node(node, "its own Emission and an added Emission shader: the added one is written")
                    links.pop("emissionColor", None)
                    links.pop("emissionStrength", None)
                p["emissionColor"], p["emissionStrength"] = list(color), strength
        p["distribution"] = node.distribution
        method = SUBSURFACE_METHOD_V2.get(node.subsurface_method)
        if method is None:
            self._warn_node(node, "subsurface method %s is written as RANDOM_WALK_SKIN" % node.subsurface_method)
            method = "RANDOM_WALK_SKIN"
        p["subsurfaceMethod"] = method
        textures, tex_index = self._node_textures(node, links, COLOR2_INPUTS,
                                                  (("Normal", "normal"), ("Coat Normal", "coatNormal")))
        ext = {"model": "principled2", "principled2": p}
        if textures:
            ext["textures"] = textures
        return self._principled2_plain(dict(PRINCIPLED2_DEFAULTS, **p), tex_index), ext

    def _node_textures(self, node, links, colors, normals):
        """The extension's "textures" of a BSDF node and the plain glTF's
        texture index ({member: (index, link)}): an entry for each linked
        input (links: member -> (image node, channel); colors: the members
        read as colour) and for a Normal Map on each of the node's normal
        sockets (normals: (socket, member)). A linked Tangent is said."""
        s = node.inputs.get("Tangent")
        if s is not None and _source(s) is not None:
            self._warn_node(_source(s).node, "drives Tangent and is not translated")
        textures, tex_index = {}, {}
        for member, link in links.items():
            entry, index = self._texture_entry(link, member in colors)
            if entry is not None:
                textures[member] = entry
                tex_index[member] = (index, link)
        for sock_name, member in normals:
            s = node.inputs.get(sock_name)
            nl = self._normal_link(s) if s is not None else None
            if nl is not None:
                entry, index = self._texture_entry((nl[0], "RGB"), False)
                if entry is not None:
                    entry.pop("channel", None)
                    entry["strength"] = nl[1]
                    textures[member] = entry
                    tex_index[member] = (index, nl)
        return textures, tex_index

    def _principled2_plain(self, p, tex):
        """The glTF of Principled v2 values p (every member, defaults filled
        in) and textures tex, per Blender 4.5's exporter
        (io_scene_gltf2/blender/exp/material/extensions/*.py): the core as
        for v1; KHR_materials_specular specularFactor = 2 x Specular IOR
        Level when below 1, specularColorFactor = Specular Tint (x 2 x
        level when that is above 1) when not white; KHR_materials_ior with
        either; KHR_materials_sheen (Sheen Tint, Sheen Roughness) when Sheen
        Weight > 0; KHR_materials_clearcoat (Coat Weight, Coat Roughness,
        Coat Normal). Blender 4.5 writes no KHR_materials_iridescence, and
        neither does this."""
        v1 = {"baseColor": p["baseColor"], "alpha": p["alpha"], "metallic": p["metallic"],
              "roughness": p["roughness"], "emission": p["emissionColor"],
              "emissionStrength": p["emissionStrength"], "transmission": p["transmissionWeight"],
              "ior": p["ior"]}
        t1 = {{"emissionColor": "emission", "transmissionWeight": "transmission"}.get(k, k): v for k, v in tex.items()}
        gm = self._principled_plain(v1, t1, specular=False)
        exts = gm.setdefault("extensions", {})
        spec = {}
        fac = None
        if "specularIorLevel" not in tex:
            fac = 2.0 * float(p["specularIorLevel"])
            if fac < 1.0:
                spec["specularFactor"] = fac
        if "specularTint" not in tex:
            color = [float(c) for c in p["specularTint"][:3]]
            if fac is not None and fac > 1.0:
                color = [c * fac for c in color]
            if color != [1.0, 1.0, 1.0]:
                spec["specularColorFactor"] = color
        if spec:
            exts["KHR_materials_specular"] = spec
        ior = float(p["ior"])
        if ior != GLTF_IOR and ("KHR_materials_transmission" in exts or "KHR_materials_specular" in exts):
            exts["KHR_materials_ior"] = {"ior": ior}
        if "sheenWeight" in tex or float(p["sheenWeight"]) != 0.0:
            sheen = {}
            tint = [float(c) for c in p["sheenTint"][:3]] if "sheenTint" not in tex else [1.0, 1.0, 1.0]
            if tint != [0.0, 0.0, 0.0]:
                sheen["sheenColorFactor"] = tint
            rough = float(p["sheenRoughness"]) if "sheenRoughness" not in tex else 1.0
            if rough != 0.0:
                sheen["sheenRoughnessFactor"] = rough
            if sheen:  # Blender's exporter leaves an empty extension out
                exts["KHR_materials_sheen"] = sheen
        coat = {}
        if "coatWeight" in tex:
            coat["clearcoatFactor"] = 1.0
        elif float(p["coatWeight"]) != 0.0:
            coat["clearcoatFactor"] = float(p["coatWeight"])
        if "coatRoughness" in tex:
            coat["clearcoatRoughnessFactor"] = 1.0
        elif abs(float(p["coatRoughness"]) - BLENDER_COAT_ROUGHNESS) > 1e-5:
            coat["clearcoatRoughnessFactor"] = float(p["coatRoughness"])
        if "coatNormal" in tex:
            coat["clearcoatNormalTexture"] = self._texture_info(tex["coatNormal"][0], tex["coatNormal"][1][0],
                                                                scale=tex["coatNormal"][1][1])
        if coat:
            exts["KHR_materials_clearcoat"] = coat
        if not exts:
            del gm["extensions"]
        return gm

    def _normal_link(self, socket):
        src = _source(socket)
        if src is None:
            return None
        node = src.node
        if node.type == 'NORMAL_MAP':
            if node.space != 'TANGENT':
                self._warn_node(node, "space %s is not translated (tangent space only)" % node.space)
                return None
            col = _source(node.inputs["Color"])
            if col is not None and col.node.type == 'TEX_IMAGE':
                img = self._image_node(col.node)
                if img:
                    strength = node.inputs["Strength"]
                    if _source(strength) is not None:
                        self._warn_node(node, "a linked Strength is not translated")
                    return img, float(_value(strength))
            elif col is not None:
                self._warn_node(col.node, "drives the Normal Map's Color and is not translated")
            return None
        self._warn_node(node, "drives Normal and is not translated (Normal Map nodes only)")
        return None

    def _principled_plain(self, p, tex, specular=True):
        """The glTF of Principled values p and textures tex (member -> (index,
        link)), per Blender 3.4's exporter."""
        pbr = {}
        base = [max(0.0, min(1.0, c)) for c in p["baseColor"][:3]]
        alpha = p.get("alpha", 1.0)
        if "baseColor" in tex and tex["baseColor"][1][1] == "RGB":
            pbr["baseColorTexture"] = self._texture_info(tex["baseColor"][0], tex["baseColor"][1][0])
            base = [1.0, 1.0, 1.0]
        if "alpha" in tex:
            alpha = 1.0
        pbr["baseColorFactor"] = base + [alpha]
        pbr["metallicFactor"] = float(p["metallic"])
        pbr["roughnessFactor"] = float(p["roughness"])
        mr = {k: tex[k][1] for k in ("metallic", "roughness") if k in tex}
        if mr:
            uri = self._metallic_roughness(mr)
            if uri is not None:
                pbr["metallicRoughnessTexture"] = {"index": self.doc.add_texture(uri, self._sampler(
                    next(iter(mr.values()))[0]))}
                for k in mr:
                    pbr[k + "Factor"] = 1.0
        gm = {"pbrMetallicRoughness": pbr}
        exts = {}
        if "normal" in tex:
            gm["normalTexture"] = self._texture_info(tex["normal"][0], tex["normal"][1][0], scale=tex["normal"][1][1])
        strength = float(p.get("emissionStrength", 1.0))
        emissive = [c * strength for c in p["emission"][:3]]
        if "emission" in tex:
            gm["emissiveTexture"] = self._texture_info(tex["emission"][0], tex["emission"][1][0])
            emissive = [strength] * 3
        if any(c > 1.0 for c in emissive):
            m = max(emissive)
            exts["KHR_materials_emissive_strength"] = {"emissiveStrength": m}
            emissive = [c / m for c in emissive]
        if any(c != 0.0 for c in emissive):
            gm["emissiveFactor"] = emissive
        transmission = float(p.get("transmission", 0.0))
        if "transmission" in tex:
            exts["KHR_materials_transmission"] = {"transmissionFactor": 1.0}
            self.warn_material("Transmission texture: only the factor is written in plain glTF")
        elif transmission > 0.0:
            exts["KHR_materials_transmission"] = {"transmissionFactor": transmission}
        if not specular:  # Principled v2: _principled2_plain adds its own
            if exts:
                gm["extensions"] = exts
            return gm
        spec, tint, ior = float(p["specular"]), float(p["specularTint"]), float(p["ior"])
        if not any(k in tex for k in ("specular", "specularTint", "transmission")) and \
                (spec != BLENDER_SPECULAR or tint != 0.0):
            f0 = ((ior - 1.0) / (ior + 1.0)) ** 2
            if f0 == 0.0:
                color = [1.0, 1.0, 1.0]
            else:
                lum = luminance(p["baseColor"])
                tint_rgb = [(1.0 - tint) + (c / lum if lum else c) * tint for c in p["baseColor"][:3]]
                color = [(1.0 - transmission) * (1.0 / f0) * 0.08 * spec * t + transmission * t for t in tint_rgb]
            exts["KHR_materials_specular"] = {"specularColorFactor": color}
        if ior != GLTF_IOR and ("KHR_materials_transmission" in exts or "KHR_materials_specular" in exts):
            exts["KHR_materials_ior"] = {"ior": ior}
        if exts:
            gm["extensions"] = exts
        return gm

    def _metallic_roughness(self, mr):
        """The glTF metallicRoughness image (G roughness, B metallic) of the
        linked channels: the image itself when it already is one, else a
        composed PNG."""
        chan = {"R": 0, "G": 1, "B": 2, "A": 3, "RGB": 0}
        nodes = {k: v[0] for k, v in mr.items()}
        if len({n.image.name for n in nodes.values()}) == 1:
            r = mr.get("roughness")
            m = mr.get("metallic")
            if (r is None or r[1] == "G") and (m is None or m[1] == "B"):
                return self.images.texture_image(next(iter(nodes.values())).image, color=False)
        channels = {0: 1.0, 3: 1.0, 1: 1.0, 2: 1.0}
        if "roughness" in mr:
            channels[1] = (mr["roughness"][0].image, chan[mr["roughness"][1]])
        if "metallic" in mr:
            channels[2] = (mr["metallic"][0].image, chan[mr["metallic"][1]])
        return self.images.composed_image(self.mat_name + "_metallicRoughness", channels)

    def _diffuse(self, node):
        color = _value(node.inputs["Color"])
        rough = _value(node.inputs["Roughness"])
        vcol = self._vertex_color_link(node.inputs["Color"])
        if vcol is not None:
            self._vcol = vcol
            color = [1.0, 1.0, 1.0, 1.0]
        link = None if vcol is not None else self._texture_link(node.inputs["Color"], "Color")
        ext = {"model": "diffuse", "diffuse": {"color": color, "roughness": rough}}
        tex = {}
        if link is not None:
            entry, index = self._texture_entry(link, True)
            if entry is not None:
                ext["textures"] = {"baseColor": entry}
                tex["baseColor"] = (index, link)
        normal = self._normal_link(node.inputs["Normal"])
        if normal is not None:
            entry, index = self._texture_entry((normal[0], "RGB"), False)
            if entry is not None:
                entry.pop("channel", None)
                entry["strength"] = normal[1]
                ext.setdefault("textures", {})["normal"] = entry
                tex["normal"] = (index, normal)
        p = {"baseColor": color, "metallic": 0.0, "roughness": 1.0, "specular": 0.0, "specularTint": 0.0,
             "ior": 1.45, "transmission": 0.0, "emission": [0, 0, 0, 1], "emissionStrength": 1.0, "alpha": 1.0}
        return self._principled_plain(p, tex), ext

    def _black_diffuse(self):
        """A black Diffuse BSDF (a surface Cycles renders black)."""
        return self._plain_black(), {"model": "diffuse", "diffuse": {"color": [0, 0, 0, 1]}}

    def _diffuse_constant(self, color):
        """A Diffuse BSDF of `color`, roughness 0 (what Cycles makes of an
        empty slot or a material without nodes)."""
        p = {"baseColor": color, "metallic": 0.0, "roughness": 1.0, "specular": 0.0, "specularTint": 0.0,
             "ior": 1.45, "transmission": 0.0, "emission": [0, 0, 0, 1], "emissionStrength": 1.0, "alpha": 1.0}
        return self._principled_plain(p, {}), {"model": "diffuse", "diffuse": {"color": color, "roughness": 0.0}}

    def _emission(self, node):
        color = _value(node.inputs["Color"])
        strength = _value(node.inputs["Strength"])
        ext = {"model": "emission", "emission": {"color": color, "strength": strength}}
        tex = {}
        link = self._texture_link(node.inputs["Color"], "Color")
        if link is not None:
            entry, index = self._texture_entry(link, True)
            if entry is not None:
                ext["textures"] = {"emission": entry}
                tex["emission"] = (index, link)
        p = {"baseColor": [0.0, 0.0, 0.0, 1.0], "metallic": 0.0, "roughness": 1.0, "specular": 0.0,
             "specularTint": 0.0, "ior": 1.45, "transmission": 0.0, "emission": color,
             "emissionStrength": strength, "alpha": 1.0}
        return self._principled_plain(p, tex), ext

    def _node_values(self, node, sockets):
        """The constant values of a BSDF node's sockets (member: value); a
        linked socket is said and its own value written, Normal and Tangent
        links are said."""
        out = {}
        for sock_name, member in sockets:
            sock = node.inputs[sock_name]
            out[member] = _value(sock)
            src = _source(sock)
            if src is not None:
                self._warn_node(src.node, "drives %s and is not translated; its value %s is written"
                                % (sock_name, _fmt(out[member])))
        for sock_name in ("Normal", "Tangent"):
            sock = node.inputs.get(sock_name)
            if sock is not None and _source(sock) is not None:
                self._warn_node(_source(sock).node, "drives %s and is not translated" % sock_name)
        return out

    def _metallic(self, node):
        """A Metallic BSDF (Blender 4.3+), GGX, Multiscatter GGX or Beckmann: the
        extension's "metallic" model, with the F82 Fresnel (Base Color, Edge
        Tint) or the Physical Conductor's (IOR n, Extinction k, per RGB
        channel). Cycles renders it as the Principled v2 metal lobe alone;
        it clamps the colours, Roughness and Anisotropy to [0, 1] and n, k
        to >= 0, and Rotation turns by 2 pi. The plain glTF of a conductor
        has its colour at normal incidence."""
        conductor = node.fresnel_type == 'PHYSICAL_CONDUCTOR'
        v = self._node_values(node, ((("IOR", "ior"), ("Extinction", "extinction")) if conductor else
                                     (("Base Color", "baseColor"), ("Edge Tint", "edgeTint"))) +
                              (("Roughness", "roughness"), ("Anisotropy", "anisotropy"), ("Rotation", "rotation")))
        clamp = lambda x: min(max(float(x), 0.0), 1.0)  # noqa: E731
        m = {"roughness": clamp(v["roughness"]), "anisotropy": clamp(v["anisotropy"]),
             "rotation": float(v["rotation"]) % 1.0, "distribution": node.distribution,
             "fresnelType": node.fresnel_type}
        if conductor:
            m["ior"] = [max(float(c), 0.0) for c in v["ior"][:3]]
            m["extinction"] = [max(float(c), 0.0) for c in v["extinction"][:3]]
            base = [((n - 1.0) ** 2 + k * k) / ((n + 1.0) ** 2 + k * k) for n, k in zip(m["ior"], m["extinction"])]
            base, tint = [clamp(c) for c in base] + [1.0], [1.0, 1.0, 1.0, 1.0]
        else:
            m["baseColor"] = base = [clamp(c) for c in v["baseColor"][:3]] + [1.0]
            m["edgeTint"] = tint = [clamp(c) for c in v["edgeTint"][:3]] + [1.0]
        p = dict(PRINCIPLED2_DEFAULTS, baseColor=base, metallic=1.0, roughness=m["roughness"],
                 specularTint=tint, anisotropic=m["anisotropy"], anisotropicRotation=m["rotation"])
        return self._principled2_plain(p, {}), {"model": "metallic", "metallic": m}

    def _sheen(self, node):
        """A Sheen BSDF (Blender 4.0+), Microfiber or Ashikhmin, or Blender
        3.x's Velvet BSDF (Ashikhmin, its Sigma the Roughness): the
        extension's "sheen" model (Cycles' microfiber sheen, the Principled
        v2 sheen lobe over nothing; or the Ashikhmin velvet closure). Its
        plain glTF is a black KHR_materials_sheen material."""
        velvet = node.type == 'BSDF_VELVET'
        v = self._node_values(node, (("Color", "color"), ("Sigma" if velvet else "Roughness", "roughness")))
        m = {"color": list(v["color"][:3]) + [1.0], "roughness": min(max(float(v["roughness"]), 0.0), 1.0),
             "distribution": "ASHIKHMIN" if velvet else node.distribution}
        p = dict(PRINCIPLED2_DEFAULTS, baseColor=[0.0, 0.0, 0.0, 1.0], specularIorLevel=0.0, sheenWeight=1.0,
                 sheenTint=m["color"], sheenRoughness=m["roughness"])
        return self._principled2_plain(p, {}), {"model": "sheen", "sheen": m}

    def _bsdf_node(self, node):
        """A Glossy, Glass or Refraction BSDF of Blender 4.0+: the
        extension's model "glossy", "glass" or "refraction" with the node's
        Color (an image texture or a colour attribute, as the Diffuse
        BSDF's), Roughness, IOR, Anisotropy and Rotation (image textures on
        the scalars too), clamped as Cycles clamps them; photonbridge
        renders them as Cycles 4.x does, with the node's distribution (GGX,
        Multiscatter GGX or Beckmann); Ashikhmin-Shirley is written as GGX,
        with a warning. Blender 3.x's Glossy, Anisotropic, Glass and
        Refraction BSDFs (Sharp as GGX at roughness 0) the same way but for
        Multiscatter GGX (its random walk, _like_principled); photonbridge
        renders a 3.x file's as Cycles 3.4 does. The plain glTF is the nearest
        Principled BSDF (Metallic 1, or Transmission 1 with the IOR)."""
        kind = {'BSDF_GLOSSY': "glossy", 'BSDF_ANISOTROPIC': "glossy", 'BSDF_GLASS': "glass",
                'BSDF_REFRACTION': "refraction"}[node.type]
        scalars = [("Roughness", "roughness")]
        scalars += [("Anisotropy", "anisotropy"), ("Rotation", "rotation")] if kind == "glossy" else [("IOR", "ior")]
        color_sock = node.inputs["Color"]
        m = {"color": [float(c) for c in _value(color_sock)[:3]] + [1.0]}
        links = {}
        vcol = self._vertex_color_link(color_sock)
        if vcol is not None:
            self._vcol = vcol
            m["color"] = [1.0, 1.0, 1.0, 1.0]
        else:
            link = self._texture_link(color_sock, "Color")
            if link is not None:
                links["baseColor"] = link
        ranges = {"roughness": (0.0, 1.0), "anisotropy": (-1.0, 1.0), "ior": (0.0, 1000.0)}
        for sock_name, member in scalars:
            sock = node.inputs.get(sock_name)
            if sock is None:  # Blender 4.0's Glossy has every input; be safe
                continue
            v = float(_value(sock))
            if member == "rotation":
                v %= 1.0
            else:
                lo, hi = ranges[member]
                v = min(max(v, lo), hi)
            m[member] = v
            link = self._texture_link(sock, sock_name)
            if link is not None:
                links[member] = link
        dist = node.distribution
        if dist == 'SHARP':  # Blender 3.x: the delta form, roughness ignored
            dist = 'GGX'
            m["roughness"] = 0.0
            links.pop("roughness", None)
        if dist not in ('GGX', 'MULTI_GGX', 'BECKMANN') or (kind == "refraction" and dist == 'MULTI_GGX'):
            self._warn_node(node, "the %s distribution is rendered as GGX" % dist.replace("_", " ").title())
            dist = 'GGX'
        m["distribution"] = dist
        textures, tex_index = self._node_textures(node, links, ("baseColor",), (("Normal", "normal"),))
        # the plain glTF's Principled has the colour, roughness and normal
        tex_index = {k: v for k, v in tex_index.items() if k in ("baseColor", "roughness", "normal")}
        ext = {"model": kind, kind: m}
        if textures:
            ext["textures"] = textures
        p = dict(PRINCIPLED2_DEFAULTS, baseColor=m["color"], roughness=m["roughness"])
        if kind == "glossy":
            p["metallic"] = 1.0
        else:
            p.update(transmissionWeight=1.0, ior=m["ior"])
        return self._principled2_plain(p, tex_index), ext

    def _like_principled(self, node):
        """Blender 3.x's Glass, Glossy, Anisotropic and Refraction BSDFs with
        Multiscatter GGX as the Principled inputs that mean the same in
        Cycles 3.4 (a warning says so)."""
        color = _value(node.inputs["Color"])
        rough = _value(node.inputs["Roughness"])
        p = {"baseColor": color, "metallic": 0.0, "specular": BLENDER_SPECULAR, "specularTint": 0.0,
             "roughness": rough, "ior": 1.45, "transmission": 0.0, "emission": [0, 0, 0, 1],
             "emissionStrength": 1.0, "alpha": 1.0}
        if node.type in ('BSDF_GLOSSY', 'BSDF_ANISOTROPIC'):
            p["metallic"] = 1.0
            what = "written as a Principled BSDF with Metallic 1"
            # 3.x's Anisotropic BSDF with Multiscatter GGX: its stretch
            # (alpha_x = r^2 (1 - a), alpha_y = r^2 / (1 - a), a in
            # -0.99..0.99) is not the Principled one, so it is not carried.
            aniso = node.inputs.get("Anisotropy")
            if aniso is not None and (_source(aniso) is not None or abs(_value(aniso)) > 1e-4):
                what += "; its Anisotropy is not translated (isotropic)"
        else:
            p["transmission"] = 1.0
            p["ior"] = _value(node.inputs["IOR"])
            what = "written as a Principled BSDF with Transmission 1"
        self._warn_node(node, what)
        p["distribution"] = 'GGX' if node.distribution in ('GGX', 'SHARP') else 'MULTI_GGX'
        return self._principled_plain(p, {}), {"model": "principled", "principled": p}


def _fmt(v):
    if isinstance(v, list):
        return "(" + ", ".join("%.3g" % x for x in v) + ")"
    return "%.3g" % v
