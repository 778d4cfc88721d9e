"""Blender side: small scenes for the add-on's tests, saved as .blend into
the folder after '--':
  moving.blend       a floor, a point light and a box that moves +X by 0.5 m
                     per frame over frames 1-3 (LINEAR keys)
  unsupported.blend  a lit box whose material takes its Base Color from a
                     Noise Texture (not translated: a warning)
  nolights.blend     a box and a camera, no light
  zero_area.blend    a floor, a box, a point light and a 0 m disk area
                     light (left out with a warning)
  worldlit.blend     a floor, a box and a camera lit only by a grey world
                     (Background strength 2): not an unlit scene
  empty_mesh.blend   a camera, a light and only a mesh without faces
  nocamera.blend     a box and a light, no camera
  instances.blend    a floor and a collection with one box, instanced three
                     times (collection instances) and once more through
                     geometry nodes' Instance on Points on a 4-vertex mesh
  vcolor.blend       a floor, a light and two boxes whose base colour comes
                     from colour attributes: a Principled BSDF fed by a Color
                     Attribute node (byte colours on corners, (0.8, 0.1, 0.1))
                     and a Diffuse BSDF fed by an Attribute node (float colours
                     on points, (0.1, 0.2, 0.8)); a third box's material has no
                     attribute node (its primitive gets no COLOR_0)
  vcolor_ref.blend   the same with those colours as the sockets' constants
  groups.blend       two boxes whose Principled BSDFs sit inside node groups:
                     one group exposing Base Color and Roughness (set on the
                     group node), one group nesting that group and exposing
                     its colour again, through a reroute
  groups_ref.blend   the same Principled BSDFs with those values, no groups
  mix.blend          three boxes: Mix Shader(Transparent, Principled red,
                     Fac 0.7); Mix Shader(Transparent, Principled green, Fac
                     from a packed image's Alpha); Add Shader(Emission orange
                     x 2, Principled grey)
  mix_ref.blend      the same as single Principled BSDFs: Alpha 0.7, Alpha
                     from the image's Alpha, Emission orange x 2
  mapping.blend      a box with a packed checker image read through UV map ->
                     Mapping (location (0.2, 0.1), Z rotation 30 degrees,
                     scale (3, 2)) -> Image Texture
  mapping_ref.blend  the same box with that mapping applied to its UVs and
                     no Mapping node
  lightnodes.blend   a floor and a box lit by a point light whose node tree's
                     Emission has Strength 2 and Color (1, 0.5, 0.25)
  lightnodes_ref.blend  the same light without nodes, twice the power and
                     that colour
  floattex.blend     two boxes under a point light: one whose Principled
                     Emission Color is a generated float image of (4, 2, 1)
                     (Strength 1), one whose Base Color is an EXR file of
                     (0.5, 0.25, 0.125) on disk next to the .blend
  floattex_ref.blend the same with Emission Color (1, 0.5, 0.25) x Strength 4
                     and that Base Color as constants
  missingtex.blend   a box whose Base Color and a floor whose Roughness come
                     from an image file that is not there (Cycles: magenta)
  missingtex_ref.blend  the box magenta, the floor at magenta's luminance
  sky.blend          a floor and a cube under a Nishita Sky Texture world
                     (Blender 3.4's defaults: sun 15 degrees up, disc on), no lamp
  sky_low.blend      the same, sun 5 degrees up and rotated 1 rad
  sky_nodisc.blend   the same, sun disc off
  sky_thick.blend    the same, altitude 2 km, air 3, dust 4, ozone 2
  cam_dof.blend      an emissive plane's edge far out of focus and one at the
                     focus distance (depth of field: 50 mm, f/0.5, an Empty 1 m
                     along the view as focus object; 128 x 48)
  cam_equirect.blend emissive boxes around an equirectangular camera in a grey
                     world (64 x 32); cam_fisheye.blend the same through a
                     fisheye equisolid (8 mm, 3 rad), cam_fisheye_eqd through
                     a fisheye equidistant (3.5 rad)
  (the cam_* scenes carry Cycles settings for a reference render: 64
  samples, no denoising, CPU)
  negative_light.blend  a floor, a point light, a box and a second point
                     light 'Neg' of -100 W (Blender allows it; left out with
                     a warning)
  plainmat.blend     a box whose material has no nodes (red viewport colour,
                     Metallic 1, Roughness 0.1, Specular 1, alpha 0.5) and a
                     box without a material (Cycles: Diffuse BSDFs of the
                     viewport colour and of 0.8 grey)
  plainmat_ref.blend the same as Diffuse BSDF materials of those colours
  override.blend     a red box, a box without material and the floor under
                     the view layer's Material Override (a green Diffuse BSDF)
  override_ref.blend the same with that material on every object
  mirrored.blend     a camera and a spot light parented to an Empty of scale
                     (-1, 1, 1) (a mirrored rig), a box and a floor
  mirrored_ref.blend the same without the Empty
  sequence.blend     a box whose Base Color is an image sequence of three
                     PNG frames (Start 1, Frames 3, Offset 1: frame 1 shows
                     the second file)
  sequence_ref.blend the same box with the second file as a still image
  outputs.blend      a floor, a box whose material's only Material Output
                     targets EEVEE (blue), the point light and a second one
                     whose node tree has nothing on its Light Output (Cycles
                     3.4: a black box, a dark second light)
  outputs_ref.blend  the box black (a black Diffuse BSDF), the point light
64 x 48 pixels at 100 %."""
import os
import sys

