"""Build photonbridge's sample scenes in Blender from code and export them as glTF.

Run headless (Blender 3.4 or later):

    blender -b --factory-startup --python-exit-code 1 \
        -P exporters/blender/make_samples.py -- --out samples [--only NAME]

Every scene starts from an empty factory-startup file and is built with bpy
only (no .blend files, no randomness), so running the script twice gives the
same content; tests/gltf_content.py checks that.  Each scene NAME is written
as glTF Separate to OUT/NAME/NAME.gltf + NAME.bin (+ textures) by Blender's
own glTF exporter.

Units: metres, Blender Z up (the exporter converts to glTF +Y up).  Light
powers are set the way an artist sets them in Blender: point and spot lights
in watts, the sun in W/m^2.  The exporter's default lighting mode "Standard"
(SPEC) writes point/spot intensity = P * 683 / (4 pi) cd and sun intensity =
S * 683 lx; see /work/shared/VALIDATION.md and samples/README.md.
"""

import argparse
import json
import math
import os
import struct
import sys
import tempfile
import zlib

import bpy
from mathutils import Vector

SCENES = {}  # name -> builder, in the order they are exported


def scene(fn):
    SCENES[fn.__name__] = fn
    return fn


# --------------------------------------------------------------------------
# Scene set-up helpers
# --------------------------------------------------------------------------

def reset_scene(res_x, res_y):
    """An empty factory-startup file with render settings whose aspect ratio
    the exporter writes into the glTF camera (aspectRatio, yfov)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.name = "Scene"
    sc.render.engine = 'CYCLES'
    sc.render.resolution_x = res_x
    sc.render.resolution_y = res_y
    sc.render.resolution_percentage = 100
    sc.render.pixel_aspect_x = 1.0
    sc.render.pixel_aspect_y = 1.0
    sc.unit_settings.system = 'METRIC'
    sc.unit_settings.scale_length = 1.0
    # Linear output for comparisons with Cycles; not exported.
    sc.view_settings.view_transform = 'Standard'
    return sc


def link(obj):
    bpy.context.scene.collection.objects.link(obj)
    return obj


def look_at(obj, target):
    """Point the object's local -Z (camera view axis, light axis) at target,
    local +Y up."""
    d = Vector(target) - obj.location
    obj.rotation_mode = 'QUATERNION'
    obj.rotation_quaternion = d.to_track_quat('-Z', 'Y')


def add_camera(location, target, lens_mm, sensor_mm=36.0):
    cam = bpy.data.cameras.new("Camera")
    cam.type = 'PERSP'
    cam.lens_unit = 'MILLIMETERS'
    cam.lens = lens_mm
    cam.sensor_fit = 'AUTO'
    cam.sensor_width = sensor_mm
    cam.clip_start = 0.05
    cam.clip_end = 200.0
    obj = link(bpy.data.objects.new("Camera", cam))
    obj.location = location
    look_at(obj, target)
    bpy.context.scene.camera = obj
    return obj


def add_point_light(name, location, watts, color=(1.0, 1.0, 1.0)):
    lamp = bpy.data.lights.new(name, 'POINT')
    lamp.energy = watts               # W
    lamp.color = color
    lamp.shadow_soft_size = 0.0       # radius 0: a true point light
    lamp.use_nodes = False            # the exporter then reads lamp.energy
    obj = link(bpy.data.objects.new(name, lamp))
    obj.location = location
    return obj


def add_spot_light(name, location, target, watts, spot_size_deg, spot_blend):
    lamp = bpy.data.lights.new(name, 'SPOT')
    lamp.energy = watts               # W, as if it were a point light
    lamp.shadow_soft_size = 0.0
    lamp.spot_size = math.radians(spot_size_deg)   # full cone angle
    lamp.spot_blend = spot_blend
    lamp.use_nodes = False
    obj = link(bpy.data.objects.new(name, lamp))
    obj.location = location
    look_at(obj, target)
    return obj


def add_sun(name, direction, w_per_m2):
    """direction: where the light travels (from the sun into the scene)."""
    lamp = bpy.data.lights.new(name, 'SUN')
    lamp.energy = w_per_m2            # W/m^2 (irradiance on a surface facing it)
    lamp.angle = 0.0                  # a hard directional light, as glTF has it
    lamp.use_nodes = False
    obj = link(bpy.data.objects.new(name, lamp))
    obj.location = (0.0, 0.0, 20.0)   # position does not matter for a sun
    obj.rotation_mode = 'QUATERNION'
    obj.rotation_quaternion = Vector(direction).to_track_quat('-Z', 'Y')
    return obj


def principled(name, base=(0.8, 0.8, 0.8), metallic=0.0, roughness=1.0,
               specular=0.0, transmission=0.0, ior=1.5):
    """A Principled BSDF material.  The defaults are a pure Lambertian
    diffuse: Specular 0 makes the exporter write KHR_materials_specular with
    specularColorFactor [0, 0, 0]."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*base, 1.0)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Specular"].default_value = specular
    bsdf.inputs["Transmission"].default_value = transmission
    bsdf.inputs["IOR"].default_value = ior
    mat.diffuse_color = (*base, 1.0)  # viewport colour only
    return mat


def diffuse(name, base):
    return principled(name, base=base, metallic=0.0, roughness=1.0, specular=0.0)


# --------------------------------------------------------------------------
# Geometry: meshes built from explicit vertex / face lists
# --------------------------------------------------------------------------

