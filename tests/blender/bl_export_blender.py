"""Blender side: the scene through Blender's own glTF exporter, with the
samples' options (make_samples.gltf_export), for comparison with the
engine's writer: -P bl_export_blender.py -- OUT.gltf"""
import os
import sys

import numpy

if not hasattr(numpy, "bool"):  # Debian's numpy dropped numpy.bool; the 3.4 exporter uses it
    numpy.bool = bool
import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "exporters", "blender"))
import make_samples  # noqa: E402

out = sys.argv[sys.argv.index("--") + 1]
os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
make_samples.gltf_export(os.path.abspath(out))