import bpy

# Principled BSDF socket names: Blender 4.0 renamed them (the values mean
# what 3.4's did: the versioning copies them unchanged).
SPECULAR = "Specular" if bpy.app.version < (4, 0, 0) else "Specular IOR Level"
EMISSION = "Emission" if bpy.app.version < (4, 0, 0) else "Emission Color"


def group_socket(tree, in_out, socket_type, name):
    """A node group's input or output socket: tree.interface from 4.0 on,
    tree.inputs/outputs before."""
    if hasattr(tree, "interface"):
        sub = {"NodeSocketFloatFactor": ("NodeSocketFloat", "FACTOR")}.get(socket_type)
        sock = tree.interface.new_socket(name, in_out=in_out, socket_type=sub[0] if sub else socket_type)
        if sub:
            sock.subtype = sub[1]
        return sock
    return (tree.inputs if in_out == 'INPUT' else tree.outputs).new(socket_type, name)

out = sys.argv[sys.argv.index("--") + 1]
os.makedirs(out, exist_ok=True)


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.resolution_x, sc.render.resolution_y, sc.render.resolution_percentage = 64, 48, 100
    sc.frame_start, sc.frame_end = 1, 3
    return sc


def mesh(name, verts, faces, mat=None):
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], faces)
    me.update()
    ob = bpy.data.objects.new(name, me)
    if mat:
        ob.data.materials.append(mat)
    bpy.context.scene.collection.objects.link(ob)
    return ob


def box(name, c, h, mat=None):
    x, y, z = c
    v = [(x + sx * h, y + sy * h, z + sz * h) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    f = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return mesh(name, v, f, mat)


def material(name, rgb):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    b = m.node_tree.nodes["Principled BSDF"]
    b.inputs["Base Color"].default_value = (*rgb, 1)
    b.inputs[SPECULAR].default_value = 0.0
    b.inputs["Roughness"].default_value = 1.0
    return m


def floor():
    return mesh("Floor", [(-4, -4, 0), (4, -4, 0), (4, 4, 0), (-4, 4, 0)], [(0, 1, 2, 3)], material("Grey", (0.6, 0.6, 0.6)))


def light():
    ld = bpy.data.lights.new("Lamp", 'POINT')
    ld.energy = 300.0
    ob = bpy.data.objects.new("Lamp", ld)
    ob.location = (0, 0, 3)
    bpy.context.scene.collection.objects.link(ob)


def camera():
    cd = bpy.data.cameras.new("Cam")
    ob = bpy.data.objects.new("Cam", cd)
    ob.location = (0, -6, 3)
    ob.rotation_euler = (1.1, 0, 0)
    bpy.context.scene.collection.objects.link(ob)
    bpy.context.scene.camera = ob


def save(name):
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, name), check_existing=False)


reset()
floor()
light()
camera()
b = box("Mover", (-0.5, 0, 0.5), 0.5, material("Red", (0.8, 0.1, 0.1)))
for f, x in ((1, -0.5), (3, 0.5)):
    b.location = (x, 0, 0.5)
    b.keyframe_insert("location", frame=f)
for fc in b.animation_data.action.fcurves:
    for k in fc.keyframe_points:
        k.interpolation = 'LINEAR'
save("moving.blend")

reset()
floor()
light()
camera()
m = material("Noisy", (0.8, 0.8, 0.8))
noise = m.node_tree.nodes.new("ShaderNodeTexNoise")
noise.name = "Noise Texture"
m.node_tree.links.new(noise.outputs["Color"], m.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
box("Box", (0, 0, 0.5), 0.5, m)
save("unsupported.blend")

reset()
floor()
camera()
box("Box", (0, 0, 0.5), 0.5)
save("nolights.blend")

reset()
floor()
camera()
box("Box", (0, 0, 0.5), 0.5)
world = bpy.data.worlds.new("Grey")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.5, 0.5, 0.5, 1)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 2.0
bpy.context.scene.world = world
save("worldlit.blend")

