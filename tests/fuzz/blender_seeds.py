"""Seeds for fuzz_gltf written by Blender's own glTF exporter: small scenes
that use what that exporter writes and the loader reads or will read.

    blender -b --factory-startup --python-exit-code 1 \
        -P tests/fuzz/blender_seeds.py -- OUT_DIR

Each scene is exported twice, as "glTF Embedded" (one .gltf whose buffer is
a data URI; Blender 3.4 puts the images in bufferViews of that buffer, not in
data:image URIs) and as "glTF Binary" (.glb), so every seed is one
self-contained file (fuzz_gltf writes each input alone). The files in
tests/fuzz/seeds/gltf/ were made by this script with Blender 3.4.1; they are
committed because Blender takes seconds per export and the exporter's output
changes between versions (run it again to refresh them).

Scenes (built with bpy only, no randomness, meshes of a few dozen triangles):
  skin_morph    an armature with two bones skinning a subdivided bar (JOINTS_0,
                WEIGHTS_0, inverseBindMatrices), two shape keys (morph
                targets), and Bezier keys on a bone's rotation and the
                object's translation (CUBICSPLINE; the exporter leaves out
                the shape-key action, which make_seeds.py's code-made files
                cover)
  materials     Principled BSDFs with transmission, IOR, specular, clearcoat,
                sheen, emission strength, alpha blend and clip; a volume
                (thickness); an emission shader; image textures (PNG and JPEG)
                through a Mapping node (KHR_texture_transform) and a normal map
  lights        point, spot and sun lights (KHR_lights_punctual), a
                perspective and an orthographic camera, nested transforms
"""
import math
import os
import sys

import numpy

if not hasattr(numpy, "bool"):  # Debian's numpy 1.24 dropped the alias the 3.4 exporter uses
    numpy.bool = bool

import bpy


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.frame_start, sc.frame_end = 1, 12
    sc.render.fps = 24
    return sc


def bar_mesh(name, segments=4):
    """A 0.2 x 0.2 x 2 bar along Z, `segments` rings (for skinning)."""
    verts, faces = [], []
    for i in range(segments + 1):
        z = 2.0 * i / segments
        verts += [(-0.1, -0.1, z), (0.1, -0.1, z), (0.1, 0.1, z), (-0.1, 0.1, z)]
    for i in range(segments):
        a, b = 4 * i, 4 * (i + 1)
        for k in range(4):
            faces.append((a + k, a + (k + 1) % 4, b + (k + 1) % 4, b + k))
    faces += [(3, 2, 1, 0), (b, b + 1, b + 2, b + 3)]
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], faces)
    me.update()
    return me


def skin_morph():
    sc = reset()
    arm_data = bpy.data.armatures.new("Rig")
    arm = bpy.data.objects.new("Rig", arm_data)
    sc.collection.objects.link(arm)
    bpy.context.view_layer.objects.active = arm
    bpy.ops.object.mode_set(mode='EDIT')
    b0 = arm_data.edit_bones.new("root")
    b0.head, b0.tail = (0, 0, 0), (0, 0, 1)
    b1 = arm_data.edit_bones.new("tip")
    b1.head, b1.tail, b1.parent = (0, 0, 1), (0, 0, 2), b0
    bpy.ops.object.mode_set(mode='OBJECT')
    bar = bpy.data.objects.new("Bar", bar_mesh("Bar"))
    sc.collection.objects.link(bar)
    bar.parent = arm
    mod = bar.modifiers.new("Armature", 'ARMATURE')
    mod.object = arm
    g0, g1 = bar.vertex_groups.new(name="root"), bar.vertex_groups.new(name="tip")
    for v in bar.data.vertices:
        t = v.co.z / 2.0
        g0.add([v.index], 1.0 - t, 'REPLACE')
        g1.add([v.index], t, 'REPLACE')
    bar.shape_key_add(name="Basis")
    for name, s in (("Fat", 1.8), ("Thin", 0.4)):
        k = bar.shape_key_add(name=name)
        for d in k.data:
            d.co.x *= s
            d.co.y *= s
    keys = bar.data.shape_keys
    for f, v in ((1, 0.0), (6, 1.0), (12, 0.2)):
        keys.key_blocks["Fat"].value = v
        keys.key_blocks["Fat"].keyframe_insert("value", frame=f)
    for fc in keys.animation_data.action.fcurves:
        for kp, interp in zip(fc.keyframe_points, ('CONSTANT', 'LINEAR', 'BEZIER')):
            kp.interpolation = interp
    pb = arm.pose.bones["tip"]
    pb.rotation_mode = 'XYZ'
    for f, a in ((1, 0.0), (6, 0.6), (12, -0.4)):
        pb.rotation_euler = (a, 0, 0)
        pb.keyframe_insert("rotation_euler", frame=f)
    for f, x in ((1, 0.0), (12, 1.0)):
        arm.location = (x, 0, 0)
        arm.keyframe_insert("location", frame=f)
    mat = bpy.data.materials.new("BarMat")
    mat.use_nodes = True
    bar.data.materials.append(mat)
    add_camera_and_light(sc)
    return {"export_skins": True, "export_morph": True, "export_animations": True,
            "export_force_sampling": False, "export_morph_normal": True}