def _newell(pts):
    n = Vector((0.0, 0.0, 0.0))
    for i, p in enumerate(pts):
        q = pts[(i + 1) % len(pts)]
        n.x += (p[1] - q[1]) * (p[2] + q[2])
        n.y += (p[2] - q[2]) * (p[0] + q[0])
        n.z += (p[0] - q[0]) * (p[1] + q[1])
    return n


class MeshBuilder:
    """Accumulates polygons with per-corner UVs, smooth flags and material
    slots.  Vertices are shared only within a `group`, so smooth surfaces
    never average their normals with neighbouring flat faces."""

    def __init__(self):
        self.verts = []
        self.faces = []
        self.uvs = []
        self.smooth = []
        self.mat = []
        self._index = {}

    def vert(self, p, group):
        key = (group, round(p[0], 7), round(p[1], 7), round(p[2], 7))
        i = self._index.get(key)
        if i is None:
            i = len(self.verts)
            self.verts.append((float(p[0]), float(p[1]), float(p[2])))
            self._index[key] = i
        return i

    def face(self, pts, uvs=None, normal=None, smooth=False, mat=0, group=None):
        pts = [tuple(p) for p in pts]
        if normal is not None and _newell(pts).dot(Vector(normal)) < 0.0:
            pts = pts[::-1]
            if uvs is not None:
                uvs = uvs[::-1]
        if uvs is None:
            uvs = planar_uvs(pts)
        if group is None:
            group = "flat"
        self.faces.append([self.vert(p, group) for p in pts])
        self.uvs.append([tuple(uv) for uv in uvs])
        self.smooth.append(bool(smooth))
        self.mat.append(mat)

    def quad(self, p0, p1, p2, p3, normal, mat=0):
        self.face([p0, p1, p2, p3], normal=normal, mat=mat)

    def build(self, name, materials):
        me = bpy.data.meshes.new(name)
        me.from_pydata(self.verts, [], self.faces)
        uvl = me.uv_layers.new(name="UVMap")
        flat = [c for face in self.uvs for uv in face for c in uv]
        assert len(flat) == 2 * len(uvl.data)
        uvl.data.foreach_set("uv", flat)
        me.polygons.foreach_set("use_smooth", self.smooth)
        me.polygons.foreach_set("material_index", self.mat)
        for m in materials:
            me.materials.append(m)
        assert not me.validate(verbose=True), name
        me.update()
        return me


def planar_uvs(pts):
    """Box projection in metres along the dominant axis of the face normal."""
    n = _newell(pts)
    ax = max(range(3), key=lambda k: abs(n[k]))
    u, v = [(1, 2), (0, 2), (0, 1)][ax]
    return [(p[u], p[v]) for p in pts]


def mesh_object(name, builder, materials, location=(0.0, 0.0, 0.0)):
    obj = link(bpy.data.objects.new(name, builder.build(name, materials)))
    obj.location = location
    return obj


def box(b, center, size, rot_z_deg=0.0, mat=0, skip=()):
    """Axis-aligned (then rotated about Z) box with outward normals.
    skip: faces to leave out, from {'-x','+x','-y','+y','-z','+z'}."""
    cx, cy, cz = center
    hx, hy, hz = (s * 0.5 for s in size)
    c, s = math.cos(math.radians(rot_z_deg)), math.sin(math.radians(rot_z_deg))

    def P(x, y, z):
        return (cx + c * x - s * y, cy + s * x + c * y, cz + z)

    def N(x, y, z):
        return (c * x - s * y, s * x + c * y, z)

    faces = {
        '-x': ([(-hx, -hy, -hz), (-hx, hy, -hz), (-hx, hy, hz), (-hx, -hy, hz)], (-1, 0, 0)),
        '+x': ([(hx, -hy, -hz), (hx, hy, -hz), (hx, hy, hz), (hx, -hy, hz)], (1, 0, 0)),
        '-y': ([(-hx, -hy, -hz), (hx, -hy, -hz), (hx, -hy, hz), (-hx, -hy, hz)], (0, -1, 0)),
        '+y': ([(-hx, hy, -hz), (hx, hy, -hz), (hx, hy, hz), (-hx, hy, hz)], (0, 1, 0)),
        '-z': ([(-hx, -hy, -hz), (hx, -hy, -hz), (hx, hy, -hz), (-hx, hy, -hz)], (0, 0, -1)),
        '+z': ([(-hx, -hy, hz), (hx, -hy, hz), (hx, hy, hz), (-hx, hy, hz)], (0, 0, 1)),
    }
    for key in ('-x', '+x', '-y', '+y', '-z', '+z'):
        if key in skip:
            continue
        corners, n = faces[key]
        b.face([P(*p) for p in corners], normal=N(*n), mat=mat, group=("box", center))


def uv_sphere(b, center, radius, segments, rings, mat=0, group="sphere"):
    """Smooth UV sphere, outward normals; poles are triangle fans."""
    cx, cy, cz = center

    def P(i, j):  # i: around (0..segments), j: from the south pole (0..rings)
        th = 2.0 * math.pi * (i % segments) / segments
        ph = math.pi * j / rings - 0.5 * math.pi
        return (cx + radius * math.cos(ph) * math.cos(th),
                cy + radius * math.cos(ph) * math.sin(th),
                cz + radius * math.sin(ph))

    for j in range(rings):
        for i in range(segments):
            u0, u1 = i / segments, (i + 1) / segments
            v0, v1 = j / rings, (j + 1) / rings
            if j == 0:
                pts = [P(i, 0), P(i + 1, 1), P(i, 1)]
                uvs = [((u0 + u1) * 0.5, v0), (u1, v1), (u0, v1)]
            elif j == rings - 1:
                pts = [P(i, j), P(i + 1, j), P(i, rings)]
                uvs = [(u0, v0), (u1, v0), ((u0 + u1) * 0.5, v1)]
            else:
                pts = [P(i, j), P(i + 1, j), P(i + 1, j + 1), P(i, j + 1)]
                uvs = [(u0, v0), (u1, v0), (u1, v1), (u0, v1)]
            mid = Vector((0.0, 0.0, 0.0))
            for p in pts:
                mid += Vector(p)
            mid = mid / len(pts) - Vector(center)
            b.face(pts, uvs=uvs, normal=mid, smooth=True, mat=mat, group=group)