reset()
floor()
light()
camera()
box("Box", (0, 0, 0.5), 0.5)
ad = bpy.data.lights.new("Disk", 'AREA')
ad.shape, ad.size, ad.energy = 'DISK', 0.0, 100.0
ob = bpy.data.objects.new("Disk", ad)
ob.location = (1, 0, 2)
bpy.context.scene.collection.objects.link(ob)
save("zero_area.blend")

reset()
light()
camera()
mesh("Edges", [(0, 0, 0), (1, 0, 0), (1, 1, 0)], [])
save("empty_mesh.blend")

reset()
floor()
light()
box("Box", (0, 0, 0.5), 0.5)
save("nocamera.blend")
reset()
floor()
light()
camera()
col = bpy.data.collections.new("Crates")
bpy.context.scene.collection.children.link(col)
crate = box("Crate", (0, 0, 0.25), 0.25, material("Wood", (0.5, 0.3, 0.1)))
bpy.context.scene.collection.objects.unlink(crate)
col.objects.link(crate)
bpy.context.view_layer.layer_collection.children["Crates"].exclude = True
for i, x in enumerate((-2.0, 0.0, 2.0)):
    e = bpy.data.objects.new("CrateInstance%d" % i, None)
    e.instance_type = 'COLLECTION'
    e.instance_collection = col
    e.location = (x, 1.0, 0.0)
    bpy.context.scene.collection.objects.link(e)
pts = mesh("Points", [(-1.5, -1.5, 0), (1.5, -1.5, 0), (-1.5, -2.5, 0), (1.5, -2.5, 0)], [])
gn = pts.modifiers.new("Scatter", 'NODES')
tree = bpy.data.node_groups.new("Scatter", 'GeometryNodeTree')
group_socket(tree, 'INPUT', 'NodeSocketGeometry', "Geometry")
group_socket(tree, 'OUTPUT', 'NodeSocketGeometry', "Geometry")
gin, gout = tree.nodes.new("NodeGroupInput"), tree.nodes.new("NodeGroupOutput")
inst = tree.nodes.new("GeometryNodeInstanceOnPoints")
info = tree.nodes.new("GeometryNodeObjectInfo")
info.inputs[0].default_value = crate
tree.links.new(gin.outputs[0], inst.inputs["Points"])
tree.links.new(info.outputs["Geometry"], inst.inputs["Instance"])
tree.links.new(inst.outputs[0], gout.inputs[0])
gn.node_group = tree
save("instances.blend")


