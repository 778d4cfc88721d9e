"""Blender side of the add-on tests (tests/blender/blender_check.py runs it
with --python before -E/-f/-a): enables the add-on from the checkout
(BLENDER_USER_SCRIPTS points at a folder whose addons/photonbridge links to
exporters/blender/photonbridge), selects the engine and applies settings
given after '--' as NAME=VALUE: photonbridge settings by their property
name, and 'percent', 'width', 'height', 'border' (x0,y0,x1,y1), 'crop',
'pass_z', 'frames' (start,end), 'layers' (names of view layers to add, comma
separated: Blender then calls the engine's render() once per layer)."""
import sys

import addon_utils
import bpy

mod = addon_utils.enable("photonbridge", default_set=True, handle_error=None)
if mod is None:
    print("bl_setup: the photonbridge add-on did not enable")
    sys.exit(1)
sc = bpy.context.scene
sc.render.engine = "PHOTONBRIDGE"
args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
for a in args:
    k, v = a.split("=", 1)
    if k == "percent":
        sc.render.resolution_percentage = int(v)
    elif k == "width":
        sc.render.resolution_x = int(v)
    elif k == "height":
        sc.render.resolution_y = int(v)
    elif k == "border":
        x0, y0, x1, y1 = (float(x) for x in v.split(","))
        sc.render.use_border = True
        sc.render.border_min_x, sc.render.border_min_y, sc.render.border_max_x, sc.render.border_max_y = x0, y0, x1, y1
    elif k == "crop":
        sc.render.use_crop_to_border = v == "1"
    elif k == "pass_z":
        for vl in sc.view_layers:
            vl.use_pass_z = v == "1"
    elif k == "layers":
        for name in v.split(","):
            sc.view_layers.new(name)
    elif k == "frames":
        sc.frame_start, sc.frame_end = (int(x) for x in v.split(","))
    else:
        prop = sc.photonbridge.bl_rna.properties[k]
        cur = getattr(sc.photonbridge, k)
        setattr(sc.photonbridge, k, type(cur)(v == "1") if isinstance(cur, bool) else type(cur)(v))
print("bl_setup: photonbridge enabled, settings", args)