def slab_with_holes(b, to_world, u_range, v_range, w_range, holes, mat=0,
                    skip=(), group=None):
    """A solid slab [u0,u1]x[v0,v1]x[w0,w1] in a local frame, with rectangular
    holes (u0,u1,v0,v1) cut through it along w.  to_world maps local (u,v,w)
    to world coordinates and must be a rigid axis permutation/flip.
    skip: outer sides to leave out (they abut other geometry), from
    {'-u','+u','-v','+v'}.  Faces are flat, UVs planar in metres."""
    us = sorted({u_range[0], u_range[1]} | {h[0] for h in holes} | {h[1] for h in holes})
    vs = sorted({v_range[0], v_range[1]} | {h[2] for h in holes} | {h[3] for h in holes})
    w0, w1 = w_range

    def solid(i, j):
        if i < 0 or j < 0 or i >= len(us) - 1 or j >= len(vs) - 1:
            return False
        uc, vc = 0.5 * (us[i] + us[i + 1]), 0.5 * (vs[j] + vs[j + 1])
        return not any(h[0] < uc < h[1] and h[2] < vc < h[3] for h in holes)

    def W(u, v, w):
        return to_world(u, v, w)

    def normal(nu, nv, nw):
        o = Vector(to_world(0.0, 0.0, 0.0))
        return Vector(to_world(nu, nv, nw)) - o

    g = group or ("slab", id(holes))
    for i in range(len(us) - 1):
        for j in range(len(vs) - 1):
            if not solid(i, j):
                continue
            ua, ub, va, vb = us[i], us[i + 1], vs[j], vs[j + 1]
            for w, nw in ((w0, -1.0), (w1, 1.0)):
                b.face([W(ua, va, w), W(ub, va, w), W(ub, vb, w), W(ua, vb, w)],
                       normal=normal(0, 0, nw), mat=mat, group=g)
            # Sides facing an empty neighbour (a hole or the outside).
            sides = (
                (i - 1, j, '-u', [(ua, va), (ua, vb)], (-1, 0)),
                (i + 1, j, '+u', [(ub, va), (ub, vb)], (1, 0)),
                (i, j - 1, '-v', [(ua, va), (ub, va)], (0, -1)),
                (i, j + 1, '+v', [(ua, vb), (ub, vb)], (0, 1)),
            )
            for ni, nj, tag, edge, (nu, nv) in sides:
                if solid(ni, nj):
                    continue
                outer = ni < 0 or nj < 0 or ni >= len(us) - 1 or nj >= len(vs) - 1
                if outer and tag in skip:
                    continue
                (pa, qa), (pb, qb) = edge
                b.face([W(pa, qa, w0), W(pb, qb, w0), W(pb, qb, w1), W(pa, qa, w1)],
                       normal=normal(nu, nv, 0), mat=mat, group=g)


def triangle_count(obj):
    """Triangles of the evaluated mesh (modifiers applied), as exported."""
    dg = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(dg)
    me = ev.to_mesh()
    me.calc_loop_triangles()
    n = len(me.loop_triangles)
    ev.to_mesh_clear()
    return n


def scene_triangles():
    return sum(triangle_count(o) for o in bpy.context.scene.objects if o.type == 'MESH')


# --------------------------------------------------------------------------
# Scenes
# --------------------------------------------------------------------------

# Cornell box colours: the usual linear-RGB approximations of the measured
# spectral reflectances of the original box.
CORNELL_WHITE = (0.73, 0.73, 0.73)
CORNELL_RED = (0.63, 0.065, 0.05)
CORNELL_GREEN = (0.14, 0.45, 0.091)
CORNELL_LIGHT_W = 150.0


def cornell_walls():
    """The 2 m box: x in [-1,1] (left red, right green), y in [-1,1] (open at
    y = -1, facing the camera), z in [0,2].  Single-sided walls facing in."""
    white = diffuse("CornellWhite", CORNELL_WHITE)
    red = diffuse("CornellRed", CORNELL_RED)
    green = diffuse("CornellGreen", CORNELL_GREEN)
    walls = [
        ("Floor", white, [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], (0, 0, 1)),
        ("Ceiling", white, [(-1, -1, 2), (1, -1, 2), (1, 1, 2), (-1, 1, 2)], (0, 0, -1)),
        ("BackWall", white, [(-1, 1, 0), (1, 1, 0), (1, 1, 2), (-1, 1, 2)], (0, -1, 0)),
        ("LeftWall", red, [(-1, -1, 0), (-1, 1, 0), (-1, 1, 2), (-1, -1, 2)], (1, 0, 0)),
        ("RightWall", green, [(1, -1, 0), (1, 1, 0), (1, 1, 2), (1, -1, 2)], (-1, 0, 0)),
    ]
    for name, mat, pts, n in walls:
        b = MeshBuilder()
        b.face(pts, normal=n)
        mesh_object(name, b, [mat])
    return white


