"""The depsgraph glTF writer: an evaluated Blender scene (the render
depsgraph RenderEngine.update() gets, or any evaluated depsgraph) to plain
glTF 2.0 plus the PHOTONBRIDGE_blender extension
(exporters/blender/PHOTONBRIDGE_blender.md), one .gltf and one .bin.

Why not bpy.ops.export_scene.gltf: inside a render it changes frames and
modes, sets context.window.scene and evaluates the viewport depsgraph (see
shared/BLENDER.md). This writer reads only the depsgraph it is given: no
bpy.context, no operators, nothing in the file changes.

What it writes:
- depsgraph.object_instances: every visible instance (collection, particle
  and geometry-node instances included) with its matrix_world; each mesh
  (after render-level modifiers: Object.to_mesh() on the evaluated object,
  to_mesh_clear() after) written once and shared by its instances, unless an
  instance's matrix has shear, which glTF's TRS cannot hold (that instance's
  vertices are written in world space then);
- triangulated loop normals, the render UV map and, where a material has a
  normal map, MikkTSpace tangents, all read with foreach_get into numpy;
  loops with equal attributes merged into one vertex;
- materials and textures (materials.py, images.py), lights (point, spot and
  sun as KHR_lights_punctual in Blender's "Standard" units, every light in
  the extension), the active camera, the world and the render settings;
- hide_render objects are not in a render depsgraph; holdout objects get a
  holdout material.
Coordinates: Blender Z up to glTF Y up, (x, y, z) -> (x, z, -y), as
Blender's exporter writes them; cameras and lights keep their own axes (they
look down their local -Z in both)."""
import json
import math
import os
import time

import numpy as np

import bpy
from mathutils import Matrix

from . import images as images_mod
from . import materials as materials_mod

EXTENSION = "PHOTONBRIDGE_blender"
EXTENSION_VERSION = 1
WATTS_TO_LUMENS = 683.0  # Blender's PBR_WATTS_TO_LUMENS

# Z up -> Y up.
AXIS = Matrix(((1, 0, 0, 0), (0, 0, 1, 0), (0, -1, 0, 0), (0, 0, 0, 1)))
AXIS_INV = AXIS.inverted()
AXIS3 = np.array([[1, 0, 0], [0, 0, 1], [0, -1, 0]], np.float64)

GEOMETRY_TYPES = {'MESH', 'CURVE', 'SURFACE', 'FONT', 'META'}
FLOAT, UINT16, UINT32 = 5126, 5123, 5125


def ocio_config():
    """The OCIO config this Blender shows its pictures through, as a path, so
    that photonbridge can use the same one: $OCIO where it names a file (as
    Blender reads it), else Blender's own colormanagement/config.ocio; ""
    when neither is found."""
    env = os.environ.get("OCIO", "")
    if env and os.path.isfile(env):
        return os.path.abspath(env)
    folder = bpy.utils.system_resource('DATAFILES', path="colormanagement")
    path = os.path.join(folder, "config.ocio") if folder else ""
    return os.path.abspath(path) if path and os.path.isfile(path) else ""



def _area_light_size(lamp, scale):
    """An area light's full widths in metres, times its object's scale
    (SQUARE and DISK: size both ways)."""
    return (lamp.size * abs(scale.x),
            (lamp.size_y if lamp.shape in ('RECTANGLE', 'ELLIPSE') else lamp.size) * abs(scale.y))

class WriteReport:
    def __init__(self):
        self.warnings = []
        # What only other glTF readers lose (photonbridge reads it from the
        # extension): the exporter shows these, the render engine does not, so
        # that an artist's render report lists only what changes the picture.
        self.notes = []
        self.triangles = 0
        self.meshes = 0
        self.instances = 0
        self.lights = 0
        self.seconds = 0.0
        self.path = None