def image(name, w, h, fmt):
    img = bpy.data.images.new(name, w, h, alpha=True)
    px = []
    for y in range(h):
        for x in range(w):
            c = 1.0 if (x // 4 + y // 4) % 2 else 0.2
            px += [c, 0.5 * c, 1.0 - 0.5 * c, 1.0]
    img.pixels = px
    img.file_format = fmt
    img.pack()
    return img


def principled(name, **inputs):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    for k, v in inputs.items():
        bsdf.inputs[k].default_value = v
    return mat, bsdf


def textured(mat, bsdf, img, socket, mapping=None, normal=False):
    nt = mat.node_tree
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = img
    if mapping:
        m = nt.nodes.new("ShaderNodeMapping")
        uv = nt.nodes.new("ShaderNodeTexCoord")
        m.inputs["Location"].default_value = mapping[0]
        m.inputs["Rotation"].default_value = mapping[1]
        m.inputs["Scale"].default_value = mapping[2]
        nt.links.new(uv.outputs["UV"], m.inputs["Vector"])
        nt.links.new(m.outputs["Vector"], tex.inputs["Vector"])
    if normal:
        img.colorspace_settings.name = 'Non-Color'
        nm = nt.nodes.new("ShaderNodeNormalMap")
        nm.inputs["Strength"].default_value = 0.7
        nt.links.new(tex.outputs["Color"], nm.inputs["Color"])
        nt.links.new(nm.outputs["Normal"], bsdf.inputs["Normal"])
    else:
        nt.links.new(tex.outputs["Color"], bsdf.inputs[socket])


def quad(sc, name, x, mat):
    me = bpy.data.meshes.new(name)
    me.from_pydata([(x - 0.4, -0.4, 0), (x + 0.4, -0.4, 0), (x + 0.4, 0.4, 0), (x - 0.4, 0.4, 0)], [],
                   [(0, 1, 2, 3)])
    me.uv_layers.new(name="UVMap")
    me.materials.append(mat)
    ob = bpy.data.objects.new(name, me)
    sc.collection.objects.link(ob)
    return ob


def materials():
    sc = reset()
    png, jpg = image("checker_png", 16, 16, 'PNG'), image("checker_jpg", 16, 16, 'JPEG')
    nrm = image("bumps", 8, 8, 'PNG')
    m, b = principled("Glass", **{"Transmission": 1.0, "IOR": 1.5, "Roughness": 0.05})
    quad(sc, "glass", 0, m)
    m, b = principled("Coated", **{"Clearcoat": 0.8, "Clearcoat Roughness": 0.1, "Specular": 0.7,
                                    "Sheen": 0.5, "Metallic": 0.3})
    textured(m, b, png, "Base Color", mapping=((0.25, 0.5, 0), (0, 0, 0.3), (2, 3, 1)))
    quad(sc, "coated", 1, m)
    m, b = principled("Glow", **{"Emission": (1, 0.5, 0.2, 1), "Emission Strength": 12.0})
    textured(m, b, jpg, "Base Color")
    textured(m, b, nrm, None, normal=True)
    quad(sc, "glow", 2, m)
    m, b = principled("Cutout", **{"Alpha": 0.4})
    m.blend_method = 'CLIP'
    m.alpha_threshold = 0.3
    textured(m, b, png, "Roughness")
    quad(sc, "cutout", 3, m)
    m, b = principled("Blend", **{"Alpha": 0.5})
    m.blend_method = 'BLEND'
    quad(sc, "blend", 4, m)
    m = bpy.data.materials.new("Emitter")
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.remove(nt.nodes["Principled BSDF"])
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 5.0
    nt.links.new(em.outputs["Emission"], nt.nodes["Material Output"].inputs["Surface"])
    quad(sc, "emitter", 5, m)
    m, b = principled("Thick", **{"Transmission": 1.0})
    vol = m.node_tree.nodes.new("ShaderNodeVolumeAbsorption")
    vol.inputs["Color"].default_value = (0.2, 0.8, 0.3, 1)
    m.node_tree.links.new(vol.outputs["Volume"], m.node_tree.nodes["Material Output"].inputs["Volume"])
    quad(sc, "thick", 6, m)
    add_camera_and_light(sc)
    return {"export_image_format": 'AUTO'}


def add_camera_and_light(sc, ortho=False):
    cam = bpy.data.cameras.new("Cam")
    if ortho:
        cam.type = 'ORTHO'
        cam.ortho_scale = 6.0
    co = bpy.data.objects.new("Cam", cam)
    co.location, co.rotation_euler = (1, -6, 3), (math.radians(65), 0, 0)
    sc.collection.objects.link(co)
    sc.camera = co
    li = bpy.data.lights.new("Key", 'POINT')
    li.energy = 200
    lo = bpy.data.objects.new("Key", li)
    lo.location = (2, -2, 4)
    sc.collection.objects.link(lo)


def lights():
    sc = reset()
    mat, _ = principled("Floor", **{"Base Color": (0.6, 0.6, 0.6, 1)})
    quad(sc, "floor", 0, mat)
    parent = bpy.data.objects.new("Rig", None)
    parent.location, parent.rotation_euler, parent.scale = (0.5, 0, 1), (0, 0, 0.7), (1, 2, 1)
    sc.collection.objects.link(parent)
    for kind, energy, loc in (('SPOT', 300, (0, 0, 3)), ('SUN', 3.0, (0, 0, 5)), ('POINT', 50, (1, 1, 1))):
        li = bpy.data.lights.new(kind.lower(), kind)
        li.energy = energy
        li.color = (1.0, 0.9, 0.7)
        if kind == 'SPOT':
            li.spot_size, li.spot_blend = math.radians(50), 0.25
        lo = bpy.data.objects.new(kind.lower(), li)
        lo.location = loc
        lo.parent = parent
        sc.collection.objects.link(lo)
    add_camera_and_light(sc, ortho=True)
    cam = bpy.data.cameras.new("Persp")
    cam.lens, cam.clip_start, cam.clip_end = 35, 0.05, 250
    co = bpy.data.objects.new("Persp", cam)
    co.location, co.rotation_euler = (0, -4, 2), (math.radians(70), 0, 0)
    co.parent = parent
    sc.collection.objects.link(co)
    sc.render.resolution_x, sc.render.resolution_y = 320, 180
    return {}


def export(path, fmt, extra):
    props = bpy.ops.export_scene.gltf.get_rna_type().properties.keys()
    opts = dict(filepath=path, export_format=fmt, export_yup=True, export_apply=False,
                export_texcoords=True, export_normals=True, export_tangents=True, export_materials='EXPORT',
                export_cameras=True, export_lights=True, export_extras=True, export_animations=False,
                export_skins=False, export_morph=False)
    opts.update(extra)
    for k in ("export_import_convert_lighting_mode", "convert_lighting_mode"):
        if k in props:
            opts[k] = 'SPEC'
            break
    opts = {k: v for k, v in opts.items() if k in props or k == "filepath"}
    if bpy.ops.export_scene.gltf(**opts) != {'FINISHED'}:
        raise RuntimeError("export of %s failed" % path)


def main():
    out = sys.argv[sys.argv.index("--") + 1]
    os.makedirs(out, exist_ok=True)
    for build in (skin_morph, materials, lights):
        extra = build()
        name = "blender_" + build.__name__
        export(os.path.join(out, name + ".gltf"), 'GLTF_EMBEDDED', extra)
        export(os.path.join(out, name + ".glb"), 'GLB', extra)
        print("blender_seeds: %s" % name)


main()
