"""The add-on's panels drawn by Blender itself: Blender 3.4 with its window
(under xvfb-run; the bpy module has no window manager), the Properties
editor on the Render tab with photonbridge as the engine, every
photonbridge panel open (Advanced and Algorithm re-registered open). Each panel's draw
and draw_header is wrapped to record that Blender called it and that it
returned without an exception (an exception in a panel's draw is only
printed by Blender, never raised).
    xvfb-run -a blender --factory-startup SCENE.blend --python bl_ui_window.py -- ROOT EXE OUT
(a .blend, so that no splash covers the window)
Exit 0 when every panel drew, 1 otherwise (RESULT lines on stdout); the
Properties editor's screenshot in OUT/panels.png."""
import json
import os
import sys
import traceback

import addon_utils
import bpy

ROOT, EXE, OUT = sys.argv[sys.argv.index("--") + 1:][:3]
os.makedirs(OUT, exist_ok=True)
sys.path.insert(0, os.path.join(ROOT, "exporters", "blender"))
calls = {}   # "Class.fn" -> count of clean calls
errors = []


def wrap(cls, fn):
    orig = cls.__dict__[fn]

    def drawn(self, context):
        try:
            orig(self, context)
            key = "%s.%s" % (cls.__name__, fn)
            calls[key] = calls.get(key, 0) + 1
        except Exception:
            errors.append("%s.%s: %s" % (cls.__name__, fn, traceback.format_exc()))
            raise
    setattr(cls, fn, drawn)


def done(code):
    with open(os.path.join(OUT, "result.json"), "w") as f:
        json.dump({"calls": calls, "errors": errors}, f, indent=1)
    sys.stdout.flush()
    os._exit(code)


def setup():
    try:
        addon_utils.enable("photonbridge", default_set=True, handle_error=None)
        bpy.context.preferences.addons["photonbridge"].preferences.binary = os.path.abspath(EXE)
        from photonbridge import ui
        # Advanced and its Algorithm panel re-registered open, so that Blender
        # draws them (a child goes before its parent, and after it back)
        closed = [ui.PHOTONBRIDGE_PT_sampling_advanced, ui.PHOTONBRIDGE_PT_sampling_algorithm]
        for c in reversed(closed):
            bpy.utils.unregister_class(c)
        for c in closed:
            c.bl_options = set()
            bpy.utils.register_class(c)
        for c in ui.classes:
            for fn in ("draw", "draw_header"):
                if fn in c.__dict__:
                    wrap(c, fn)
        sc = bpy.context.scene
        sc.render.engine = "PHOTONBRIDGE"
        sc.photonbridge.tracer = "images"  # its sub-settings drawn too
        win = bpy.context.window_manager.windows[0]
        props = [a for a in win.screen.areas if a.type == 'PROPERTIES']
        if not props:
            errors.append("no Properties editor in the factory layout")
            done(1)
        props[0].spaces.active.context = 'RENDER'
        props[0].tag_redraw()
    except Exception:
        errors.append("setup: " + traceback.format_exc())
        done(1)
    return 2.0


def redraw():
    win = bpy.context.window_manager.windows[0]
    try:
        with bpy.context.temp_override(window=win, screen=win.screen):
            bpy.ops.wm.redraw_timer(type='DRAW_WIN_SWAP', iterations=2)
    except Exception:
        errors.append("redraw: " + traceback.format_exc())
    return 1.0


def big():
    # The 3D view's area becomes a second Properties editor on the Render
    # tab: room for every panel in the screenshot.
    win = bpy.context.window_manager.windows[0]
    area = max(win.screen.areas, key=lambda a: a.width * a.height)
    area.type = 'PROPERTIES'
    state["big"] = area
    bpy.context.scene.photonbridge.tracer = "bvh"  # the default, in the picture
    return 1.0


def tab():
    try:
        state["big"].spaces.active.context = 'RENDER'
    except Exception as e:  # only the screenshot's
        print("bl_ui_window: the big editor stays on its tab: %s" % e, flush=True)
    return 0.5


state = {}


def shoot():
    # OUT/panels.png: the Properties editor as drawn (to look at; not compared)
    win = bpy.context.window_manager.windows[0]
    area = state.get("big") or [a for a in win.screen.areas if a.type == 'PROPERTIES'][0]
    try:
        with bpy.context.temp_override(window=win, screen=win.screen, area=area):
            bpy.ops.screen.screenshot_area(filepath=os.path.join(OUT, "panels.png"))
    except Exception as e:
        print("bl_ui_window: no screenshot: %s" % e, flush=True)
    return 0.5


def check():
    from photonbridge import ui
    want = ["%s.%s" % (c.__name__, fn) for c in ui.classes for fn in ("draw", "draw_header") if fn in c.__dict__]
    missing = [w for w in want if not calls.get(w)]
    for w in want:
        print("RESULT %s %s" % ("ok  " if calls.get(w) else "FAIL", w), flush=True)
    for e in errors:
        print("RESULT FAIL " + e, flush=True)
    done(1 if missing or errors else 0)


steps = [setup, redraw, redraw, big, redraw, tab, redraw, shoot, check]


def step():
    try:
        delay = steps.pop(0)()
    except Exception:  # never a hang: the test ends
        errors.append("step: " + traceback.format_exc())
        check()
    return delay if steps else None


bpy.app.timers.register(step, first_interval=2.0)
