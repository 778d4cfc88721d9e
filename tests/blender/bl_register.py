"""Blender side: the add-on registers and unregisters cleanly (run with
--factory-startup --python-exit-code 1)."""
import addon_utils
import bpy

failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def engine_registered():
    # A class stays among __subclasses__ after unregistering; is_registered says.
    # (4.x registers engines without a bl_idname of their own, e.g. Hydra's base.)
    return any(getattr(c, "bl_idname", None) == "PHOTONBRIDGE" and c.is_registered
               for c in bpy.types.RenderEngine.__subclasses__())


check(not engine_registered(), "no engine before enabling")
for round_ in (1, 2):  # twice: unregister leaves nothing that breaks a second register
    mod = addon_utils.enable("photonbridge", default_set=True, handle_error=None)
    check(mod is not None, "round %d: enabled" % round_)
    check(engine_registered(), "round %d: RenderEngine PHOTONBRIDGE registered" % round_)
    check(hasattr(bpy.types.Scene, "photonbridge"), "round %d: Scene.photonbridge settings" % round_)
    check(hasattr(bpy.ops.export_scene, "photonbridge_gltf"), "round %d: File > Export operator" % round_)
    for p in ("PHOTONBRIDGE_PT_sampling", "PHOTONBRIDGE_PT_sampling_advanced", "PHOTONBRIDGE_PT_light_paths",
              "PHOTONBRIDGE_PT_film", "PHOTONBRIDGE_PT_performance"):
        check(hasattr(bpy.types, p), "round %d: the photonbridge panel %s" % (round_, p))
    for p in ("RENDER_PT_color_management", "RENDER_PT_format", "RENDER_PT_output", "DATA_PT_lens",
              "DATA_PT_camera", "DATA_PT_EEVEE_light", "EEVEE_MATERIAL_PT_surface", "EEVEE_WORLD_PT_surface"):
        check("PHOTONBRIDGE" in getattr(bpy.types, p).COMPAT_ENGINES, "round %d: %s shows for the engine" % (round_, p))
    bpy.context.scene.render.engine = "PHOTONBRIDGE"
    check(bpy.context.scene.render.engine == "PHOTONBRIDGE", "round %d: the scene can select it" % round_)
    # The photon tracer setting: the property, its command line
    # (settings.cli_args: render and serve) and the viewport's "settings"
    # request, both ways.
    s = bpy.context.scene.photonbridge
    from photonbridge import settings as pb_settings, viewport as pb_viewport
    args = pb_settings.cli_args(s)
    check(s.tracer == "bvh" and args[args.index("--tracer") + 1] == "bvh" and "--image-maps" not in args,
          "round %d: tracer bvh by default, --tracer bvh" % round_)
    s.tracer, s.image_maps, s.image_map_resolution = "images", 4, 32
    args = pb_settings.cli_args(s, sequence=True)
    check(args[args.index("--tracer") + 1] == "images" and args[args.index("--image-maps") + 1] == "4" and
          args[args.index("--image-map-resolution") + 1] == "32", "round %d: --tracer images --image-maps 4 "
          "--image-map-resolution 32 from the properties: %s" % (round_, args))
    st = pb_viewport.Viewport._settings(None, bpy.context.scene)
    check(st.get("tracer") == "images" and st.get("image_maps") == 4 and st.get("image_map_resolution") == 32,
          "round %d: the viewport's settings request carries the tracer: %s" % (round_, st))
    try:
        s.tracer = "kdtree"
        check(False, "round %d: an unknown tracer is refused" % round_)
    except TypeError:
        check(s.tracer == "images", "round %d: an unknown tracer is refused" % round_)
    s.tracer = "bvh"
    e = [c for c in bpy.types.RenderEngine.__subclasses__() if getattr(c, "bl_idname", None) == "PHOTONBRIDGE"][0]
    check(e.bl_use_preview is False and e.bl_use_shading_nodes_custom is False and e.bl_use_eevee_viewport is True
          and e.bl_use_postprocess is True, "round %d: engine flags" % round_)
    check("view_update" in e.__dict__ and "view_draw" in e.__dict__,
          "round %d: viewport callbacks (view_update, view_draw: viewport.py)" % round_)
    bpy.context.scene.render.engine = "CYCLES"
    addon_utils.disable("photonbridge", default_set=True, handle_error=None)
    check(not engine_registered(), "round %d: engine gone after disabling" % round_)
    check(not hasattr(bpy.types.Scene, "photonbridge"), "round %d: settings gone" % round_)
    check(not hasattr(bpy.types, "PHOTONBRIDGE_PT_sampling") and not hasattr(bpy.types, "PHOTONBRIDGE_PT_performance"),
          "round %d: panels gone" % round_)
    check("refresh_devices" not in dir(bpy.ops.photonbridge), "round %d: operators gone" % round_)
    check("PHOTONBRIDGE" not in bpy.types.RENDER_PT_format.COMPAT_ENGINES, "round %d: panels restored" % round_)
print("%d failed" % len(failures))
if failures:
    raise SystemExit(1)