class Document:
    """A glTF document under construction: JSON objects and one binary
    buffer, 4-byte aligned views."""

    def __init__(self):
        self.j = {"asset": {"version": "2.0", "generator": "photonbridge Blender add-on (depsgraph writer)"},
                  "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [],
                  "accessors": [], "bufferViews": [], "buffers": [], "textures": [], "images": [],
                  "samplers": [], "cameras": []}
        self.chunks = []
        self.size = 0
        self.used = set()
        self.lights = []
        self.image_index = {}
        self.sampler_index = {}
        self.texture_index = {}

    def view(self, data, target=None):
        data = np.ascontiguousarray(data)
        pad = (-self.size) % 4
        if pad:
            self.chunks.append(b"\0" * pad)
            self.size += pad
        v = {"buffer": 0, "byteOffset": self.size, "byteLength": data.nbytes}
        if target:
            v["target"] = target
        self.chunks.append(data.tobytes())
        self.size += data.nbytes
        self.j["bufferViews"].append(v)
        return len(self.j["bufferViews"]) - 1

    def accessor(self, data, kind, target=34962, minmax=False):
        """An accessor over `data` (float32 rows of 2/3/4 or uint indices)."""
        data = np.ascontiguousarray(data)
        comp = {np.float32: FLOAT, np.uint16: UINT16, np.uint32: UINT32}[data.dtype.type]
        a = {"bufferView": self.view(data, target), "componentType": comp, "count": int(data.shape[0]),
             "type": kind}
        if minmax:
            a["min"] = [float(x) for x in data.min(axis=0)]
            a["max"] = [float(x) for x in data.max(axis=0)]
        self.j["accessors"].append(a)
        return len(self.j["accessors"]) - 1

    def add_material(self, m):
        self.j["materials"].append(m)
        for k in m.get("extensions", {}):
            self.used.add(k)
        return len(self.j["materials"]) - 1

    def _image(self, uri):
        if uri not in self.image_index:
            self.j["images"].append({"uri": uri, "name": os.path.splitext(uri)[0]})
            self.image_index[uri] = len(self.j["images"]) - 1
        return self.image_index[uri]

    def add_texture(self, uri, sampler, float_uri=None):
        """A glTF texture of image `uri`; float_uri: the same image at full
        precision (images.ImageWriter.float_image), which photonbridge reads
        instead (extensions.PHOTONBRIDGE_blender.source)."""
        src = self._image(uri)
        fsrc = self._image(float_uri) if float_uri else None
        sk = json.dumps(sampler, sort_keys=True)
        if sk not in self.sampler_index:
            self.j["samplers"].append(sampler)
            self.sampler_index[sk] = len(self.j["samplers"]) - 1
        tk = (src, self.sampler_index[sk], fsrc)
        if tk not in self.texture_index:
            t = {"source": tk[0], "sampler": tk[1]}
            if fsrc is not None:
                t["extensions"] = {"PHOTONBRIDGE_blender": {"source": fsrc}}
                self.used.add("PHOTONBRIDGE_blender")
            self.j["textures"].append(t)
            self.texture_index[tk] = len(self.j["textures"]) - 1
        return self.texture_index[tk]

    def add_node(self, node):
        self.j["nodes"].append(node)
        self.j["scenes"][0]["nodes"].append(len(self.j["nodes"]) - 1)
        return len(self.j["nodes"]) - 1

    def finish(self, gltf_path):
        bin_name = os.path.splitext(os.path.basename(gltf_path))[0] + ".bin"
        if self.size:
            self.j["buffers"] = [{"uri": bin_name, "byteLength": self.size}]
        if self.lights:
            self.j.setdefault("extensions", {})["KHR_lights_punctual"] = {"lights": self.lights}
            self.used.add("KHR_lights_punctual")
        self.used.add(EXTENSION)
        self.j["extensionsUsed"] = sorted(self.used)
        for k in ("meshes", "materials", "accessors", "bufferViews", "buffers", "textures", "images",
                  "samplers", "cameras"):
            if not self.j[k]:
                del self.j[k]
        folder = os.path.dirname(os.path.abspath(gltf_path))
        if self.size:
            tmp = os.path.join(folder, bin_name + ".tmp")
            with open(tmp, "wb") as f:
                for c in self.chunks:
                    f.write(c)
            os.replace(tmp, os.path.join(folder, bin_name))
        tmp = gltf_path + ".tmp"
        with open(tmp, "w") as f:
            json.dump(self.j, f, indent=1, allow_nan=False)
        os.replace(tmp, gltf_path)


def _trs(m):
    """glTF TRS of a 4x4 matrix, or None when it has shear (not TRS)."""
    loc, rot, scale = m.decompose()
    back = Matrix.LocRotScale(loc, rot, scale)
    err = max(abs(back[i][j] - m[i][j]) for i in range(3) for j in range(3))
    if err > 1e-5 * max(1.0, max(abs(s) for s in scale)):
        return None
    node = {}
    if loc.length > 0:
        node["translation"] = [loc.x, loc.y, loc.z]
    if abs(rot.w) < 1.0 - 1e-12:
        rot.normalize()
        node["rotation"] = [rot.x, rot.y, rot.z, rot.w]
    if any(abs(s - 1.0) > 1e-9 for s in scale):
        node["scale"] = [scale.x, scale.y, scale.z]
    return node


def instance_key(inst):
    """What identifies an instance from frame to frame: its object, its
    instancer and its persistent id (Blender's own key for motion blur)."""
    return (inst.object.original.name if inst.object.original else inst.object.name,
            inst.parent.original.name if inst.is_instance and inst.parent else "",
            tuple(inst.persistent_id) if inst.is_instance else ())


def node_matrix(inst):
    """A mesh instance's node matrix in glTF axes."""
    return AXIS @ inst.matrix_world @ AXIS_INV


def rigid_matrix(m):
    """A light's or camera's node matrix (scale removed) in glTF axes."""
    return AXIS @ _rigid(m)


def _rigid(m):
    """m without its scale (lights and cameras)."""
    loc, rot, _ = m.decompose()
    if m.to_3x3().determinant() < 0:
        # A mirrored object (a negative scale, its own or a parent's):
        # decompose() negates all three axes, so a camera, spot, sun or area
        # light would look or shine backwards (a camera saw nothing). Cycles
        # normalises each axis and keeps its direction (transform_clear_scale);
        # flipping X alone keeps the view/emission axis -Z and up +Y.
        r = m.to_3x3().normalized()
        r.col[0] = -r.col[0]
        rot = r.to_quaternion()
    return Matrix.Translation(loc) @ rot.to_matrix().to_4x4()


class MeshData:
    """One evaluated mesh as glTF primitives (one per material slot used)."""

    def __init__(self, positions, normals, uvs, tangents, indices_by_slot, colors=None):
        self.positions = positions  # (n, 3) float32, glTF axes
        self.normals = normals
        self.uvs = uvs              # (n, 2) or None
        self.tangents = tangents    # (n, 4) or None
        self.colors = colors        # (n, 4) linear RGBA or None (COLOR_0)
        self.indices_by_slot = indices_by_slot  # slot -> (m, 3) uint32
        self.triangles = sum(len(i) for i in indices_by_slot.values())


def _color_attribute(mesh, want, warn, name):
    """Colour attribute `want` of `mesh` ('' for its render colour attribute)
    as (loops, 4) linear RGBA, or None (with a warning) when it has none."""
    attrs = getattr(mesh, "color_attributes", None)
    layer = None
    if attrs is not None and len(attrs):
        if want:
            layer = attrs.get(want)
        else:
            i = attrs.render_color_index
            layer = attrs[i] if 0 <= i < len(attrs) else attrs[0]
    if layer is None or layer.domain not in ('POINT', 'CORNER'):
        warn("mesh '%s': a material reads colour attribute '%s', which the mesh %s; white is used"
             % (name, want or "(render)", "lacks" if layer is None else "has on the %s domain" % layer.domain))
        return None
    c = np.empty(len(layer.data) * 4, np.float32)
    layer.data.foreach_get("color", c)  # linear for byte and float colours alike
    c = c.reshape(-1, 4)
    if layer.domain == 'POINT':
        loop_vert = np.empty(len(mesh.loops), np.int32)
        mesh.loops.foreach_get("vertex_index", loop_vert)
        c = c[loop_vert]
    return c


