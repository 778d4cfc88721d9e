"""Build the skin and shape-key test scene in Blender and export it with
Blender's own glTF exporter, animated and baked (tests/unit/test_deform_blender.c
compares photonbridge's pose of the first with Blender's own deformation in
the others):

    blender -b --factory-startup --python-exit-code 1 \
        -P tests/data/deform/make_deform.py -- --out tests/data/deform

The scene (Blender Z up; the exporter writes glTF Y up), 24 fps, frames 0-24:
  - "Cylinder": radius 0.3, 3 m tall, 24 segments x 13 rings with capped ends,
    smooth shaded, skinned to a chain of three bones along +Z (one per metre;
    weights: hat functions around the bones' middles, normalised), under an
    armature modifier; the middle bone bends about X to 0.6 rad and the top
    one to (0.8, 0, 0.5) rad (Euler XYZ) by frame 24, Bezier keys;
  - "ShapeCube": a 1 m cube at x = 2 with two shape keys, "Tall" (the top
    face 1 m higher) and "Pinch" (the top face scaled by 0.5), whose values
    go 0 -> 1 and 0 -> 0.6 over frames 0-24;
  - a floor and a backdrop 2 m behind (8 m each, no material), a camera
    and a sun (4 W/m^2).

Written to OUT: deform.gltf (+ deform.bin): skins, shape keys as morph
targets, every frame sampled (LINEAR keys); deform_baked_fNN.gltf (+ .bin)
for NN in 00, 12, 24: the same scene at that frame with the armature and the
shape keys applied by Blender (no skins, no morph targets, no animation).
Deterministic: no randomness, no .blend file.
"""

import argparse
import math
import os
import sys

import bpy

FRAMES = (0, 12, 24)


def reset():
    bpy.ops.wm.read_homefile(use_empty=True)
    sc = bpy.context.scene
    sc.render.fps = 24
    sc.render.fps_base = 1.0
    sc.frame_start = 0
    sc.frame_end = 24
    sc.render.resolution_x = 320
    sc.render.resolution_y = 240
    return sc


def cylinder_mesh():
    verts, faces = [], []
    seg, rings = 24, 13
    for r in range(rings):
        z = 3.0 * r / (rings - 1)
        for k in range(seg):
            a = 2 * math.pi * k / seg
            verts.append((0.3 * math.cos(a), 0.3 * math.sin(a), z))
    for r in range(rings - 1):
        for k in range(seg):
            a, b = r * seg + k, r * seg + (k + 1) % seg
            faces.append((a, b, b + seg, a + seg))
    bottom, top = len(verts), len(verts) + 1
    verts += [(0, 0, 0), (0, 0, 3)]
    for k in range(seg):
        faces.append((bottom, (k + 1) % seg, k))
        t = (rings - 1) * seg
        faces.append((top, t + k, t + (k + 1) % seg))
    me = bpy.data.meshes.new("Cylinder")
    me.from_pydata(verts, [], faces)
    for p in me.polygons:
        p.use_smooth = True
    me.update()
    return me