def cornell_light_and_camera():
    # 25 cm under the ceiling, centred: 150 W -> 11.9 W/sr.
    add_point_light("CeilingLight", (0.0, 0.0, 1.75), CORNELL_LIGHT_W)
    # 50 mm on a 36 mm sensor (39.6 degrees), square image: the box opening
    # just fills the frame, as in the classic set-up.
    add_camera((0.0, -3.9, 1.0), (0.0, 0.0, 1.0), 50.0)


@scene
def cornell_box():
    reset_scene(512, 512)
    white = cornell_walls()
    short = MeshBuilder()
    box(short, (0.33, -0.3, 0.3), (0.6, 0.6, 0.6), rot_z_deg=-17.0, skip=('-z',))
    mesh_object("ShortBlock", short, [white])
    tall = MeshBuilder()
    box(tall, (-0.33, 0.3, 0.6), (0.6, 0.6, 1.2), rot_z_deg=17.0, skip=('-z',))
    mesh_object("TallBlock", tall, [white])
    cornell_light_and_camera()


@scene
def cornell_caustics():
    """The same box with Jensen's two spheres instead of the blocks."""
    reset_scene(512, 512)
    cornell_walls()
    mirror = principled("Mirror", base=(0.95, 0.95, 0.95), metallic=1.0, roughness=0.0,
                        specular=0.5)
    glass = principled("Glass", base=(1.0, 1.0, 1.0), metallic=0.0, roughness=0.0,
                       specular=0.5, transmission=1.0, ior=1.5)
    r = 0.4
    b = MeshBuilder()
    uv_sphere(b, (0.0, 0.0, 0.0), r, 64, 32)
    mesh_object("MirrorSphere", b, [mirror], location=(-0.45, 0.35, r))
    b = MeshBuilder()
    uv_sphere(b, (0.0, 0.0, 0.0), r, 64, 32)
    mesh_object("GlassSphere", b, [glass], location=(0.45, -0.3, r))
    cornell_light_and_camera()


RING_R = 0.5        # inner radius (m)
RING_T = 0.01       # wall thickness (m)
RING_H = 0.2        # height (m)
RING_SEG = 512
RING_LIGHT_W = 1000.0


@scene
def ring():
    """A polished metal ring on a diffuse plane.  Light from a low point
    light reflects off the ring's inner wall and focuses into the cardioid /
    nephroid caustic of a coffee cup.  The light is placed so that the ray
    grazing the near rim lands near the foot of the far wall (slope about
    H / 2R): the whole inner wall facing the light is lit and its reflection
    falls on the plane inside the ring."""
    reset_scene(960, 540)
    ground_mat = diffuse("GroundWhite", (0.8, 0.8, 0.8))
    metal = principled("PolishedSilver", base=(0.97, 0.96, 0.91), metallic=1.0,
                       roughness=0.0, specular=0.5)
    g = MeshBuilder()
    g.face([(-2, -2, 0), (2, -2, 0), (2, 2, 0), (-2, 2, 0)], normal=(0, 0, 1))
    mesh_object("Ground", g, [ground_mat])

    b = MeshBuilder()
    r0, r1, h = RING_R, RING_R + RING_T, RING_H

    def C(r, i, z):
        th = 2.0 * math.pi * (i % RING_SEG) / RING_SEG
        return (r * math.cos(th), r * math.sin(th), z)

    for i in range(RING_SEG):
        u0, u1 = i / RING_SEG, (i + 1) / RING_SEG
        th = 2.0 * math.pi * (i + 0.5) / RING_SEG
        radial = (math.cos(th), math.sin(th), 0.0)
        inward = (-radial[0], -radial[1], 0.0)
        # Inner wall (the mirror that makes the caustic), normals inward.
        b.face([C(r0, i, 0), C(r0, i + 1, 0), C(r0, i + 1, h), C(r0, i, h)],
               uvs=[(u0, 0), (u1, 0), (u1, 1), (u0, 1)], normal=inward,
               smooth=True, group="inner")
        # Outer wall, normals outward.
        b.face([C(r1, i, 0), C(r1, i + 1, 0), C(r1, i + 1, h), C(r1, i, h)],
               uvs=[(u0, 0), (u1, 0), (u1, 1), (u0, 1)], normal=radial,
               smooth=True, group="outer")
        # Top and bottom rims, flat.
        b.face([C(r0, i, h), C(r1, i, h), C(r1, i + 1, h), C(r0, i + 1, h)],
               normal=(0, 0, 1), group="top")
        b.face([C(r0, i, 0), C(r1, i, 0), C(r1, i + 1, 0), C(r0, i + 1, 0)],
               normal=(0, 0, -1), group="bottom")
    mesh_object("Ring", b, [metal])

    # Light 3 m from the centre, slope to the near rim (h - H) / (3 - R) = 0.18.
    add_point_light("RingLight", (-3.0, 0.0, RING_H + 0.18 * (3.0 - RING_R)), RING_LIGHT_W)
    add_camera((0.6, -2.5, 2.1), (0.05, 0.0, 0.0), 50.0)


def png_bytes(width, height, rgb_rows):
    """A deterministic 8-bit RGB PNG (no timestamps, fixed zlib level)."""
    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data
                + struct.pack(">I", zlib.crc32(tag + data) & 0xffffffff))
    raw = b"".join(b"\x00" + bytes(row) for row in rgb_rows)
    return (b"\x89PNG\r\n\x1a\n"
            + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9))
            + chunk(b"IEND", b""))