def read_mesh(mesh, want_tangents, warn, name, want_color=None):
    """Loop triangles of `mesh` with numpy: merged vertices in glTF axes
    (want_color: the colour attribute to read as COLOR_0, '' for the render
    one, None for none)."""
    mesh.calc_loop_triangles()
    n_tri = len(mesh.loop_triangles)
    if n_tri == 0:
        return None
    if hasattr(mesh, "calc_normals_split"):
        mesh.calc_normals_split()
    n_loops, n_verts = len(mesh.loops), len(mesh.vertices)
    tri_loops = np.empty(n_tri * 3, np.int32)
    mesh.loop_triangles.foreach_get("loops", tri_loops)
    tri_mat = np.empty(n_tri, np.int32)
    mesh.loop_triangles.foreach_get("material_index", tri_mat)
    loop_vert = np.empty(n_loops, np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vert)
    co = np.empty(n_verts * 3, np.float32)
    mesh.vertices.foreach_get("co", co)
    nrm = np.empty(n_loops * 3, np.float32)
    mesh.loops.foreach_get("normal", nrm)
    cols = [co.reshape(-1, 3)[loop_vert], nrm.reshape(-1, 3)]
    uv_layer = None
    for layer in mesh.uv_layers:
        if layer.active_render:
            uv_layer = layer
    if uv_layer is None and len(mesh.uv_layers):
        uv_layer = mesh.uv_layers[0]
    if uv_layer is not None:
        uv = np.empty(n_loops * 2, np.float32)
        uv_layer.data.foreach_get("uv", uv)
        uv = uv.reshape(-1, 2)
        uv[:, 1] = 1.0 - uv[:, 1]  # glTF's v runs down the image
        cols.append(uv)
    tangent = None
    if want_tangents:
        if uv_layer is None:
            warn("mesh '%s': a normal map without a UV map; no tangents" % name)
        else:
            try:
                mesh.calc_tangents(uvmap=uv_layer.name)
                t = np.empty(n_loops * 3, np.float32)
                mesh.loops.foreach_get("tangent", t)
                sign = np.empty(n_loops, np.float32)
                mesh.loops.foreach_get("bitangent_sign", sign)
                tangent = np.concatenate([t.reshape(-1, 3), sign.reshape(-1, 1)], axis=1)
                cols.append(tangent)
            except RuntimeError as e:
                warn("mesh '%s': tangents failed (%s); photonbridge derives them from the UVs" % (name, e))
    color = _color_attribute(mesh, want_color, warn, name) if want_color is not None else None
    if color is not None:
        cols.append(color)
    attr = np.ascontiguousarray(np.concatenate(cols, axis=1), dtype=np.float32)
    # Merge loops whose attributes are bit-identical into one vertex (the
    # corners glTF shares): sort the loops by vertex index, then by a hash of
    # their attribute bits, and start a new vertex wherever a row differs
    # from the one before. Rows that are equal end up adjacent (up to hash
    # collisions, which only merge less), in O(n log n) on two int keys.
    bits = attr.view(np.uint32)
    h = bits[:, 0].astype(np.uint64)
    for c in range(1, bits.shape[1]):
        h = (h * np.uint64(0x100000001B3)) ^ bits[:, c]
    order = np.lexsort((h, loop_vert))
    sb = bits[order]
    new = np.empty(n_loops, bool)
    new[0] = True
    np.any(sb[1:] != sb[:-1], axis=1, out=new[1:])
    vertex_of_loop = np.empty(n_loops, np.uint32)
    vertex_of_loop[order] = np.cumsum(new, dtype=np.uint32) - 1
    verts = attr[order[new]]
    idx = vertex_of_loop[tri_loops].reshape(-1, 3)
    pos = (verts[:, 0:3] @ AXIS3.T).astype(np.float32)
    n = (verts[:, 3:6] @ AXIS3.T).astype(np.float32)
    length = np.linalg.norm(n, axis=1)
    bad = ~(length > 1e-12)
    n[~bad] /= length[~bad, None]
    n[bad] = (0.0, 1.0, 0.0)  # degenerate corners (zero-area faces)
    c = 6
    uvs = None
    if uv_layer is not None:
        uvs = verts[:, c:c + 2].copy()
        c += 2
    tan = None
    if tangent is not None:
        t3 = (verts[:, c:c + 3] @ AXIS3.T).astype(np.float32)
        tl = np.linalg.norm(t3, axis=1)
        ok = tl > 1e-12
        t3[ok] /= tl[ok, None]
        t3[~ok] = (1.0, 0.0, 0.0)
        w = np.where(verts[:, c + 3] < 0, -1.0, 1.0).astype(np.float32)
        tan = np.concatenate([t3, w[:, None]], axis=1)
        c += 4
    colors = None
    if color is not None:
        colors = np.clip(verts[:, c:c + 4], 0.0, None).astype(np.float32)
    by_slot = {}
    for slot in np.unique(tri_mat):
        by_slot[int(slot)] = np.ascontiguousarray(idx[tri_mat == slot])
    return MeshData(pos, n, uvs, tan, by_slot, colors)