def build(sc):
    # Armature: three bones along +Z.
    arm_data = bpy.data.armatures.new("Rig")
    arm = bpy.data.objects.new("Rig", arm_data)
    sc.collection.objects.link(arm)
    bpy.context.view_layer.objects.active = arm
    arm.select_set(True)
    bpy.ops.object.mode_set(mode='EDIT')
    prev = None
    for i in range(3):
        b = arm_data.edit_bones.new("Bone%d" % i)
        b.head = (0, 0, i)
        b.tail = (0, 0, i + 1)
        if prev:
            b.parent = prev
            b.use_connect = True
        prev = b
    bpy.ops.object.mode_set(mode='OBJECT')

    cyl = bpy.data.objects.new("Cylinder", cylinder_mesh())
    sc.collection.objects.link(cyl)
    cyl.parent = arm
    mod = cyl.modifiers.new("Armature", 'ARMATURE')
    mod.object = arm
    groups = [cyl.vertex_groups.new(name="Bone%d" % i) for i in range(3)]
    for v in cyl.data.vertices:
        z = v.co.z
        w = [max(0.0, 1.0 - abs(z - (i + 0.5))) for i in range(3)]
        s = sum(w)
        for i in range(3):
            if w[i] > 0:
                groups[i].add([v.index], w[i] / s, 'REPLACE')
    mat = bpy.data.materials.new("Skin")
    mat.use_nodes = True
    cyl.data.materials.append(mat)

    for pb in arm.pose.bones:
        pb.rotation_mode = 'XYZ'
    for frame, r1, r2 in ((0, (0, 0, 0), (0, 0, 0)), (24, (0.6, 0, 0), (0.8, 0, 0.5))):
        arm.pose.bones["Bone1"].rotation_euler = r1
        arm.pose.bones["Bone2"].rotation_euler = r2
        arm.pose.bones["Bone1"].keyframe_insert("rotation_euler", frame=frame)
        arm.pose.bones["Bone2"].keyframe_insert("rotation_euler", frame=frame)

    # The shape-key cube.
    bpy.ops.mesh.primitive_cube_add(size=1, location=(2, 0, 0.5))
    cube = bpy.context.object
    cube.name = "ShapeCube"
    cube.data.name = "ShapeCube"
    cube.shape_key_add(name="Basis")
    tall = cube.shape_key_add(name="Tall")
    pinch = cube.shape_key_add(name="Pinch")
    for i, v in enumerate(cube.data.vertices):
        if v.co.z > 0:
            tall.data[i].co.z += 1.0
            pinch.data[i].co.x *= 0.5
            pinch.data[i].co.y *= 0.5
    keys = cube.data.shape_keys
    for frame, a, b in ((0, 0.0, 0.0), (24, 1.0, 0.6)):
        keys.key_blocks["Tall"].value = a
        keys.key_blocks["Pinch"].value = b
        keys.key_blocks["Tall"].keyframe_insert("value", frame=frame)
        keys.key_blocks["Pinch"].keyframe_insert("value", frame=frame)

    bpy.ops.mesh.primitive_plane_add(size=8, location=(1, 0, 0))
    bpy.context.object.name = "Floor"
    bpy.ops.mesh.primitive_plane_add(size=8, location=(1, 2, 4), rotation=(math.radians(90), 0, 0))
    bpy.context.object.name = "Backdrop"

    cam_data = bpy.data.cameras.new("Camera")
    cam = bpy.data.objects.new("Camera", cam_data)
    sc.collection.objects.link(cam)
    cam.location = (1.0, -7.0, 2.5)
    cam.rotation_euler = (math.radians(82), 0, 0)
    sc.camera = cam
    sun_data = bpy.data.lights.new("Sun", 'SUN')
    sun_data.energy = 4.0
    sun = bpy.data.objects.new("Sun", sun_data)
    sc.collection.objects.link(sun)
    sun.rotation_euler = (math.radians(40), math.radians(10), math.radians(30))


def export(path, animated):
    props = bpy.ops.export_scene.gltf.get_rna_type().properties.keys()
    opts = dict(filepath=path, export_format='GLTF_SEPARATE', export_yup=True, export_apply=True,
                export_texcoords=True, export_normals=True, export_tangents=False, export_colors=False,
                export_materials='EXPORT', export_cameras=True, export_lights=True, export_extras=False,
                export_animations=animated, export_skins=animated, export_morph=animated,
                export_morph_normal=animated, export_morph_tangent=False, use_selection=False,
                export_draco_mesh_compression_enable=False)
    if not animated:  # this frame (the exporter moves to frame_start otherwise)
        opts.update(export_current_frame=True)
    if animated:
        opts.update(export_frame_range=True, export_frame_step=1, export_force_sampling=True,
                    export_nla_strips=False, export_nla_strips_merged_animation_name="Deform",
                    export_optimize_animation_size=False, export_current_frame=False, export_def_bones=False)
    for key in ("export_import_convert_lighting_mode", "convert_lighting_mode"):
        if key in props:
            opts[key] = 'SPEC'
    opts = {k: v for k, v in opts.items() if k in props or k == "filepath"}
    if bpy.ops.export_scene.gltf(**opts) != {'FINISHED'}:
        raise RuntimeError("export of %s failed" % path)


def main():
    import numpy
    numpy.bool = bool  # Debian's numpy lacks it; the 3.4 exporter uses it
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", required=True)
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    sc = reset()
    build(sc)
    sc.frame_set(0)
    export(os.path.join(args.out, "deform.gltf"), True)
    # The exporter applies modifiers only to objects that have one: without,
    # it writes the cube's basis shape. A displacement of strength 0 changes
    # nothing but makes it export the evaluated mesh, shape keys applied.
    cube = bpy.data.objects["ShapeCube"]
    cube.modifiers.new("Evaluate", 'DISPLACE').strength = 0.0
    for f in FRAMES:
        sc.frame_set(f)
        export(os.path.join(args.out, "deform_baked_f%02d.gltf" % f), False)
    print("make_deform: wrote deform.gltf and %d baked frames to %s" % (len(FRAMES), args.out))


main()
