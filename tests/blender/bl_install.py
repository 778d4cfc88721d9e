"""Blender side of the install test (blender_check.py part 'install'):
installs a zip made by scripts/blender_package.py the way a user does, into
the user folders the environment points at (BLENDER_USER_RESOURCES for 4.2+,
BLENDER_USER_SCRIPTS/CONFIG for 3.4), enables it, checks that the engine
registered under the module name Blender gives it, and renders a small
scene with it (F12's path: bpy.ops.render.render write_still), which
finds the binary through $PHOTONBRIDGE_BIN.

usage: ... -P bl_install.py -- legacy|extension ZIP OUT.png"""
import os
import sys

import addon_utils
import bpy

kind, zip_path, out = sys.argv[sys.argv.index("--") + 1:][:3]
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


if kind == "extension":
    r = bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default", enable_on_install=True)
    module = "bl_ext.user_default.photonbridge"
else:
    r = bpy.ops.preferences.addon_install(filepath=zip_path)
    module = "photonbridge"
    addon_utils.enable(module, default_set=True, handle_error=None)
check(r == {'FINISHED'}, "%s: Blender installed %s (%s)" % (kind, zip_path, r))
check(module in bpy.context.preferences.addons.keys(), "%s: enabled as %s" % (kind, module))
prefs = bpy.context.preferences.addons.get(module)
check(prefs is not None and hasattr(prefs.preferences, "binary"),
      "%s: its preferences (the binary's path) are found under %s" % (kind, module))
engines = [getattr(c, "bl_idname", None) for c in bpy.types.RenderEngine.__subclasses__()
           if getattr(c, "is_registered", False)]
check("PHOTONBRIDGE" in engines, "%s: the PHOTONBRIDGE engine is registered (%s)" % (kind, engines))

# A small scene: a floor and a box of Diffuse BSDFs, a point light, a camera.
sc = bpy.context.scene
for o in list(sc.objects):
    bpy.data.objects.remove(o, do_unlink=True)
bpy.ops.mesh.primitive_plane_add(size=6)
bpy.ops.mesh.primitive_cube_add(size=1, location=(0, 0, 0.5))
mat = bpy.data.materials.new("Grey")
mat.use_nodes = True
nt = mat.node_tree
nt.nodes.clear()
d = nt.nodes.new("ShaderNodeBsdfDiffuse")
d.inputs["Color"].default_value = (0.6, 0.6, 0.6, 1)
o = nt.nodes.new("ShaderNodeOutputMaterial")
nt.links.new(d.outputs[0], o.inputs["Surface"])
for ob in sc.objects:
    ob.data.materials.append(mat)
light = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", 'POINT'))
light.data.energy = 500
light.location = (2, -2, 3)
sc.collection.objects.link(light)
cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
cam.location = (0, -6, 3)
cam.rotation_euler = (1.15, 0, 0)
sc.collection.objects.link(cam)
sc.camera = cam
sc.render.engine = "PHOTONBRIDGE"
sc.render.resolution_x, sc.render.resolution_y, sc.render.resolution_percentage = 64, 48, 100
s = sc.photonbridge
s.photons, s.iterations, s.spp = 4096, 1, 1
sc.render.image_settings.file_format = 'OPEN_EXR'
sc.render.filepath = out
try:
    bpy.ops.render.render(write_still=True)
    ok = True
except RuntimeError as e:
    print(e)
    ok = False
check(ok and os.path.isfile(out), "%s: F12 with the installed engine wrote %s" % (kind, out))
print("%d failed" % len(failures))
if failures:
    raise SystemExit(1)
