"""Blender side (4.5+): a scene lit by lights that use Blender 4.5's light
settings, saved as lights45.blend into the folder after '--':
  a 6 m floor and a box of Diffuse BSDFs, no world (black), a camera, and
  Warm    point 200 W, radius 0.1 m, Exposure +1, Temperature 3000 K;
  Raw     spot 50 W, radius 0.25 m, 70 degrees, Normalize off;
  Panel   area 2 x 1 m rectangle 20 W, Normalize off, Exposure -0.5;
  Disc    area disc 0.6 m 10 W, Normalize off;
  Sun     sun 1 W/m^2, angle 10 degrees, Normalize off, Exposure +3;
  Ghost   point 30 W with Shadow off (Light.use_shadow False).
and sphere45.blend: the same floor and box lit by two sphere lights (Soft
Falloff off) close to them: Orb, a point light of 150 W and radius 0.5 m
0.3 m above the box's top, and Cone, a spot of 100 W, radius 0.3 m, 90 degrees,
1 m above the floor. Cycles 4.5 renders both as the reference (blender_check.py
part lights45)."""
import math
import os
import sys

import bpy

out = sys.argv[sys.argv.index("--") + 1]
os.makedirs(out, exist_ok=True)
bpy.ops.wm.read_factory_settings(use_empty=True)
sc = bpy.context.scene


def diffuse(name, rgb):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = rgb + (1.0,)
    o = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(d.outputs[0], o.inputs["Surface"])
    return m


bpy.ops.mesh.primitive_plane_add(size=6)
sc.objects[-1].data.materials.append(diffuse("Floor", (0.8, 0.8, 0.8)))
bpy.ops.mesh.primitive_cube_add(size=1, location=(0, 0, 0.5))
bpy.context.active_object.data.materials.append(diffuse("Box", (0.8, 0.5, 0.3)))


def light(name, kind, loc, rot=(0, 0, 0), **props):
    data = bpy.data.lights.new(name, kind)
    for k, v in props.items():
        setattr(data, k, v)
    ob = bpy.data.objects.new(name, data)
    ob.location, ob.rotation_euler = loc, rot
    sc.collection.objects.link(ob)
    return ob


light("Warm", 'POINT', (-1.5, -1.0, 2.5), energy=200.0, shadow_soft_size=0.1, exposure=1.0, use_temperature=True,
      temperature=3000.0)
light("Raw", 'SPOT', (1.5, -1.5, 3.0), (0.3, 0.3, 0), energy=50.0, shadow_soft_size=0.25,
      spot_size=math.radians(70), normalize=False)
light("Panel", 'AREA', (0.0, 1.5, 2.5), energy=20.0, shape='RECTANGLE', size=2.0, size_y=1.0, normalize=False,
      exposure=-0.5)
light("Disc", 'AREA', (-1.0, 1.0, 1.8), energy=10.0, shape='DISK', size=0.6, normalize=False)
light("Sun", 'SUN', (0, 0, 5), (0.4, 0.2, 0), energy=1.0, angle=math.radians(10), normalize=False, exposure=3.0)
light("Ghost", 'POINT', (0.0, 0.0, 1.4), energy=30.0, shadow_soft_size=0.05, use_shadow=False)
cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
cam.location, cam.rotation_euler = (0.0, -6.0, 3.2), (math.radians(62), 0, 0)
sc.collection.objects.link(cam)
sc.camera = cam
sc.render.resolution_x, sc.render.resolution_y, sc.render.resolution_percentage = 64, 48, 100
sc.cycles.samples = 512
sc.cycles.use_denoising = False
sc.cycles.device = 'CPU'
sc.render.threads_mode = 'FIXED'
sc.render.threads = 2
sc.cycles.seed = 3
sc.view_settings.view_transform = 'Standard'
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, "lights45.blend"))
for ob in [o for o in sc.objects if o.type == 'LIGHT']:
    bpy.data.objects.remove(ob, do_unlink=True)
light("Orb", 'POINT', (0.0, 0.0, 1.8), energy=150.0, shadow_soft_size=0.5, use_soft_falloff=False)
light("Cone", 'SPOT', (1.6, -0.8, 1.0), (0.5, 0.0, 0.0), energy=100.0, shadow_soft_size=0.3,
      spot_size=math.radians(90), use_soft_falloff=False)
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, "sphere45.blend"))
print("bl_lights45: wrote", out)
