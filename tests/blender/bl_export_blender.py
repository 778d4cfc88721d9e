"""Blender side: the scene through Blender's own glTF exporter, with the
samples' options (make_samples.gltf_export), and through the render
engine's writer, in one Blender run:
    -P bl_export_blender.py -- BLENDER_OUT.gltf ADDON_OUT.gltf"""
import os
import sys

import numpy

if not hasattr(numpy, "bool"):  # Debian's numpy dropped numpy.bool; the 3.4 exporter uses it
    numpy.bool = bool
import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "exporters", "blender"))
import make_samples  # noqa: E402
from photonbridge import writer  # noqa: E402

theirs, ours = sys.argv[sys.argv.index("--") + 1:][:2]
report = writer.write_gltf(bpy.context.evaluated_depsgraph_get(), os.path.abspath(ours))
print("bl_export_blender: the add-on's writer: %d triangles in %.3f s" % (report.triangles, report.seconds))
os.makedirs(os.path.dirname(os.path.abspath(theirs)), exist_ok=True)
make_samples.gltf_export(os.path.abspath(theirs))
