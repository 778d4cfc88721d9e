"""photonbridge for Blender: a render engine (F12, `blender -b -E
PHOTONBRIDGE`) that hands the evaluated scene to `photonbridge render` as
glTF plus the PHOTONBRIDGE_blender extension, and File > Export >
photonbridge glTF with the same writer. See docs/blender.md in the
photonbridge repository.

One package, two ways to install it: the legacy add-on (bl_info below;
Blender 3.4 to 5.x, "Install from Disk" of a zip holding this folder) and a
Blender 4.2+ extension (blender_manifest.toml; imported as
bl_ext.REPOSITORY.photonbridge, so every lookup of the add-on's own
preferences goes through __package__)."""

bl_info = {
    "name": "photonbridge",
    "author": "photonbridge",
    "version": (0, 1, 0),  # the CLI's version, as blender_manifest.toml
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine; File > Export > photonbridge glTF",
    "description": "GPU photon-mapping render engine (photonbridge CLI)",
    "category": "Render",
}

if "bpy" in locals():  # re-enabling the add-on reloads its modules
    import importlib
    for _m in (devices, settings, prefs, writer, viewport, engine, ui, export_op):  # noqa: F821
        importlib.reload(_m)

import bpy  # noqa: E402

from . import devices, settings, prefs, writer, viewport, engine, ui, export_op  # noqa: E402

_modules = (devices, settings, prefs, engine, ui, export_op)


def register():
    for m in _modules:
        m.register()


def unregister():
    for m in reversed(_modules):
        m.unregister()