def vcolor_scene(attrs):
    reset()
    floor()
    light()
    camera()
    red, blue = (0.8, 0.1, 0.1), (0.1, 0.2, 0.8)
    m1 = material("PaintedRed", red if not attrs else (0.8, 0.8, 0.8))
    a = box("Painted", (-1.2, 0, 0.5), 0.5, m1)
    m2 = bpy.data.materials.new("PaintedBlue")
    m2.use_nodes = True
    nt = m2.node_tree
    nt.nodes.remove(nt.nodes["Principled BSDF"])
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (*blue, 1) if not attrs else (0.8, 0.8, 0.8, 1)
    nt.links.new(d.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    b = box("Dyed", (1.2, 0, 0.5), 0.5, m2)
    box("Plain", (0, 1.5, 0.5), 0.4, material("Plain", (0.7, 0.7, 0.2)))
    if attrs:
        ca = a.data.color_attributes.new("Paint", 'BYTE_COLOR', 'CORNER')
        for e in ca.data:
            e.color = (*red, 1)
        node = m1.node_tree.nodes.new("ShaderNodeVertexColor")
        node.layer_name = "Paint"
        m1.node_tree.links.new(node.outputs["Color"], m1.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
        cb = b.data.color_attributes.new("Dye", 'FLOAT_COLOR', 'POINT')
        for e in cb.data:
            e.color = (*blue, 1)
        at = nt.nodes.new("ShaderNodeAttribute")
        at.attribute_name = "Dye"
        nt.links.new(at.outputs["Color"], d.inputs["Color"])
    save("vcolor.blend" if attrs else "vcolor_ref.blend")


vcolor_scene(True)
vcolor_scene(False)


def pbr_group():
    g = bpy.data.node_groups.new("PBR", 'ShaderNodeTree')
    group_socket(g, 'INPUT', 'NodeSocketColor', "Color")
    group_socket(g, 'INPUT', 'NodeSocketFloatFactor', "Rough")
    group_socket(g, 'OUTPUT', 'NodeSocketShader', "BSDF")
    gi, go = g.nodes.new("NodeGroupInput"), g.nodes.new("NodeGroupOutput")
    b = g.nodes.new("ShaderNodeBsdfPrincipled")
    b.inputs[SPECULAR].default_value = 0.3
    g.links.new(gi.outputs["Color"], b.inputs["Base Color"])
    g.links.new(gi.outputs["Rough"], b.inputs["Roughness"])
    g.links.new(b.outputs[0], go.inputs["BSDF"])
    return g


def grouped(name, color, rough, nested):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.remove(nt.nodes["Principled BSDF"])
    pbr = bpy.data.node_groups.get("PBR") or pbr_group()
    if nested:
        w = bpy.data.node_groups.new("Wrap", 'ShaderNodeTree')
        group_socket(w, 'INPUT', 'NodeSocketColor', "Tint")
        group_socket(w, 'OUTPUT', 'NodeSocketShader', "Shader")
        wi, wo = w.nodes.new("NodeGroupInput"), w.nodes.new("NodeGroupOutput")
        inner = w.nodes.new("ShaderNodeGroup")
        inner.node_tree = pbr
        inner.inputs["Rough"].default_value = rough
        rr = w.nodes.new("NodeReroute")
        w.links.new(wi.outputs["Tint"], rr.inputs[0])
        w.links.new(rr.outputs[0], inner.inputs["Color"])
        w.links.new(inner.outputs["BSDF"], wo.inputs["Shader"])
        node = nt.nodes.new("ShaderNodeGroup")
        node.node_tree = w
        node.inputs["Tint"].default_value = (*color, 1)
        out = node.outputs["Shader"]
    else:
        node = nt.nodes.new("ShaderNodeGroup")
        node.node_tree = pbr
        node.inputs["Color"].default_value = (*color, 1)
        node.inputs["Rough"].default_value = rough
        out = node.outputs["BSDF"]
    nt.links.new(out, nt.nodes["Material Output"].inputs["Surface"])
    return m


def plain(name, color, rough):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    b = m.node_tree.nodes["Principled BSDF"]
    b.inputs["Base Color"].default_value = (*color, 1)
    b.inputs["Roughness"].default_value = rough
    b.inputs[SPECULAR].default_value = 0.3
    return m


for ref in (False, True):
    reset()
    floor()
    light()
    camera()
    make = plain if ref else (lambda n, c, r, nested: grouped(n, c, r, nested))
    a = (0.1, 0.7, 0.2), 0.35
    b = (0.8, 0.3, 0.1), 0.6
    box("GroupA", (-1.2, 0, 0.5), 0.5, plain("A", *a) if ref else grouped("A", *a, False))
    box("GroupB", (1.2, 0, 0.5), 0.5, plain("B", *b) if ref else grouped("B", *b, True))
    save("groups_ref.blend" if ref else "groups.blend")


def mix_scene(ref):
    reset()
    floor()
    light()
    camera()
    img = bpy.data.images.new("Fade", 16, 16, alpha=True)
    img.pixels = [v for y in range(16) for x in range(16) for v in (1.0, 1.0, 1.0, x / 15.0)]
    img.pack()

    def bsdf(name, rgb):
        m = material(name, rgb)
        return m, m.node_tree, m.node_tree.nodes["Principled BSDF"]

    def around(nt, b, kind, **kw):
        out = nt.nodes["Material Output"]
        if kind == "mix":
            t, mx = nt.nodes.new("ShaderNodeBsdfTransparent"), nt.nodes.new("ShaderNodeMixShader")
            nt.links.new(t.outputs[0], mx.inputs[1])
            nt.links.new(b.outputs[0], mx.inputs[2])
            if "fac_image" in kw:
                tex = nt.nodes.new("ShaderNodeTexImage")
                tex.image = kw["fac_image"]
                nt.links.new(tex.outputs["Alpha"], mx.inputs[0])
            else:
                mx.inputs[0].default_value = kw["fac"]
            nt.links.new(mx.outputs[0], out.inputs["Surface"])
        else:
            e, add = nt.nodes.new("ShaderNodeEmission"), nt.nodes.new("ShaderNodeAddShader")
            e.inputs["Color"].default_value = (1.0, 0.5, 0.1, 1)
            e.inputs["Strength"].default_value = 2.0
            nt.links.new(e.outputs[0], add.inputs[0])
            nt.links.new(b.outputs[0], add.inputs[1])
            nt.links.new(add.outputs[0], out.inputs["Surface"])

    m, nt, b = bsdf("Veil", (0.8, 0.1, 0.1))
    if ref:
        b.inputs["Alpha"].default_value = 0.7
    else:
        around(nt, b, "mix", fac=0.7)
    box("Veil", (-1.2, 0, 0.5), 0.5, m)
    m, nt, b = bsdf("Leaf", (0.1, 0.7, 0.1))
    if ref:
        tex = nt.nodes.new("ShaderNodeTexImage")
        tex.image = img
        nt.links.new(tex.outputs["Alpha"], b.inputs["Alpha"])
    else:
        around(nt, b, "mix", fac_image=img)
    box("Leaf", (1.2, 0, 0.5), 0.5, m)
    m, nt, b = bsdf("Glow", (0.5, 0.5, 0.5))
    if ref:
        b.inputs[EMISSION].default_value = (1.0, 0.5, 0.1, 1)
        b.inputs["Emission Strength"].default_value = 2.0
    else:
        around(nt, b, "add")
    box("Glow", (0, 1.5, 0.4), 0.4, m)
    save("mix_ref.blend" if ref else "mix.blend")


mix_scene(False)
mix_scene(True)


def mapping_scene(ref):
    import math
    reset()
    floor()
    light()
    camera()
    img = bpy.data.images.new("Checker", 8, 8)
    img.pixels = [v for y in range(8) for x in range(8)
                  for v in ((0.9, 0.8, 0.1, 1.0) if (x + y) % 2 else (0.1, 0.2, 0.7, 1.0))]
    img.pack()
    m = material("Tiles", (0.8, 0.8, 0.8))
    nt = m.node_tree
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = img
    tex.interpolation = 'Closest'
    nt.links.new(tex.outputs["Color"], nt.nodes["Principled BSDF"].inputs["Base Color"])
    ob = box("Tiles", (0, 0, 0.8), 0.8, m)
    me = ob.data
    uv = me.uv_layers.new(name="UVMap")
    corners = [(0, 0), (1, 0), (1, 1), (0, 1)]
    th, L, S = math.radians(30), (0.2, 0.1), (3.0, 2.0)
    for poly in me.polygons:
        for k, li in enumerate(poly.loop_indices):
            u, v = corners[k % 4]
            if ref:
                u, v = S[0] * u, S[1] * v
                u, v = math.cos(th) * u - math.sin(th) * v + L[0], math.sin(th) * u + math.cos(th) * v + L[1]
            uv.data[li].uv = (u, v)
    if not ref:
        tc = nt.nodes.new("ShaderNodeTexCoord")
        mp = nt.nodes.new("ShaderNodeMapping")
        mp.inputs["Location"].default_value = (L[0], L[1], 0.0)
        mp.inputs["Rotation"].default_value = (0.0, 0.0, th)
        mp.inputs["Scale"].default_value = (S[0], S[1], 1.0)
        nt.links.new(tc.outputs["UV"], mp.inputs["Vector"])
        nt.links.new(mp.outputs["Vector"], tex.inputs["Vector"])
    save("mapping_ref.blend" if ref else "mapping.blend")


mapping_scene(False)
mapping_scene(True)


def lightnodes_scene(ref):
    reset()
    floor()
    camera()
    box("Box", (0, 0, 0.5), 0.5, material("White", (0.8, 0.8, 0.8)))
    ld = bpy.data.lights.new("Lamp", 'POINT')
    ld.energy = 300.0 * (2.0 if ref else 1.0)
    if ref:
        ld.color = (1.0, 0.5, 0.25)
    else:
        ld.use_nodes = True
        e = ld.node_tree.nodes["Emission"]
        e.inputs["Strength"].default_value = 2.0
        e.inputs["Color"].default_value = (1.0, 0.5, 0.25, 1.0)
    ob = bpy.data.objects.new("Lamp", ld)
    ob.location = (0, 0, 3)
    bpy.context.scene.collection.objects.link(ob)
    save("lightnodes_ref.blend" if ref else "lightnodes.blend")


lightnodes_scene(False)
lightnodes_scene(True)


def sky_scene(name, **params):
    """A floor and a cube under a Nishita Sky Texture world (no lamp)."""
    reset()
    floor()
    camera()
    box("Cube", (0, 0, 0.5), 0.5, material("Cube", (0.8, 0.5, 0.2)))
    w = bpy.data.worlds.new("Sky")
    w.use_nodes = True
    sky = w.node_tree.nodes.new("ShaderNodeTexSky")
    sky.sky_type = 'NISHITA'
    for k, v in params.items():
        setattr(sky, k, v)
    w.node_tree.links.new(sky.outputs["Color"], w.node_tree.nodes["Background"].inputs["Color"])
    bpy.context.scene.world = w
    save(name + ".blend")


sky_scene("sky")  # Blender 3.4's defaults: sun 15 degrees up, disc on
sky_scene("sky_low", sun_elevation=0.0872665, sun_rotation=1.0)
sky_scene("sky_nodisc", sun_disc=False)
sky_scene("sky_thick", altitude=2000.0, air_density=3.0, dust_density=4.0, ozone_density=2.0)


def node_material(name, kind, **inputs):
    """A material whose Surface is one new node of type `kind` with those
    input values (the default Principled BSDF removed)."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.remove(nt.nodes["Principled BSDF"])
    n = nt.nodes.new(kind)
    for k, v in inputs.items():
        n.inputs[k].default_value = v
    nt.links.new(n.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    return m


def emitter(name, rgb, strength=1.0):
    return node_material(name, "ShaderNodeEmission", Color=(*rgb, 1), Strength=strength)


def cycles_settings(sc):
    """What the Cycles reference render of these scenes uses."""
    sc.cycles.samples = 64
    sc.cycles.use_denoising = False
    sc.cycles.device = 'CPU'


def cam_dof_scene():
    """An emissive plane's vertical edge 6 m in front of a camera focused at
    1 m by a focus object off the axis (50 mm, f/0.5: Cycles' aperture
    radius 0.05 m), and a smaller
    emissive plane at the focus distance in the upper part of the picture;
    128 x 48."""
    sc = reset()
    cycles_settings(sc)
    sc.render.resolution_x = 128
    cd = bpy.data.cameras.new("Cam")
    cd.dof.use_dof = True
    cd.dof.aperture_fstop = 0.5
    cd.dof.focus_distance = 3.0  # ignored: the focus object's distance along the view axis is 1 m
    target = bpy.data.objects.new("Focus", None)
    target.location = (0.4, 1.0, 0.3)
    sc.collection.objects.link(target)
    cd.dof.focus_object = target
    ob = bpy.data.objects.new("Cam", cd)
    ob.location = (0, 0, 0)
    ob.rotation_euler = (1.5707963, 0, 0)  # looking along +Y
    sc.collection.objects.link(ob)
    sc.camera = ob
    white = emitter("White", (1, 1, 1))
    mesh("Far", [(-20, 6, -20), (0, 6, -20), (0, 6, 0.0), (-20, 6, 0.0)], [(0, 1, 2, 3)], white)
    mesh("Near", [(-0.5, 1.0, 0.05), (0, 1.0, 0.05), (0, 1.0, 0.5), (-0.5, 1.0, 0.5)], [(0, 1, 2, 3)], white)
    save("cam_dof.blend")


def cam_pano_scene(name, kind, **params):
    """Emissive boxes of four colours around the camera (front, right, back,
    left) and one above, in a grey world, seen by a panoramic camera."""
    sc = reset()
    cycles_settings(sc)
    sc.render.resolution_x, sc.render.resolution_y = 64, 32 if kind == 'EQUIRECTANGULAR' else 48
    cd = bpy.data.cameras.new("Cam")
    cd.type = 'PANO'
    pano = cd if hasattr(cd, "panorama_type") else cd.cycles  # on the camera since 3.3; 4.x has only that
    pano.panorama_type = kind
    for k, v in params.items():
        setattr(pano, k, v)
    ob = bpy.data.objects.new("Cam", cd)
    ob.location = (0, 0, 1)
    ob.rotation_euler = (1.5707963, 0, -1.5707963)  # pointing along +X: the manual's match with the world map
    sc.collection.objects.link(ob)
    sc.camera = ob
    for n, (c, rgb) in enumerate((((4, 0, 1), (1, 0.2, 0.1)), ((0, -4, 1), (0.1, 1, 0.2)), ((-4, 0, 1), (0.2, 0.1, 1)),
                                  ((0, 4, 1), (1, 1, 0.2)), ((1, 1, 4), (1, 1, 1)))):
        box("Box%d" % n, c, 0.8, emitter("E%d" % n, rgb, 2.0))
    w = bpy.data.worlds.new("Grey")
    w.use_nodes = True
    w.node_tree.nodes["Background"].inputs["Color"].default_value = (0.2, 0.2, 0.2, 1)
    sc.world = w
    save(name + ".blend")


cam_dof_scene()
cam_pano_scene("cam_equirect", 'EQUIRECTANGULAR')
cam_pano_scene("cam_fisheye", 'FISHEYE_EQUISOLID', fisheye_lens=8.0, fisheye_fov=3.0)
cam_pano_scene("cam_fisheye_eqd", 'FISHEYE_EQUIDISTANT', fisheye_fov=3.5)
print("bl_scenes: saved into", out)


def floattex_scene(ref):
    reset()
    floor()
    light()
    camera()
    m = material("Glow", (0.0, 0.0, 0.0))
    b = m.node_tree.nodes["Principled BSDF"]
    if ref:
        b.inputs[EMISSION].default_value = (1.0, 0.5, 0.25, 1.0)
        b.inputs["Emission Strength"].default_value = 4.0
    else:
        img = bpy.data.images.new("Glow", 4, 4, float_buffer=True)
        img.pixels = [4.0, 2.0, 1.0, 1.0] * 16
        img.pack()
        t = m.node_tree.nodes.new("ShaderNodeTexImage")
        t.image = img
        m.node_tree.links.new(t.outputs["Color"], b.inputs[EMISSION])
        b.inputs["Emission Strength"].default_value = 1.0
    box("Glow", (-1.2, 0, 0.5), 0.5, m)
    m2 = material("Paint", (0.5, 0.25, 0.125))
    if not ref:
        img = bpy.data.images.new("Paint", 4, 4, float_buffer=True)
        img.pixels = [0.5, 0.25, 0.125, 1.0] * 16
        # Image.save() of a generated float image writes Blender 3.4's
        # display-encoded values into the EXR (0.5 -> 0.7354, the sRGB
        # curve), so Cycles would render this box brighter than its constant
        # too; save_render with an EXR format writes the linear pixels.
        bpy.context.scene.render.image_settings.file_format = 'OPEN_EXR'
        img.save_render(os.path.join(out, "paint.exr"), scene=bpy.context.scene)
        img = bpy.data.images.load(os.path.join(out, "paint.exr"))
        t = m2.node_tree.nodes.new("ShaderNodeTexImage")
        t.image = img
        m2.node_tree.links.new(t.outputs["Color"], m2.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
    box("Paint", (1.2, 0, 0.5), 0.5, m2)
    save("floattex_ref.blend" if ref else "floattex.blend")


floattex_scene(False)
floattex_scene(True)


# missingtex.blend: a box whose Base Color comes from an image file that is
# not there (Cycles renders it magenta, IMAGE_TEXTURE_MISSING_RGBA; Cycles 3.4,
# 64 spp: this scene and missingtex_ref both 0.2454 / 0.1939 / 0.2454), and a
# floor whose Roughness does (a Color output on a scalar input: Cycles takes
# its luminance, linear_rgb_to_gray, 0.2126729 + 0.0721750 for magenta);
# missingtex_ref: the box magenta, the floor at that Roughness, no images.
def missingtex_scene(ref):
    reset()
    light()
    camera()
    fm = material("Grey", (0.6, 0.6, 0.6))
    fm.node_tree.nodes["Principled BSDF"].inputs["Roughness"].default_value = 0.2848479 if ref else 0.6
    mesh("Floor", [(-4, -4, 0), (4, -4, 0), (4, 4, 0), (-4, 4, 0)], [(0, 1, 2, 3)], fm)
    m = material("Gone", (1.0, 0.0, 1.0) if ref else (0.8, 0.8, 0.8))
    if not ref:
        img = bpy.data.images.new("gone.png", 4, 4)
        img.source = 'FILE'
        img.filepath = os.path.join(out, "no_such_folder", "gone.png")
        for mat, inp in ((m, "Base Color"), (fm, "Roughness")):
            t = mat.node_tree.nodes.new("ShaderNodeTexImage")
            t.image = img
            mat.node_tree.links.new(t.outputs["Color"], mat.node_tree.nodes["Principled BSDF"].inputs[inp])
    box("Gone", (0, 0, 0.5), 0.5, m)
    save("missingtex_ref.blend" if ref else "missingtex.blend")


missingtex_scene(False)
missingtex_scene(True)


reset()
floor()
light()
camera()
box("Box", (0, 0, 0.5), 0.5, material("Red", (0.8, 0.1, 0.1)))
ld = bpy.data.lights.new("Neg", 'POINT')
ld.energy = -100.0
ob = bpy.data.objects.new("Neg", ld)
ob.location = (1, 1, 2)
bpy.context.scene.collection.objects.link(ob)
save("negative_light.blend")


def diffuse(name, rgb):
    return node_material(name, "ShaderNodeBsdfDiffuse", Color=(*rgb, 1))


# plainmat: Cycles 3.4 renders a material without nodes as a Diffuse BSDF of
# its viewport colour and an object without material as one of 0.8 grey
# (32 spp: plainmat and plainmat_ref both 0.2358 / 0.2098 / 0.2098).
def plainmat_scene(ref):
    reset()
    floor()
    light()
    camera()
    if ref:
        box("Plain", (-1, 0, 0.5), 0.5, diffuse("Plain", (0.8, 0.2, 0.2)))
        box("NoMaterial", (1, 0, 0.5), 0.5, diffuse("Grey08", (0.8, 0.8, 0.8)))
    else:
        m = bpy.data.materials.new("Plain")
        m.use_nodes = False
        m.diffuse_color = (0.8, 0.2, 0.2, 0.5)
        m.metallic, m.roughness, m.specular_intensity = 1.0, 0.1, 1.0
        box("Plain", (-1, 0, 0.5), 0.5, m)
        box("NoMaterial", (1, 0, 0.5), 0.5)
    save("plainmat_ref.blend" if ref else "plainmat.blend")


plainmat_scene(False)
plainmat_scene(True)


# override: Cycles renders every slot, empty ones too, with the view layer's
# Material Override (a clay render).
def override_scene(ref):
    reset()
    clay = diffuse("Clay", (0.2, 0.8, 0.2))
    fl = floor()
    light()
    camera()
    red = box("Red", (-1, 0, 0.5), 0.5, material("Red", (0.8, 0.1, 0.1)))
    bare = box("Bare", (1, 0, 0.5), 0.5)
    if ref:
        for ob in (fl, red, bare):
            ob.data.materials.clear()
            ob.data.materials.append(clay)
    else:
        bpy.context.view_layer.material_override = clay
    save("override_ref.blend" if ref else "override.blend")


override_scene(False)
override_scene(True)


# mirrored: a camera and a spot light under a parent of scale (-1, 1, 1), as
# in a mirrored rig; both on the mirror plane (x = 0) looking down their own
# -Z, so Cycles sees the unmirrored scene mirrored left to right.
def mirrored_scene(ref):
    reset()
    floor()
    camera()
    box("Box", (0, 0, 0.5), 0.5, material("Red", (0.8, 0.1, 0.1)))
    ld = bpy.data.lights.new("Spot", 'SPOT')
    ld.energy, ld.spot_size = 500.0, 1.2
    spot = bpy.data.objects.new("Spot", ld)
    spot.location = (0, -1, 3)
    spot.rotation_euler = (0.3, 0, 0)
    bpy.context.scene.collection.objects.link(spot)
    if not ref:
        rig = bpy.data.objects.new("Rig", None)
        rig.scale = (-1, 1, 1)
        bpy.context.scene.collection.objects.link(rig)
        for ob in (bpy.context.scene.camera, spot):
            ob.parent = rig
    save("mirrored_ref.blend" if ref else "mirrored.blend")


mirrored_scene(False)
mirrored_scene(True)


# sequence: three PNG frames of different colours; the Image Texture's image
# user (Start 1, Frames 3, Offset 1) shows the second at scene frame 1, as
# Cycles picks it (BKE_image_user_frame_get).
def sequence_scene(ref):
    reset()
    floor()
    light()
    camera()
    sc = bpy.context.scene
    sc.render.image_settings.file_format = 'PNG'
    for i, rgb in enumerate(((0.8, 0.1, 0.1), (0.1, 0.8, 0.1), (0.1, 0.1, 0.8))):
        img = bpy.data.images.new("frame", 4, 4)
        img.pixels = [*rgb, 1.0] * 16
        img.save_render(os.path.join(out, "seq", "frame_%03d.png" % (i + 1)), scene=sc)
        bpy.data.images.remove(img)
    m = material("Seq", (0.8, 0.8, 0.8))
    t = m.node_tree.nodes.new("ShaderNodeTexImage")
    if ref:
        t.image = bpy.data.images.load(os.path.join(out, "seq", "frame_002.png"))
    else:
        t.image = bpy.data.images.load(os.path.join(out, "seq", "frame_001.png"))
        t.image.source = 'SEQUENCE'
        t.image_user.frame_start, t.image_user.frame_duration, t.image_user.frame_offset = 1, 3, 1
    m.node_tree.links.new(t.outputs["Color"], m.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
    box("Seq", (0, 0, 0.5), 0.5, m)
    sc.frame_set(1)
    save("sequence_ref.blend" if ref else "sequence.blend")


sequence_scene(False)
sequence_scene(True)


# outputs: Cycles uses only a Material/Light Output of target All or Cycles,
# and a light's shader is its nodes alone (32 spp: the box black, a light
# with nothing on its Light Output black).
def outputs_scene(ref):
    reset()
    floor()
    light()
    camera()
    if ref:
        box("Box", (0, 0, 0.5), 0.5, diffuse("Black", (0.0, 0.0, 0.0)))
    else:
        m = material("EeveeOnly", (0.2, 0.2, 0.8))
        m.node_tree.nodes["Material Output"].target = 'EEVEE'
        box("Box", (0, 0, 0.5), 0.5, m)
        ld = bpy.data.lights.new("Unlinked", 'POINT')
        ld.energy = 300.0
        ld.use_nodes = True
        for link in list(ld.node_tree.links):
            ld.node_tree.links.remove(link)
        ob = bpy.data.objects.new("Unlinked", ld)
        ob.location = (2, -2, 2)
        bpy.context.scene.collection.objects.link(ob)
    save("outputs_ref.blend" if ref else "outputs.blend")


outputs_scene(False)
outputs_scene(True)
