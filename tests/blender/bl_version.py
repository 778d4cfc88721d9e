"""Prints the running Blender's version (blender_check.py)."""
import bpy

print("BLENDER_VERSION %d %d %d" % tuple(bpy.app.version), flush=True)
