"""Blender side of screenshot.sh: with the UI up (under Xvfb), the
photonbridge add-on enabled, the Properties editor on the Render tab (the
photonbridge panel), F12 rendered into an Image Editor that replaces the 3D
view, then a screenshot of the whole window and quit.
    blender SAMPLE.blend --python screenshot.py -- OUT.png"""
import os
import sys

import addon_utils
import bpy

OUT = os.path.abspath(sys.argv[sys.argv.index("--") + 1])


def setup():
    addon_utils.enable("photonbridge", default_set=True, handle_error=None)
    sc = bpy.context.scene
    sc.render.engine = "PHOTONBRIDGE"
    sc.render.resolution_percentage = 50
    s = sc.photonbridge
    s.photons, s.iterations, s.spp, s.progressive = 65536, 8, 8, True
    sc.view_settings.view_transform = 'Filmic'
    win = bpy.context.window_manager.windows[0]
    for area in win.screen.areas:
        if area.type == 'PROPERTIES':
            area.spaces.active.context = 'RENDER'
    return 1.0


def render():
    bpy.ops.render.render()
    win = bpy.context.window_manager.windows[0]
    for area in win.screen.areas:
        if area.type == 'VIEW_3D':
            area.type = 'IMAGE_EDITOR'
            area.spaces.active.image = bpy.data.images["Render Result"]
    return 2.0


def shoot():
    win = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=win, screen=win.screen, area=win.screen.areas[0]):
        bpy.ops.screen.screenshot(filepath=OUT)
    print("screenshot:", OUT)
    return 1.0


steps = [setup, render, shoot, lambda: bpy.ops.wm.quit_blender()]


def step():
    f = steps.pop(0)
    delay = f()
    return delay if steps else None


bpy.app.timers.register(step, first_interval=2.0)