class SceneWriter:
    def __init__(self, depsgraph, gltf_path, camera=None, image_folder=None):
        self.dg = depsgraph
        self.scene = depsgraph.scene
        self.path = gltf_path
        self.folder = image_folder or os.path.dirname(os.path.abspath(gltf_path))
        self.report = WriteReport()
        self.doc = Document()
        self.images = images_mod.ImageWriter(self.folder, self.warn)
        self.images.frame = self.scene.frame_current
        self.mats = materials_mod.MaterialWriter(self.doc, self.images, self.warn)
        self.camera = camera
        self.mesh_cache = {}
        self.warned = set()
        # instance key -> glTF node index (anim.py samples these over frames)
        self.node_of = {}
        self._holdout_objects = None  # names in the view layer's holdout collections

    def warn(self, text):
        if text not in self.warned:
            self.warned.add(text)
            self.report.warnings.append(text)

    def note(self, text):
        if text not in self.warned:
            self.warned.add(text)
            self.report.notes.append(text)

    # ---- geometry ------------------------------------------------------------------

    def _materials(self, obj):
        mats = tuple(s.material for s in obj.material_slots) or (None,)
        override = getattr(self.dg.view_layer, "material_override", None)
        if override is not None:
            # The view layer's Material Override (a clay render): Cycles
            # renders every slot, empty ones too, with it (find_used_shaders).
            return (override,) * len(mats)
        return mats

    def _mesh_entry(self, obj, holdout):
        """[glTF mesh index or None until a TRS instance needs it, MeshData or
        None] of an evaluated object, cached by its evaluated data and
        materials (each mesh read and written once)."""
        mats = self._materials(obj)
        key = (obj.data.as_pointer() if obj.data else obj.as_pointer(), tuple(m.name if m else "" for m in mats),
               holdout)
        if key not in self.mesh_cache:
            self.mesh_cache[key] = [None, self._mesh_data(obj, mats, holdout)]
        return self.mesh_cache[key]

    def _mesh_data(self, obj, mats, holdout):
        gltf_mats = [self.mats.material(m, holdout) for m in mats]
        want_tan = any(i in self.mats.uses_normal_map for i in gltf_mats)
        vcols = sorted({self.mats.vertex_color[i] for i in gltf_mats if i in self.mats.vertex_color})
        if len(vcols) > 1:
            self.warn("object '%s': its materials read colour attributes %s; '%s' is written for all"
                      % (obj.name, ", ".join("'%s'" % v for v in vcols), vcols[0]))
        try:
            mesh = obj.to_mesh(preserve_all_data_layers=False, depsgraph=self.dg)
        except RuntimeError as e:
            self.warn("object '%s': no mesh (%s); left out" % (obj.name, e))
            return None
        if mesh is None:
            return None
        try:
            data = read_mesh(mesh, want_tan, self.warn, obj.name, vcols[0] if vcols else None)
        finally:
            obj.to_mesh_clear()
        if data is None:
            if any(m.type == 'NODES' and m.show_render for m in getattr(obj, "modifiers", ())):
                # Geometry nodes that output instances only: the instances
                # come as instances of their own, nothing is lost.
                self.note("object '%s': no faces of its own (geometry-node instances only)" % obj.name)
            else:
                self.warn("object '%s': its mesh has no faces; left out" % obj.name)
        else:
            data.gltf_materials = gltf_mats
        return data

    def _write_mesh(self, name, data, world=None):
        """A glTF mesh of `data` (vertices transformed by `world`, a 4x4 in
        glTF axes, when an instance cannot be a TRS node)."""
        pos, nrm, tan = data.positions, data.normals, data.tangents
        if world is not None:
            m = np.array(world, np.float64)
            pos = (pos @ m[:3, :3].T + m[:3, 3]).astype(np.float32)
            nm = np.linalg.inv(m[:3, :3]).T
            nrm = nrm @ nm.T
            nrm = (nrm / np.linalg.norm(nrm, axis=1)[:, None]).astype(np.float32)
            if tan is not None:
                t3 = tan[:, :3] @ m[:3, :3].T
                t3 /= np.linalg.norm(t3, axis=1)[:, None]
                flip = -1.0 if np.linalg.det(m[:3, :3]) < 0 else 1.0
                tan = np.concatenate([t3, tan[:, 3:] * flip], axis=1).astype(np.float32)
        attrs = {"POSITION": self.doc.accessor(pos, "VEC3", minmax=True),
                 "NORMAL": self.doc.accessor(nrm, "VEC3")}
        if data.uvs is not None:
            attrs["TEXCOORD_0"] = self.doc.accessor(data.uvs, "VEC2")
        if tan is not None:
            attrs["TANGENT"] = self.doc.accessor(tan, "VEC4")
        small = len(pos) < 65536
        color_acc = None
        prims = []
        for slot, idx in sorted(data.indices_by_slot.items()):
            mi = data.gltf_materials[min(slot, len(data.gltf_materials) - 1)]
            ind = idx.ravel().astype(np.uint16 if small else np.uint32)
            pa = attrs
            if data.colors is not None and mi in self.mats.vertex_color:
                # COLOR_0 only where the material reads it: glTF multiplies
                # every material's base colour by it.
                if color_acc is None:
                    color_acc = self.doc.accessor(data.colors, "VEC4")
                pa = dict(attrs, COLOR_0=color_acc)
            prims.append({"attributes": pa, "indices": self.doc.accessor(ind, "SCALAR", target=34963),
                          "material": mi, "mode": 4})
        self.doc.j["meshes"].append({"name": name, "primitives": prims})
        self.report.meshes += 1
        return len(self.doc.j["meshes"]) - 1

    def _instance(self, inst, obj):
        holdout = bool(getattr(obj, "is_holdout", False)) or self._collection_holdout(obj)
        entry = self._mesh_entry(obj, holdout)
        data = entry[1]
        if data is None:
            return
        m = node_matrix(inst)
        node = _trs(m)
        name = obj.name if not inst.is_instance else "%s (instance of %s)" % (inst.parent.name if inst.parent
                                                                              else "?", obj.name)
        baked = node is None
        if baked:
            # Shear: this instance's vertices in world space (glTF nodes are TRS).
            node = {}
            index = self._write_mesh(obj.name + " (baked)", data, world=[list(r) for r in m])
        else:
            if entry[0] is None:
                entry[0] = self._write_mesh(obj.name, data)
            index = entry[0]
        node["name"] = name
        node["mesh"] = index
        n = self.doc.add_node(node)
        if not baked:
            self.node_of[instance_key(inst)] = n
        self.report.instances += 1
        self.report.triangles += data.triangles

    def _collection_holdout(self, obj):
        """The view layer's holdout collections (Cycles' layer holdout)."""
        holdouts = self._holdout_objects
        if holdouts is None:
            holdouts = set()

            def walk(lc):
                if lc.holdout:
                    for o in lc.collection.all_objects:
                        holdouts.add(o.name)
                for c in lc.children:
                    walk(c)
            walk(self.dg.view_layer.layer_collection)
            self._holdout_objects = holdouts
        return obj.original.name in holdouts if obj.original else False

    # ---- lights ------------------------------------------------------------------

    def _light(self, inst, obj):
        lamp = obj.data
        m = rigid_matrix(inst.matrix_world)
        node = _trs(m) or {}
        node["name"] = obj.name
        scale = inst.matrix_world.to_scale()
        cyc = getattr(lamp, "cycles", None)
        tint, gain = self._light_nodes(obj)
        color = [c * t for c, t in zip(lamp.color, tint)]
        energy = lamp.energy * gain
        color, energy, factors = self._light_factors(obj, lamp, color, energy, scale)
        if not energy >= 0.0:
            # Blender allows negative power (Cycles subtracts that light);
            # photonbridge refuses a negative light in a file (exit 5), which
            # failed the whole render: it is left out instead.
            self.warn("light '%s': negative %s %g is not rendered (photonbridge has no negative light); left out"
                      % (obj.name, "strength" if lamp.type == 'SUN' else "power", energy))
            return
        ext = {"type": lamp.type, "name": lamp.name, "color": color,
               "castShadow": self._light_casts_shadow(lamp, cyc),
               "useMIS": bool(getattr(cyc, "use_multiple_importance_sampling", True))}
        if lamp.type == 'SUN':
            ext["strength"] = energy
            ext["angle"] = lamp.angle
        else:
            ext["power"] = energy
        ext.update(factors)
        if bpy.app.version >= (4, 0, 0):
            # Cycles 4.0 changed two light models: an area light's radiance is
            # P / (pi A) (3.4: P / (4 A)) and a spot's falloff lost its cosine.
            ext["model"] = "cycles4"
        link = getattr(obj, "light_linking", None)
        if link is not None and (link.receiver_collection is not None or link.blocker_collection is not None):
            # 4.0+ light and shadow linking: per-light receiver and blocker sets.
            self.warn("light '%s': light linking is not supported; it lights and is blocked by every object"
                      % obj.name)
        if lamp.type in ('POINT', 'SPOT'):
            ext["radius"] = lamp.shadow_soft_size
            if not getattr(lamp, "use_soft_falloff", bpy.app.version < (4, 0, 0)):
                # 4.1+: Soft Falloff off makes Cycles' light a true sphere
                # (kernel/light/point.h is_sphere); on, 3.4's facing disc.
                # 4.0 had only the sphere (no setting), 3.x only the disc.
                ext["softFalloff"] = False
        if lamp.type == 'SPOT':
            ext["spotSize"] = lamp.spot_size
            ext["spotBlend"] = lamp.spot_blend
        if lamp.type == 'AREA':
            ext["shape"] = lamp.shape
            ext["size"], ext["sizeY"] = _area_light_size(lamp, scale)
            ext["spread"] = getattr(lamp, "spread", math.pi)
            if not (ext["size"] > 0 and ext["sizeY"] > 0):
                # Cycles 3.4 renders a zero-area light black (measured: a 0 m
                # disk, 16 spp); photonbridge refuses one in a file (exit 5),
                # so the render leaves it out instead of failing.
                self.warn("light '%s': area light of size %g x %g m emits nothing; left out"
                          % (obj.name, ext["size"], ext["sizeY"]))
                return
            self.note("light '%s': area lights have no glTF form; only the %s extension describes it"
                      % (obj.name, EXTENSION))
        if lamp.type in ('POINT', 'SPOT', 'SUN'):
            # Blender 3.4's exporter, lighting mode "Standard" (SPEC).
            light = {"name": lamp.name, "color": color,
                     "type": {"POINT": "point", "SPOT": "spot", "SUN": "directional"}[lamp.type],
                     "intensity": energy * WATTS_TO_LUMENS / (1.0 if lamp.type == 'SUN' else 4.0 * math.pi)}
            if lamp.type == 'SPOT':
                outer = lamp.spot_size * 0.5
                light["spot"] = {"innerConeAngle": outer - outer * lamp.spot_blend, "outerConeAngle": outer}
            if lamp.use_custom_distance:
                light["range"] = lamp.cutoff_distance
            self.doc.lights.append(light)
            node.setdefault("extensions", {})["KHR_lights_punctual"] = {"light": len(self.doc.lights) - 1}
        node.setdefault("extensions", {})[EXTENSION] = {"light": ext}
        self.node_of[instance_key(inst)] = self.doc.add_node(node)
        self.report.lights += 1

    def _light_casts_shadow(self, lamp, cyc):
        """Cycles 3.x reads the light's Cycles 'Cast Shadow'; 4.x removed it
        and reads Light.use_shadow (blender/light.cpp)."""
        if cyc is not None and hasattr(cyc, "cast_shadow"):
            return bool(cyc.cast_shadow)
        return bool(getattr(lamp, "use_shadow", True))

    def _light_factors(self, obj, lamp, color, energy, scale):
        """(colour, power or strength, extension members) with the light
        settings Blender 4.5 adds, as Cycles 4.5 computes them: strength =
        colour x temperature colour x energy x 2^exposure (blender/light.cpp),
        and Normalize off leaves out the 1/area of the emission
        (scene/light.cpp Light::area: a point or spot light's sphere 4 pi r^2,
        4 when r = 0; an area light's w x h, x pi/4 for ellipses and discs;
        a sun's pi sin^2(angle/2), 1 when the angle is 0), which is the
        normalized light's power times that area. Lights of 3.4 files have
        none of these and keep their power."""
        ext = {}
        exposure = float(getattr(lamp, "exposure", 0.0))
        if exposure != 0.0:
            energy *= 2.0 ** exposure
            ext["exposure"] = exposure
        if getattr(lamp, "use_temperature", False):
            tc = list(lamp.temperature_color)
            color = [c * t for c, t in zip(color, tc)]
            ext["temperature"] = float(lamp.temperature)
        if not getattr(lamp, "normalize", True):
            if lamp.type in ('POINT', 'SPOT'):
                r = lamp.shadow_soft_size
                area = 4.0 * math.pi * r * r or 4.0
            elif lamp.type == 'SUN':
                area = math.pi * math.sin(lamp.angle * 0.5) ** 2 if lamp.angle > 0 else 1.0
            else:
                w, h = _area_light_size(lamp, scale)
                area = w * h * (math.pi / 4.0 if lamp.shape in ('DISK', 'ELLIPSE') else 1.0)
            energy *= area
            ext["normalize"] = False
        return color, energy, ext

    def _light_nodes(self, obj):
        """(RGB tint, gain) of a light's node tree: Cycles multiplies the
        light's colour and power by the Emission shader on its Light Output
        (Color x Strength; white and 1 without nodes). Anything else there is
        a warning and leaves the light as it is."""
        lamp = obj.data
        if not lamp.use_nodes or lamp.node_tree is None:
            return (1.0, 1.0, 1.0), 1.0
        out = materials_mod.active_output(lamp.node_tree)
        src = materials_mod._source(out.inputs["Surface"]) if out else None
        if src is None:
            # Cycles builds the light's shader from its nodes alone: with
            # nothing on a Cycles Light Output it emits nothing (measured:
            # a black render); it had rendered at full power here.
            self.warn("light '%s': nothing is connected to a Light Output for Cycles; it emits nothing, as in Cycles"
                      % obj.name)
            return (1.0, 1.0, 1.0), 0.0
        e = src.node
        if e.type == 'EMISSION' and materials_mod._source(e.inputs["Color"]) is None and \
                materials_mod._source(e.inputs["Strength"]) is None:
            return tuple(materials_mod._value(e.inputs["Color"])[:3]), float(materials_mod._value(e.inputs["Strength"]))
        self.warn("light '%s': its node tree is not translated (colour and power are the light's own)" % obj.name)
        return (1.0, 1.0, 1.0), 1.0

    # ---- camera -------------------------------------------------------------------

    def _render_size(self):
        r = self.scene.render
        return r.resolution_x * r.resolution_percentage // 100, r.resolution_y * r.resolution_percentage // 100

    def _camera(self, obj):
        cam = obj.data
        r = self.scene.render
        # Blender's exporter: the full resolution with the pixel aspect.
        width, height = r.pixel_aspect_x * r.resolution_x, r.pixel_aspect_y * r.resolution_y
        aspect = width / height
        c = {"name": cam.name}
        if cam.type == 'ORTHO':
            sq = max(width, height)
            c["type"] = "orthographic"
            c["orthographic"] = {"xmag": cam.ortho_scale * (width / sq) / 2, "ymag": cam.ortho_scale * (height / sq) / 2,
                                 "znear": cam.clip_start, "zfar": cam.clip_end}
        else:
            if cam.type not in ('PERSP', 'PANO'):
                self.warn("camera '%s': type %s is rendered as perspective" % (obj.name, cam.type))
            if width >= height:
                yfov = cam.angle if cam.sensor_fit == 'VERTICAL' else 2.0 * math.atan(math.tan(cam.angle * 0.5) / aspect)
            else:
                yfov = 2.0 * math.atan(math.tan(cam.angle * 0.5) / aspect) if cam.sensor_fit == 'HORIZONTAL' else cam.angle
            c["type"] = "perspective"
            c["perspective"] = {"aspectRatio": aspect, "yfov": yfov, "znear": cam.clip_start, "zfar": cam.clip_end}
        ext = {
            "type": "ORTHO" if cam.type == 'ORTHO' else "PERSP", "lens": cam.lens, "sensorFit": cam.sensor_fit,
            "sensorWidth": cam.sensor_width, "sensorHeight": cam.sensor_height, "orthoScale": cam.ortho_scale,
            "shiftX": cam.shift_x, "shiftY": cam.shift_y, "clipStart": cam.clip_start, "clipEnd": cam.clip_end,
            "aspect": aspect}
        if cam.type == 'PANO':
            self._panorama(obj, cam, ext)
        if cam.dof.use_dof:
            ext.update(self._dof(obj, cam))
        c["extensions"] = {EXTENSION: ext}
        if obj.matrix_world.to_3x3().determinant() < 0:
            self.warn("camera '%s': a negative scale mirrors the image in Cycles; photonbridge renders it unmirrored"
                      % obj.name)
        if r.pixel_aspect_x != r.pixel_aspect_y:
            self.warn("render: pixel aspect %g:%g is rendered with square pixels"
                      % (r.pixel_aspect_x, r.pixel_aspect_y))
        self.doc.j["cameras"].append(c)
        m = rigid_matrix(obj.matrix_world)
        node = _trs(m) or {}
        node["name"] = obj.name
        node["camera"] = len(self.doc.j["cameras"]) - 1
        self.node_of["camera"] = self.doc.add_node(node)

    # Cycles 3.4's panoramic cameras (blender/camera.cpp): the properties live on
    # the camera since 3.3 (before on cam.cycles); the polynomial fisheye and
    # others are rendered as perspective.
    PANORAMAS = ("EQUIRECTANGULAR", "FISHEYE_EQUIDISTANT", "FISHEYE_EQUISOLID", "MIRRORBALL")

    def _panorama(self, obj, cam, ext):
        src = cam if hasattr(cam, "panorama_type") else getattr(cam, "cycles", cam)
        kind = getattr(src, "panorama_type", "FISHEYE_EQUISOLID")
        if kind not in self.PANORAMAS:
            self.warn("camera '%s': panorama type %s is rendered as perspective" % (obj.name, kind))
            return
        ext["type"] = "PANO"
        ext["panoramaType"] = kind
        for key, name in (("fisheyeFov", "fisheye_fov"), ("fisheyeLens", "fisheye_lens"),
                          ("latitudeMin", "latitude_min"), ("latitudeMax", "latitude_max"),
                          ("longitudeMin", "longitude_min"), ("longitudeMax", "longitude_max")):
            if hasattr(src, name):
                ext[key] = float(getattr(src, name))

    def _dof(self, obj, cam):
        """Depth of field as Blender holds it; the loader makes Cycles' aperture
        radius of it. A focus object gives its distance along the camera's view
        axis (blender_camera_focal_distance: the bone's head with a subtarget)."""
        dof = cam.dof
        focus = dof.focus_distance
        target = dof.focus_object
        if target is not None:
            m = target.matrix_world
            sub = getattr(dof, "focus_subtarget", "")
            if sub and target.pose and sub in target.pose.bones:
                m = m @ target.pose.bones[sub].matrix
            cm = obj.matrix_world
            view = cm.col[2].xyz.normalized()
            focus = abs(view.dot(cm.col[3].xyz - m.col[3].xyz))
        return {"focusDistance": float(focus), "apertureFstop": float(dof.aperture_fstop),
                "apertureBlades": int(dof.aperture_blades), "apertureRotation": float(dof.aperture_rotation),
                "apertureRatio": float(dof.aperture_ratio)}

    # ---- world and root ----------------------------------------------------------

    def _scene_world(self):
        """The world Cycles renders: the view layer's World Override (4.x)
        when set, else the scene's."""
        return getattr(self.dg.view_layer, "world_override", None) or self.scene.world

    def _world(self):
        world = self._scene_world()
        if world is None:
            return None
        w = {"color": list(world.color), "strength": 1.0}
        vis = getattr(world, "cycles_visibility", None)
        w["visibleToCamera"] = bool(getattr(vis, "camera", True))
        if not world.use_nodes or world.node_tree is None:
            return w
        out = materials_mod.active_output(world.node_tree)
        src = materials_mod._source(out.inputs["Surface"]) if out else None
        if src is None:
            return None  # nothing connected: Cycles renders black
        node = src.node
        if node.type != 'BACKGROUND':
            self.warn("world '%s': node '%s' (%s) is not translated; the world is black" % (world.name, node.name,
                                                                                          node.bl_label))
            return None
        w["color"] = list(node.inputs["Color"].default_value)[:3]
        w["strength"] = float(node.inputs["Strength"].default_value)
        if materials_mod._source(node.inputs["Strength"]) is not None:
            self.warn("world '%s': a linked Strength is not translated" % world.name)
        col = materials_mod._source(node.inputs["Color"])
        if col is not None:
            if col.node.type == 'TEX_ENVIRONMENT' and col.node.image is not None:
                env = col.node
                if env.projection != 'EQUIRECTANGULAR':
                    self.warn("world '%s': environment projection %s is written as equirectangular"
                              % (world.name, env.projection))
                uri = self.images.environment_image(env.image)
                if uri:
                    e = {"uri": uri, "projection": "EQUIRECTANGULAR", "rotation": [0.0, 0.0, 0.0], "strength": 1.0}
                    vec = materials_mod._source(env.inputs["Vector"])
                    if vec is not None and vec.node.type == 'MAPPING':
                        e["rotation"] = list(vec.node.inputs["Rotation"].default_value)
                    elif vec is not None:
                        self.warn("world '%s': node '%s' drives the environment's Vector and is not translated"
                                  % (world.name, vec.node.name))
                    w["environment"] = e
            elif col.node.type == 'TEX_SKY' and col.node.sky_type in ('NISHITA', 'SINGLE_SCATTERING'):
                # 5.0 renamed Nishita to Single Scattering (Dust to Aerosol).
                self._sky(world, col.node, w)
            elif col.node.type == 'TEX_SKY' and col.node.sky_type == 'MULTIPLE_SCATTERING':
                # 5.0's default sky model; its ground reflection and
                # multiple scattering are not modelled here.
                self.warn("world '%s': Sky Texture '%s' uses Multiple Scattering, which photonbridge does not "
                          "model; it is baked with the Single Scattering model (darker and bluer near the horizon "
                          "than Cycles)" % (world.name, col.node.name))
                self._sky(world, col.node, w)
            else:
                self.warn("world '%s': node '%s' (%s) drives the Background colour and is not translated; its "
                          "colour is written" % (world.name, col.node.name, col.node.bl_label))
        return w

    def _sky(self, world, node, w):
        """A Nishita Sky Texture on the Background colour (sky.py): the sky
        baked into an equirectangular .hdr environment, the sun disc (when
        on) a soft sun light of angle sun_size with the disc's irradiance
        times the Background strength."""
        from . import sky as sky_mod
        if materials_mod._source(node.inputs["Vector"]) is not None:
            self.warn("world '%s': node '%s' drives the Sky Texture's Vector and is not translated"
                      % (world.name, materials_mod._source(node.inputs["Vector"]).node.name))
        sky, rgb, irr = sky_mod.baked(node)
        uri = self.images._unique(world.name + "_sky", ".hdr")
        sky_mod.write_hdr(os.path.join(self.images.folder, uri), rgb)
        w["environment"] = {"uri": uri, "projection": "EQUIRECTANGULAR", "rotation": [0.0, 0.0, 0.0],
                            "strength": 1.0}
        if irr is None or not max(irr) * w["strength"] > 0:
            return
        strength = float(max(irr)) * w["strength"]
        color = [float(c) / float(max(irr)) for c in irr]
        from mathutils import Vector
        m = Vector(tuple(float(c) for c in sky.sun_direction())).to_track_quat('Z', 'Y').to_matrix().to_4x4()
        node_j = _trs(AXIS @ m) or {}
        node_j["name"] = world.name + " sun disc"
        ext = {"type": "SUN", "name": node_j["name"], "color": color, "castShadow": True, "useMIS": True,
               "strength": strength, "angle": sky.sun_size}
        self.doc.lights.append({"name": node_j["name"], "color": color, "type": "directional",
                                "intensity": strength * WATTS_TO_LUMENS})
        node_j["extensions"] = {"KHR_lights_punctual": {"light": len(self.doc.lights) - 1},
                                EXTENSION: {"light": ext}}
        self.doc.add_node(node_j)
        self.note("world '%s': Sky Texture baked (%s) with its sun disc as a %.4g W/m^2 sun light"
                  % (world.name, uri, strength))

    def _root(self, frame_range):
        sc, r, vs = self.scene, self.scene.render, self.scene.view_settings
        cyc = getattr(sc, "cycles", None)
        size = self._render_size()
        border = None
        if r.use_border:
            border = [r.border_min_x, r.border_min_y, r.border_max_x, r.border_max_y]
        root = {
            "version": EXTENSION_VERSION, "blender": bpy.app.version_string, "scene": sc.name,
            "viewLayer": self.dg.view_layer.name,
            "frame": {"current": sc.frame_current, "start": sc.frame_start, "end": sc.frame_end,
                      "step": sc.frame_step, "fps": r.fps, "fpsBase": r.fps_base},
            "render": {"resolution": list(size), "pixelAspect": [r.pixel_aspect_x, r.pixel_aspect_y],
                       "border": border, "crop": bool(r.use_crop_to_border),
                       "filmTransparent": bool(r.film_transparent),
                       "bounces": {"max": getattr(cyc, "max_bounces", 12), "diffuse": getattr(cyc, "diffuse_bounces", 4),
                                   "glossy": getattr(cyc, "glossy_bounces", 4),
                                   "transmission": getattr(cyc, "transmission_bounces", 12),
                                   "transparent": getattr(cyc, "transparent_max_bounces", 8)},
                       "filterWidth": getattr(cyc, "filter_width", 1.5)},
            "colorManagement": {"display": sc.display_settings.display_device, "view": vs.view_transform,
                                "look": vs.look, "exposure": vs.exposure, "gamma": vs.gamma},
        }
        config = ocio_config()
        if config:
            root["colorManagement"]["ocioConfig"] = config
        if frame_range is not None:
            root["frame"]["start"], root["frame"]["end"] = frame_range
        world = self._world()
        if world is not None:
            root["world"] = world
        return root

    # ---- the file -------------------------------------------------------------------

    def write(self, frame_range=None):
        t0 = time.perf_counter()
        self.collect()
        return self.finish(t0, frame_range)

    def collect(self):
        """Every instance, light and the camera, at the depsgraph's frame."""
        cam = self.camera or self.scene.camera
        if self.scene.render.use_motion_blur:
            self.warn("scene '%s': motion blur is not rendered (each frame is an instant)" % self.scene.name)
        for inst in self.dg.object_instances:
            obj = inst.object
            if obj.type in GEOMETRY_TYPES:
                # show_self: the instancer's own geometry (hidden when its
                # "Show Instancer for Render" or a particle emitter's is off,
                # as Cycles' sync skips it); show_particles: its particles.
                if getattr(inst, "show_self", True):
                    self._instance(inst, obj)
                if not inst.is_instance and getattr(inst, "show_particles", True):
                    for ps in getattr(obj, "particle_systems", ()):
                        st = ps.settings
                        if st.type == 'HAIR' and st.render_type == 'PATH':
                            self.warn("object '%s': hair of particle system '%s' is not rendered (strands); "
                                      "set Render As to Object or Collection for instances" % (obj.name, ps.name))
            elif obj.type == 'LIGHT':
                self._light(inst, obj)
            elif obj.type in ('CURVES', 'POINTCLOUD', 'VOLUME', 'GPENCIL', 'GREASEPENCIL'):
                self.warn("object '%s': type %s is not rendered" % (obj.name, obj.type))
        if cam is not None and cam.type == 'CAMERA':
            self._camera(cam.evaluated_get(self.dg) if not cam.is_evaluated else cam)
        else:
            self.warn("scene '%s': no camera; photonbridge frames the scene with a default camera" % self.scene.name)
        if self.report.lights == 0 and not self._world_lit() and not any(
                m.get("emissiveFactor") for m in self.doc.j["materials"]):
            self.warn("scene '%s': no lights, no emissive materials and a black world" % self.scene.name)

    def _world_lit(self):
        """Whether the world (as _world translates it) may emit: a lit world is
        a light, so a scene lit by it alone is not unlit. No side effects
        (_world writes the environment image)."""
        world = self._scene_world()
        if world is None:
            return False
        if not world.use_nodes or world.node_tree is None:
            return max(world.color) > 0
        out = materials_mod.active_output(world.node_tree)
        src = materials_mod._source(out.inputs["Surface"]) if out else None
        if src is None or src.node.type != 'BACKGROUND':
            return False
        node = src.node
        if materials_mod._source(node.inputs["Color"]) is not None:
            return True  # an environment (or a colour the writer keeps)
        strength = node.inputs["Strength"]
        if materials_mod._source(strength) is not None:
            return True
        return float(strength.default_value) > 0 and max(list(node.inputs["Color"].default_value)[:3]) > 0

    def finish(self, t0, frame_range=None):
        self.doc.j.setdefault("extensions", {})[EXTENSION] = self._root(frame_range)
        self.doc.finish(self.path)
        self.report.seconds = time.perf_counter() - t0
        self.report.path = self.path
        return self.report


def write_gltf(depsgraph, path, camera=None, image_folder=None):
    """Writes the evaluated scene of `depsgraph` to `path` (.gltf, with a .bin
    and the images beside it); returns a WriteReport (warnings, counts,
    seconds). `camera`: the camera object to write (default: the scene's)."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    return SceneWriter(depsgraph, path, camera, image_folder).write()
