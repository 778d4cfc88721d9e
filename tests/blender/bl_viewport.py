"""Blender side of the viewport test (tests/blender/viewport_check.py runs
Blender with its window, under xvfb-run): the add-on enabled, the factory
scene (cube, light, camera) with a floor, the photonbridge engine with small
settings, the view transform Standard without dither; the 3D view set to a
fixed user view in RENDERED shading, overlays, gizmos and the header off. A
timer (bpy.app.timers) waits until the engine has drawn the frame of the
last still pass (PHOTONBRIDGE_VIEWPORT_PASSES) and nothing more comes, then
takes a screenshot of the window (viewport.png) and writes view.gltf (the
scene through the add-on's writer with a camera made from the view's
matrices, for the CLI render the test compares with); then orbits the view
and waits for its last pass again (orbit.png), then moves the cube and waits
for the reloaded scene's last pass (edit.png), then makes the cube's
material red and waits again (material.png); then sets the view back to
Solid shading and, 3 s later, writes whether the serve process still runs
(after_solid.json). view.json: the region's place
in the window, the first view's matrices, the size photonbridge rendered,
and for each screenshot what was drawn (frame, passes, the serve pid, the
reloads sent). Then Blender quits. Any failure: OUT/error.txt.

usage: blender --factory-startup --python bl_viewport.py -- OUT PASSES"""
import json
import math
import os
import sys
import time
import traceback

import addon_utils
import bpy

OUT, PASSES = sys.argv[sys.argv.index("--") + 1:][:2]
PASSES = int(PASSES)
T0 = time.time()
TIMEOUT = 400.0
state = {"phase": "wait", "shot_at": 0.0, "since": time.time()}


def finish(error=None):
    if error:
        with open(os.path.join(OUT, "error.txt"), "w") as f:
            f.write(error + "\n")
        print("bl_viewport: " + error, flush=True)
    # Leave RENDERED shading first: Blender frees the engine, and its serve
    # ends with it (checked 3 s later, while Blender still runs).
    pid = drawn().get("pid")
    try:
        view3d()[1].shading.type = 'SOLID'
    except Exception:
        pass
    t_solid = time.time()

    def check_and_quit():
        alive = False
        if pid:
            try:
                with open("/proc/%d/stat" % pid) as f:
                    alive = f.read().split(")")[-1].split()[0] != "Z"
            except OSError:
                alive = False
        with open(os.path.join(OUT, "after_solid.json"), "w") as f:
            json.dump({"pid": pid, "alive": alive, "seconds": time.time() - t_solid}, f)
        bpy.ops.wm.quit_blender()
        return None
    bpy.app.timers.register(check_and_quit, first_interval=3.0)


def view3d():
    win = bpy.context.window_manager.windows[0]
    for area in win.screen.areas:
        if area.type == 'VIEW_3D':
            region = next(r for r in area.regions if r.type == 'WINDOW')
            return win, area.spaces.active, area, region
    raise RuntimeError("no 3D view in the factory layout")