def checker_rows(size=256, checks=8):
    """sRGB-encoded checker with a thin grout line: light tiles of linear
    albedo ~0.70, dark tiles ~0.20, grout ~0.05."""
    def srgb8(lin):
        s = 12.92 * lin if lin <= 0.0031308 else 1.055 * lin ** (1.0 / 2.4) - 0.055
        return int(round(255.0 * s))
    light = (srgb8(0.70), srgb8(0.68), srgb8(0.64))
    dark = (srgb8(0.20), srgb8(0.16), srgb8(0.12))
    grout = (srgb8(0.05),) * 3
    cell = size // checks
    rows = []
    for y in range(size):
        row = []
        for x in range(size):
            if x % cell == 0 or y % cell == 0:
                c = grout
            elif ((x // cell) + (y // cell)) % 2 == 0:
                c = light
            else:
                c = dark
            row.extend(c)
        rows.append(row)
    return rows


SPOT_W = 400.0


@scene
def spot_room():
    """A closed 6 x 5 x 3 m room lit only by a spot light; the floor is a
    checker texture generated here, 0.25 m per tile (UV = position / 2 m)."""
    reset_scene(1280, 720)
    tmpdir = tempfile.mkdtemp(prefix="pb_samples_")
    png_path = os.path.join(tmpdir, "floor_checker.png")
    with open(png_path, "wb") as f:
        f.write(png_bytes(256, 256, checker_rows()))
    img = bpy.data.images.load(png_path)
    img.name = "floor_checker"
    img.colorspace_settings.name = 'sRGB'

    floor_mat = diffuse("CheckerFloor", (1.0, 1.0, 1.0))
    nodes = floor_mat.node_tree.nodes
    tex = nodes.new("ShaderNodeTexImage")
    tex.name = "FloorTexture"
    tex.image = img
    tex.interpolation = 'Linear'
    tex.extension = 'REPEAT'
    uvmap = nodes.new("ShaderNodeUVMap")
    uvmap.uv_map = "UVMap"
    floor_mat.node_tree.links.new(uvmap.outputs["UV"], tex.inputs["Vector"])
    floor_mat.node_tree.links.new(tex.outputs["Color"],
                                  nodes["Principled BSDF"].inputs["Base Color"])

    wall_mat = diffuse("WallPlaster", (0.7, 0.7, 0.68))
    ceil_mat = diffuse("CeilingWhite", (0.8, 0.8, 0.8))
    crate_mat = diffuse("CrateWood", (0.45, 0.3, 0.16))
    ball_mat = diffuse("BallOrange", (0.8, 0.3, 0.05))

    x0, x1, y0, y1, h = -3.0, 3.0, -2.5, 2.5, 3.0
    f = MeshBuilder()
    corners = [(x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0)]
    f.face(corners, uvs=[(p[0] / 2.0, p[1] / 2.0) for p in corners], normal=(0, 0, 1))
    mesh_object("Floor", f, [floor_mat])
    c = MeshBuilder()
    c.face([(x0, y0, h), (x1, y0, h), (x1, y1, h), (x0, y1, h)], normal=(0, 0, -1))
    mesh_object("Ceiling", c, [ceil_mat])
    w = MeshBuilder()
    w.face([(x0, y0, 0), (x1, y0, 0), (x1, y0, h), (x0, y0, h)], normal=(0, 1, 0))
    w.face([(x0, y1, 0), (x1, y1, 0), (x1, y1, h), (x0, y1, h)], normal=(0, -1, 0))
    w.face([(x0, y0, 0), (x0, y1, 0), (x0, y1, h), (x0, y0, h)], normal=(1, 0, 0))
    w.face([(x1, y0, 0), (x1, y1, 0), (x1, y1, h), (x1, y0, h)], normal=(-1, 0, 0))
    mesh_object("Walls", w, [wall_mat])

    crate = MeshBuilder()
    box(crate, (0.0, 0.0, 0.0), (0.7, 0.7, 0.7), rot_z_deg=25.0, skip=('-z',))
    mesh_object("Crate", crate, [crate_mat], location=(0.3, 0.6, 0.35))
    ball = MeshBuilder()
    uv_sphere(ball, (0.0, 0.0, 0.0), 0.3, 48, 24)
    mesh_object("Ball", ball, [ball_mat], location=(-0.9, -0.4, 0.3))

    # In a ceiling corner, aimed at the floor between the crate and the ball.
    add_spot_light("SpotLight", (-2.4, -1.9, 2.8), (0.0, 0.2, 0.0), SPOT_W,
                   spot_size_deg=50.0, spot_blend=0.2)
    add_camera((2.7, -2.2, 1.6), (-0.6, 0.6, 0.5), 24.0)
    return [tmpdir]


SUN_W_M2 = 4.0
ATRIUM_COL_SEG = 192
ATRIUM_COL_RINGS = 32


def fluted_column(b, height, radius, flutes, segments, rings, mat=0):
    """A column on a square plinth with a square abacus.  The shaft has
    `flutes` smooth flutes (radius modulated by 3 %) and entasis (tapering
    by 12 % towards the top), smooth shaded, segments x rings quads."""
    plinth_h, abacus_h = 0.3, 0.3
    side = 2.7 * radius
    box(b, (0.0, 0.0, plinth_h * 0.5), (side, side, plinth_h), skip=('-z',))
    box(b, (0.0, 0.0, height - abacus_h * 0.5), (side, side, abacus_h), skip=('+z',))
    z0, z1 = plinth_h, height - abacus_h

    def P(i, j):
        th = 2.0 * math.pi * (i % segments) / segments
        t = j / rings
        r = radius * (1.0 - 0.12 * t * t) * (1.0 - 0.03 * 0.5 * (1.0 - math.cos(flutes * th)))
        return (r * math.cos(th), r * math.sin(th), z0 + (z1 - z0) * t)

    for j in range(rings):
        for i in range(segments):
            th = 2.0 * math.pi * (i + 0.5) / segments
            u0, u1 = i / segments, (i + 1) / segments
            v0, v1 = j / rings, (j + 1) / rings
            b.face([P(i, j), P(i + 1, j), P(i + 1, j + 1), P(i, j + 1)],
                   uvs=[(u0, v0), (u1, v0), (u1, v1), (u0, v1)],
                   normal=(math.cos(th), math.sin(th), 0.0), smooth=True, mat=mat,
                   group="shaft")


@scene
def sun_atrium():
    """A 24 x 16 x 10 m stone hall: a roof with three skylights, a south wall
    (Blender -Y) with six tall windows, two rows of five fluted columns, lit
    only by a sun from the south-south-east at 60 degrees elevation."""
    reset_scene(1280, 720)
    floor_mat = diffuse("FloorStone", (0.45, 0.42, 0.38))
    wall_mat = diffuse("WallStone", (0.65, 0.62, 0.56))
    col_mat = diffuse("ColumnMarble", (0.8, 0.78, 0.74))

    X, Y, H, T, RT = 12.0, 8.0, 10.0, 0.4, 0.5   # half sizes, height, wall / roof thickness

    f = MeshBuilder()
    f.face([(-X, -Y, 0), (X, -Y, 0), (X, Y, 0), (-X, Y, 0)], normal=(0, 0, 1))
    mesh_object("Floor", f, [floor_mat])

    walls = MeshBuilder()
    windows = [(cx - 0.8, cx + 0.8, 1.5, 6.5) for cx in (-10.0, -6.0, -2.0, 2.0, 6.0, 10.0)]
    # South wall: u = x, v = z, w = y (outer face at y = -Y - T).
    slab_with_holes(walls, lambda u, v, w: (u, w, v), (-X - T, X + T), (0.0, H),
                    (-Y - T, -Y), windows, skip=('-v', '+v'), group="south")
    # North wall, with a row of small clerestory windows.
    clerestory = [(cx - 1.0, cx + 1.0, 7.5, 9.0) for cx in (-8.0, -4.0, 0.0, 4.0, 8.0)]
    slab_with_holes(walls, lambda u, v, w: (u, w, v), (-X - T, X + T), (0.0, H),
                    (Y, Y + T), clerestory, skip=('-v', '+v'), group="north")
    # West and east walls between them: u = y, v = z, w = x.
    for name, wr in (("west", (-X - T, -X)), ("east", (X, X + T))):
        slab_with_holes(walls, lambda u, v, w: (w, u, v), (-Y, Y), (0.0, H), wr, [],
                        skip=('-u', '+u', '-v', '+v'), group=name)
    mesh_object("Walls", walls, [wall_mat])

    roof = MeshBuilder()
    skylights = [(cx - 2.0, cx + 2.0, -2.0, 2.0) for cx in (-8.0, 0.0, 8.0)]
    slab_with_holes(roof, lambda u, v, w: (u, v, w), (-X - T, X + T), (-Y - T, Y + T),
                    (H, H + RT), skylights, group="roof")
    mesh_object("Roof", roof, [wall_mat])

    # One column mesh repeated by two Array modifiers (5 along x, 2 along y);
    # the exporter applies them, so every triangle is in the file.
    col = MeshBuilder()
    fluted_column(col, H, 0.45, 24, ATRIUM_COL_SEG, ATRIUM_COL_RINGS)
    cols = mesh_object("Columns", col, [col_mat], location=(-8.0, -4.0, 0.0))
    ax = cols.modifiers.new("ArrayX", 'ARRAY')
    ax.count = 5
    ax.use_relative_offset = False
    ax.use_constant_offset = True
    ax.constant_offset_displace = (4.0, 0.0, 0.0)
    ay = cols.modifiers.new("ArrayY", 'ARRAY')
    ay.count = 2
    ay.use_relative_offset = False
    ay.use_constant_offset = True
    ay.constant_offset_displace = (0.0, 8.0, 0.0)

    # Travelling north (+Y), a little west and down at 60 degrees elevation:
    # through the skylights it falls on the north row of columns, through the
    # south windows on the floor in front of the south row.
    add_sun("Sun", (-0.15, 0.4770, -0.8660), SUN_W_M2)
    add_camera((11.2, -1.5, 1.7), (-6.0, 1.0, 4.0), 20.0)
    tris = scene_triangles()
    assert tris >= 100_000, "sun_atrium has %d triangles, needs >= 100k" % tris


# --------------------------------------------------------------------------
# Animated variants: the same scenes with one object keyframed (node TRS only)
# --------------------------------------------------------------------------

# 2 s at 24 fps: 49 frames, keys on Blender frames ANIM_FIRST..ANIM_LAST.  The
# 3.4 exporter writes a key at Blender frame f as time f / fps (no offset to
# the start of the range), so the range starts at frame 0 to make the file's
# times run from 0 to 2 s.  Without export_current_frame the exporter also
# sets frame 0 before it writes the static node TRS, so the static pose in the
# file is the first key's pose.
ANIM_FPS = 24
ANIM_FIRST = 0
ANIM_LAST = 48
ANIMATED = {}  # scene name -> (animated object = glTF node name, animation name)


def animated(target, anim_name):
    def register(fn):
        ANIMATED[fn.__name__] = (target, anim_name)
        return scene(fn)
    return register


def set_animation_range():
    sc = bpy.context.scene
    sc.render.fps = ANIM_FPS
    sc.render.fps_base = 1.0
    sc.frame_start = ANIM_FIRST
    sc.frame_end = ANIM_LAST
    sc.frame_set(ANIM_FIRST)


def keyframe(obj, action_name, keys, interpolation):
    """keys: [(frame, {data_path: value})].  interpolation: 'LINEAR' or
    'BEZIER' (Blender's auto-clamped handles).  Extrapolation stays constant,
    so frames outside the keys hold the first / last pose."""
    ad = obj.animation_data_create()
    ad.action = bpy.data.actions.new(action_name)
    for frame, values in keys:
        for path, value in values.items():
            setattr(obj, path, value)
            obj.keyframe_insert(path, frame=frame)
    for fc in ad.action.fcurves:
        for kp in fc.keyframe_points:
            kp.interpolation = interpolation
            if interpolation == 'BEZIER':
                kp.handle_left_type = 'AUTO_CLAMPED'
                kp.handle_right_type = 'AUTO_CLAMPED'
        fc.extrapolation = 'CONSTANT'
        fc.update()
    bpy.context.scene.frame_set(ANIM_FIRST)


@animated("CeilingLight", "LightAcrossCeiling")
def cornell_box_moving_light():
    """cornell_box with CeilingLight moving left to right under the ceiling,
    x -0.6 -> 0.6 m at z = 1.75 m (two linear keys); everything else still."""
    cornell_box()
    set_animation_range()
    light = bpy.data.objects["CeilingLight"]
    keyframe(light, "LightAcrossCeiling",
             [(ANIM_FIRST, {"location": (-0.6, 0.0, 1.75)}),
              (ANIM_LAST, {"location": (0.6, 0.0, 1.75)})], 'LINEAR')


@animated("GlassSphere", "GlassSphereAcrossFloor")
def cornell_caustics_moving_sphere():
    """cornell_caustics with GlassSphere sliding across the floor from its
    place front right (0.45, -0.3) to front left (-0.4, -0.55), resting on the
    floor (z = r) all the way; two linear translation keys.  The path stays
    at least 0.87 m (centre to centre) from MirrorSphere, 5 cm inside the
    left wall and the box opening."""
    cornell_caustics()
    set_animation_range()
    sphere = bpy.data.objects["GlassSphere"]
    z = sphere.location.z
    keyframe(sphere, "GlassSphereAcrossFloor",
             [(ANIM_FIRST, {"location": (0.45, -0.3, z)}),
              (ANIM_LAST, {"location": (-0.4, -0.55, z)})], 'LINEAR')


ATRIUM_FLIGHT = [  # (frame, camera position, point looked at), Blender coordinates
    (0, (11.2, -1.5, 1.7), (-6.0, 1.0, 4.0)),     # sun_atrium's camera
    (12, (6.0, -0.8, 2.4), (-8.0, 1.5, 4.5)),
    (24, (0.0, 0.0, 3.2), (-8.0, -1.0, 6.0)),
    (36, (-5.0, 0.8, 3.0), (-10.0, 3.5, 4.0)),
    (48, (-9.0, 0.5, 2.5), (-2.0, 5.0, 4.0)),     # turned to the sunlit north row
]


@animated("Camera", "CameraFlythrough")
def sun_atrium_flythrough():
    """sun_atrium with the camera flying west along the nave (between the
    column rows, 1.7 - 3.2 m high), turning right at the end to look back
    east along the north row of columns, lit through the skylights: five
    location + rotation keys with Bezier (auto-clamped) interpolation.
    Rotation is Euler XYZ (pitch about X, heading about Z, no roll), so the
    camera never rolls between keys.  The turn stays well under 180 degrees
    from the first orientation: the exporter decomposes each sampled rotation
    from its frame's matrix on its own and does not keep consecutive
    quaternions in one hemisphere; a first path turning further got a sign
    flip between two rotation keys (describe_animation now fails on one)."""
    sun_atrium()
    set_animation_range()
    cam = bpy.context.scene.camera
    cam.rotation_mode = 'XYZ'
    keys, prev = [], None
    for frame, pos, target in ATRIUM_FLIGHT:
        q = (Vector(target) - Vector(pos)).to_track_quat('-Z', 'Y')
        e = q.to_euler('XYZ', prev) if prev is not None else q.to_euler('XYZ')
        keys.append((frame, {"location": pos, "rotation_euler": e}))
        prev = e
    assert keys[0][0] == ANIM_FIRST and keys[-1][0] == ANIM_LAST
    keyframe(cam, "CameraFlythrough", keys, 'BEZIER')


# --------------------------------------------------------------------------
# Export
# --------------------------------------------------------------------------

def gltf_export(path, animation=None):
    """animation: None (static scenes: no animations) or the name of the one
    glTF animation to write: every active action, sampled at every frame of
    the playback range into LINEAR keys (export_force_sampling; all 49 kept,
    export_optimize_animation_size off), merged into one animation
    (export_nla_strips off), static TRS = the pose at frame 0."""
    props = bpy.ops.export_scene.gltf.get_rna_type().properties.keys()
    opts = dict(
        filepath=path,
        export_format='GLTF_SEPARATE',
        export_texture_dir="",
        export_keep_originals=False,
        export_image_format='AUTO',
        export_yup=True,
        export_apply=True,
        export_texcoords=True,
        export_normals=True,
        export_tangents=False,
        export_colors=False,
        export_materials='EXPORT',
        export_cameras=True,
        export_lights=True,
        export_extras=False,
        export_animations=False,
        export_skins=False,
        export_morph=False,
        use_selection=False,
        use_visible=False,
        use_renderable=False,
        use_active_collection=False,
        export_draco_mesh_compression_enable=False,
    )
    if animation is not None:
        opts.update(
            export_animations=True,
            export_frame_range=True,
            export_frame_step=1,
            export_force_sampling=True,
            export_nla_strips=False,
            export_nla_strips_merged_animation_name=animation,
            export_optimize_animation_size=False,
            export_current_frame=False,
            export_def_bones=False,
        )
    # "Standard" (physical) lighting units; the option was renamed in 3.6.
    for key in ("export_import_convert_lighting_mode", "convert_lighting_mode"):
        if key in props:
            opts[key] = 'SPEC'
            break
    else:
        print("make_samples: this exporter has no lighting-mode option (pre-3.4?)")
    opts = {k: v for k, v in opts.items() if k in props or k == "filepath"}
    result = bpy.ops.export_scene.gltf(**opts)
    if result != {'FINISHED'}:
        raise RuntimeError("glTF export of %s failed: %s" % (path, result))


def gltf_triangles(path):
    """Triangles actually in the exported file (mode 4 primitives)."""
    with open(path) as f:
        doc = json.load(f)
    n = 0
    for mesh in doc.get("meshes", []):
        for prim in mesh["primitives"]:
            if prim.get("mode", 4) != 4:
                continue
            if "indices" in prim:
                n += doc["accessors"][prim["indices"]]["count"] // 3
            else:
                n += doc["accessors"][prim["attributes"]["POSITION"]]["count"] // 3
    return n, doc


def read_floats(doc, folder, accessor):
    """The float components of a tightly packed accessor of the written file."""
    acc = doc["accessors"][accessor]
    view = doc["bufferViews"][acc["bufferView"]]
    n = acc["count"] * {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[acc["type"]]
    with open(os.path.join(folder, doc["buffers"][view["buffer"]]["uri"]), "rb") as f:
        f.seek(view.get("byteOffset", 0) + acc.get("byteOffset", 0))
        return struct.unpack("<%df" % n, f.read(4 * n))


def describe_animation(name, doc, target):
    """Print the exported animation and check that it moves `target` over
    0 .. 2 s (49 keys)."""
    anims = doc.get("animations", [])
    assert anims, "%s: no animations exported" % name
    nodes = doc["nodes"]
    for a in anims:
        for ch in a["channels"]:
            s = a["samplers"][ch["sampler"]]
            acc = doc["accessors"][s["input"]]
            node = nodes[ch["target"]["node"]].get("name")
            print("make_samples: %s:   animation %s: %s.%s %s, %d keys, %.6g .. %.6g s" % (
                name, a.get("name"), node, ch["target"]["path"],
                s.get("interpolation", "LINEAR"), acc["count"], acc["min"][0], acc["max"][0]))
            assert node == target, (name, node, target)
            assert acc["count"] == ANIM_LAST - ANIM_FIRST + 1, (name, acc["count"])
            if ch["target"]["path"] == "rotation":
                q = read_floats(doc, os.path.dirname(doc["_path"]), s["output"])
                q = [q[i:i + 4] for i in range(0, len(q), 4)]
                flips = sum(1 for a_, b_ in zip(q, q[1:])
                            if sum(x * y for x, y in zip(a_, b_)) < 0.0)
                assert not flips, "%s: %d quaternion sign flips" % (name, flips)


def save_blend(path):
    """The scene as a .blend beside its glTF, images packed (the texture
    files live in a temporary folder), so that it renders from Blender with
    any engine, photonbridge's included, and the render engine's own glTF
    writer can be compared with Blender's exporter on the same scene."""
    if bpy.data.images:
        bpy.ops.file.pack_all()
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True, check_existing=False)


def export_scene(name, out_root):
    outdir = os.path.join(out_root, name)
    os.makedirs(outdir, exist_ok=True)
    # Remove what an earlier run wrote, so a renamed texture leaves nothing stale.
    for fn in sorted(os.listdir(outdir)):
        if fn.endswith((".gltf", ".bin", ".png", ".jpg", ".blend", ".blend1")):
            os.remove(os.path.join(outdir, fn))
    tmpdirs = SCENES[name]() or []
    path = os.path.join(outdir, name + ".gltf")
    anim = ANIMATED.get(name)
    gltf_export(path, anim[1] if anim else None)
    save_blend(os.path.join(outdir, name + ".blend"))
    for d in tmpdirs:
        for fn in os.listdir(d):
            os.remove(os.path.join(d, fn))
        os.rmdir(d)
    tris, doc = gltf_triangles(path)
    if name.startswith("sun_atrium"):
        assert tris >= 100_000, tris
    if anim:
        doc["_path"] = path
        describe_animation(name, doc, anim[0])
    lights = doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", [])
    sizes = {fn: os.path.getsize(os.path.join(outdir, fn)) for fn in sorted(os.listdir(outdir))}
    print("make_samples: %s: %d triangles, files %s" % (name, tris, sizes))
    for light in lights:
        print("make_samples: %s:   light %s %s intensity %.6g%s" % (
            name, light.get("name"), light["type"], light.get("intensity", 1.0),
            (" spot %s" % light["spot"]) if "spot" in light else ""))


def main(argv):
    ap = argparse.ArgumentParser(prog="make_samples.py")
    ap.add_argument("--out", required=True, help="output root; scenes go to OUT/NAME/NAME.gltf")
    ap.add_argument("--only", choices=sorted(SCENES), action="append",
                    help="export only this scene (may be repeated)")
    args = ap.parse_args(argv)
    out = os.path.abspath(args.out)
    names = [n for n in SCENES if not args.only or n in args.only]
    for name in names:
        export_scene(name, out)
    bpy.ops.wm.read_factory_settings(use_empty=True)


if __name__ == "__main__":
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    main(argv)