def setup():
    mod = addon_utils.enable("photonbridge", default_set=True, handle_error=None)
    if mod is None:
        raise RuntimeError("the photonbridge add-on did not enable")
    sc = bpy.context.scene
    bpy.ops.mesh.primitive_plane_add(size=12, location=(0, 0, -1))
    sc.render.engine = "PHOTONBRIDGE"
    s = sc.photonbridge
    s.photons, s.iterations, s.spp, s.seed, s.progressive = 16384, 1, 1, 5, False
    s.blender_bounces = True  # Max Bounces 12: --max-bounces 13
    sc.view_settings.view_transform = 'Standard'
    sc.view_settings.look = 'None'
    sc.view_settings.exposure, sc.view_settings.gamma = 0.0, 1.0
    sc.render.dither_intensity = 0.0
    win, space, area, region = view3d()
    # About 96 px across: the viewport's Pixel Size divides the region.
    div = max(1, min(8, region.width // 96))
    sc.render.preview_pixel_size = str(min((1, 2, 4, 8), key=lambda d: abs(d - div)))
    space.overlay.show_overlays = False
    space.show_gizmo = False
    space.show_region_toolbar = False
    space.show_region_ui = False
    space.show_region_header = False       # the header overlaps the region's top rows
    space.show_region_tool_header = False
    r3d = space.region_3d
    r3d.view_perspective = 'PERSP'
    r3d.view_location = (0, 0, 0)
    from mathutils import Euler
    r3d.view_rotation = Euler((math.radians(62), 0, math.radians(38)), 'XYZ').to_quaternion()
    r3d.view_distance = 11.0
    space.shading.type = 'RENDERED'


def tick():
    try:
        if time.time() - T0 > TIMEOUT:
            finish("timed out after %.0f s in phase %s (last drawn: %r)" % (TIMEOUT, state["phase"], drawn()))
            return None
        win, space, area, region = view3d()
        d = drawn()  # the engine's own timer redraws the view when a frame comes
        ph = state["phase"]
        now = time.time()
        key = (d.get("frame"), d.get("passes"), d.get("reloads"))
        if key != state.get("key"):
            state["key"], state["since"] = key, now
            print("bl_viewport: %.1f s: %s drew frame %s, pass %s, %s reloads" % (now - T0, ph, *key), flush=True)
        quiet = d.get("passes") == PASSES and now - state["since"] > 2.0
        if ph == "wait":  # the first view's last still pass
            if quiet:
                shot(win, space, area, region, d, "viewport.png", first=True)
                state["phase"] = "settle"  # the view camera's object makes the engine reload
            return 0.25
        if ph == "settle":
            if quiet and now - state["shot_at"] > 3.0:
                state["orbit_from"] = dict(d)
                r3d = space.region_3d
                from mathutils import Euler
                r3d.view_rotation = Euler((math.radians(70), 0, math.radians(-25)), 'XYZ').to_quaternion()
                state["phase"] = "orbit"
            return 0.25
        if ph == "orbit":  # a new camera: refined again, without a reload
            f0 = state["orbit_from"]
            if quiet and d.get("frame", -1) > f0.get("frame", -1):
                shot(win, space, area, region, d, "orbit.png")
                state["edit_from"] = dict(d)
                bpy.data.objects["Cube"].location.x += 1.5
                state["phase"] = "edit"
            return 0.25
        if ph == "edit":  # an object moved: the scene reloaded and refined again
            f0 = state["edit_from"]
            if quiet and d.get("reloads", 0) > f0.get("reloads", 0) and d.get("frame", -1) > f0.get("frame", -1):
                shot(win, space, area, region, d, "edit.png")
                state["material_from"] = dict(d)
                mat = bpy.data.objects["Cube"].active_material
                mat.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.8, 0.05, 0.05, 1)
                state["phase"] = "material"
            return 0.25
        if ph == "material":  # a material edit: reloaded, the cube red
            f0 = state["material_from"]
            if quiet and d.get("reloads", 0) > f0.get("reloads", 0) and d.get("frame", -1) > f0.get("frame", -1):
                shot(win, space, area, region, d, "material.png")
                state["info"]["orbit_from"] = state["orbit_from"]
                with open(os.path.join(OUT, "view.json"), "w") as fh:
                    json.dump(state["info"], fh, indent=1)
                finish()
                return None
            return 0.25
    except Exception:
        finish("exception: " + traceback.format_exc())
        return None
    return 0.5


def drawn():
    mod = sys.modules.get("photonbridge.viewport")
    return dict(mod.last_drawn) if mod else {}


def shot(win, space, area, region, d, name, first=False):
    path = os.path.join(OUT, name)
    with bpy.context.temp_override(window=win, area=area, region=region):
        bpy.ops.screen.screenshot(filepath=path)
    state["shot_at"] = time.time()
    print("bl_viewport: %s after pass %s, frame %s, %s reloads (%.1f s)"
          % (name, d.get("passes"), d.get("frame"), d.get("reloads"), time.time() - T0), flush=True)
    info = state.setdefault("info", {"shots": {}})
    info["shots"][name] = {"drawn": d, "region": [region.x, region.y, region.width, region.height],
                           "seconds": time.time() - T0}
    if not first:
        return
    r3d = space.region_3d
    V = [list(row) for row in r3d.view_matrix]
    P = [list(row) for row in r3d.window_matrix]
    info.update({"region": [region.x, region.y, region.width, region.height], "window": [win.width, win.height],
                 "view": V, "projection": P, "drawn": d, "pixel_size": bpy.context.scene.render.preview_pixel_size,
                 "seconds": time.time() - T0})
    # A camera at the view, its vertical angle and clip planes from the
    # projection (a user view has no lens shift: checked by the test).
    sc = bpy.context.scene
    cam_data = bpy.data.cameras.new("ViewCam")
    cam_data.sensor_fit = 'VERTICAL'
    cam_data.angle_y = 2.0 * math.atan(1.0 / P[1][1])
    n = P[2][3] / (P[2][2] - 1.0)
    f = P[2][3] / (P[2][2] + 1.0)
    cam_data.clip_start, cam_data.clip_end = n, f
    cam = bpy.data.objects.new("ViewCam", cam_data)
    sc.collection.objects.link(cam)
    cam.matrix_world = r3d.view_matrix.inverted()
    dg = bpy.context.evaluated_depsgraph_get()
    dg.update()
    from photonbridge import viewport, writer
    info["cli_args"] = viewport.serve_args(sc)  # the frame options the viewport's serve runs with
    writer.write_gltf(dg, os.path.join(OUT, "view.gltf"), camera=cam.evaluated_get(dg))


def tick_broken():
    """PASSES 0: the binary is broken (the test's script exits 3 with an
    error line): the viewport must say so and Blender go on."""
    mod = sys.modules.get("photonbridge.viewport")
    err = mod.last_error.get("message") if mod else None
    if err or time.time() - T0 > 120:
        with open(os.path.join(OUT, "broken.json"), "w") as f:
            json.dump({"error": err, "seconds": time.time() - T0}, f)
        finish()
        return None
    return 0.25


try:
    setup()
    bpy.app.timers.register(tick if PASSES else tick_broken, first_interval=1.0)
except Exception:
    finish("setup: " + traceback.format_exc())
