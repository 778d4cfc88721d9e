"""The render engine: F12, `blender -b -E PHOTONBRIDGE -f/-a`.

update(data, depsgraph) runs while Blender's UI is locked: the only safe
place to read the scene, so the whole hand-off (writer.py: the evaluated
depsgraph to glTF) happens there, into a temporary folder. render(depsgraph)
then runs `photonbridge render` on that file without touching the scene,
as a job of the `photonbridge batch -` session kept between still renders
(cli.Job: the device and its compiled pipelines stay, so the next F12
starts at once; a cancel ends the session, the next render starts another):
its progress lines come in on a reader thread, the refining picture
is loaded into the render result every few seconds from the CLI's --preview
EXR, test_break() cancels it with SIGINT, and the finished multilayer EXR
(Blender's channel names, --blender-layer) is loaded into the result with
its passes. Combined stays scene-linear: Blender's view transform, look,
exposure and gamma apply to it as they do to Cycles'.

Animation: every frame of `-a` is handed off and rendered on its own (the
camera, lights and objects of that frame). With the scene's "Render
Animation as One Sequence" setting, the first frame of an animation render
writes the whole frame range as one glTF with animation (sampled at every
frame, anim.py) and starts one `photonbridge render --frames` (temporal
filtering across frames); each frame Blender asks for is then loaded from
that sequence as soon as its EXR exists.

Viewport (RENDERED shading): view_update and view_draw hand over to
viewport.py, which keeps one `photonbridge serve` per engine and draws its
refining frames; free() (and __del__) end it."""
import atexit
import os
import shutil
import tempfile
import time

import bpy

from . import anim, cli, settings, viewport, writer

# Passes photonbridge adds (besides Combined, and Depth, which Blender adds
# itself when the view layer has its Z pass): (name, channels, chan_id, type)
# as --blender-layer names them (src/app/render_out.h).
PASSES = [("Normal", 3, "XYZ", 'VECTOR'), ("Emit", 3, "RGB", 'COLOR'), ("Direct", 3, "RGB", 'COLOR'),
          ("Indirect", 3, "RGB", 'COLOR'), ("Caustic", 3, "RGB", 'COLOR'), ("Albedo", 3, "RGB", 'COLOR')]

POLL_S = 0.1

# The running animation sequence (sequence mode), kept between the engine
# instances Blender makes for each frame.
_sequence = {}


def addon_prefs():
    addon = bpy.context.preferences.addons.get(__package__) if bpy.context else None
    return addon.preferences if addon else None


def result_passes(result):
    """The passes of a render result's first layer, for --blender-passes
    (the CLI writes exactly those)."""
    return ",".join(p.name for p in result.layers[0].passes)


def border_rect(render, full_w, full_h):
    """Blender's render border in pixels: (x, y_top, w, h), y from the top
    row; the engine renders exactly that region (render_init_from_main:
    xmin = int(border.min_x * width), ...)."""
    if not render.use_border:
        return 0, 0, full_w, full_h
    x0, x1 = int(render.border_min_x * full_w), int(render.border_max_x * full_w)
    y0, y1 = int(render.border_min_y * full_h), int(render.border_max_y * full_h)
    return x0, full_h - y1, max(0, x1 - x0), max(0, y1 - y0)


class PhotonbridgeRenderEngine(bpy.types.RenderEngine):
    bl_idname = "PHOTONBRIDGE"
    bl_label = "photonbridge"
    bl_use_preview = False              # no CLI run per material thumbnail
    bl_use_shading_nodes_custom = False  # artists keep the Cycles/EEVEE node editor
    bl_use_eevee_viewport = True         # Material Preview stays on EEVEE
    bl_use_postprocess = True            # the compositor runs on the result

    def __init__(self, *args, **kwargs):
        # Blender 4.4+ builds Python subclasses of its types through
        # __init__(*args, **kwargs) and refuses one that does not forward
        # them ("could not create instance"); 3.4 passes none.
        super().__init__(*args, **kwargs)
        self.handoff = None      # this frame's folder, glTF path, writer report
        self.handoff_error = None
        self.exe = None
        self.viewport = None     # viewport.Viewport, made by the first view_update

    def _remove_handoff(self):
        """The hand-off folder now, not when the engine is freed (a
        sequence keeps its own)."""
        h = getattr(self, "handoff", None)
        if h and not h.get("sequence"):
            shutil.rmtree(h["folder"], ignore_errors=True)

    def free(self):
        """The engine goes (Blender frees it when the viewport leaves
        RENDERED shading, the area closes or the file changes): its serve
        process and folder go with it."""
        vp = getattr(self, "viewport", None)
        if vp is not None:
            vp.stop()
            self.viewport = None

    def __del__(self):
        self.free()
        self._remove_handoff()  # the folder goes with the frame
        parent_del = getattr(super(), "__del__", None)
        if parent_del is not None:
            parent_del()

    # ---- the viewport (viewport.py: `photonbridge serve`) ---------------------------

    def view_update(self, context, depsgraph):
        if self.viewport is None:
            self.viewport = viewport.Viewport()
        self.viewport.update(self, context, depsgraph)

    def view_draw(self, context, depsgraph):
        if self.viewport is not None:
            self.viewport.draw(self, context, depsgraph)

    # ---- the hand-off (UI locked) -------------------------------------------------

    def update(self, data, depsgraph):
        self.handoff, self.handoff_error = None, None
        scene = depsgraph.scene
        prefs = addon_prefs()
        try:
            self.exe = cli.find_binary(prefs.binary if prefs else "")
        except cli.BinaryNotFound as e:
            self.handoff_error = str(e)
            return
        folder = tempfile.mkdtemp(prefix="photonbridge_", dir=self.temporary_directory or None)
        path = os.path.join(folder, "scene.gltf")
        try:
            if self.is_animation and scene.photonbridge.animation_sequence:
                key = (scene.name, depsgraph.view_layer.name)
                seq = _sequence.get(key)
                # The first frame writes the whole range in render(), where
                # frame_set may evaluate the other frames.
                self.handoff = {"folder": folder, "sequence": key, "new": not (seq and seq.get("running")),
                                "path": path}
            else:
                report = writer.write_gltf(depsgraph, path, camera=self.camera_override)
                self.handoff = {"folder": folder, "path": path, "report": report}
        except Exception as e:  # a broken scene is a report, never a crash
            shutil.rmtree(folder, ignore_errors=True)
            self.handoff = None
            self.handoff_error = "photonbridge: the scene could not be written: %s: %s" % (type(e).__name__, e)

    # ---- passes ---------------------------------------------------------------

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", 'COLOR')
        if renderlayer.use_pass_z:
            self.register_pass(scene, renderlayer, "Depth", 1, "Z", 'VALUE')
        for name, ch, chan_id, kind in PASSES:
            self.register_pass(scene, renderlayer, name, ch, chan_id, kind)

    # ---- render ---------------------------------------------------------------

    def _fail(self, message):
        self.report({'ERROR'}, message)
        self.error_set(message)

    def render(self, depsgraph):
        if self.handoff_error:
            self._fail(self.handoff_error)
            return
        if not self.handoff:
            self._fail("photonbridge: no scene was handed over (update() did not run)")
            return
        scene = depsgraph.scene
        layer = depsgraph.view_layer.name
        full_w, full_h = self.resolution_x, self.resolution_y
        x, y, w, h = border_rect(scene.render, full_w, full_h)
        if w <= 0 or h <= 0 or full_w <= 0 or full_h <= 0:
            self._fail("photonbridge: the image is %dx%d pixels (resolution %dx%d at %d%%, border %dx%d); nothing "
                       "to render" % (full_w, full_h, scene.render.resolution_x, scene.render.resolution_y,
                                      scene.render.resolution_percentage, w, h))
            return
        report = self.handoff.get("report")
        if report is not None:
            for warning in report.warnings:
                self.report({'WARNING'}, "photonbridge: " + warning)
            self.update_stats("", "photonbridge: scene written (%d triangles, %.2f s)"
                              % (report.triangles, report.seconds))
        exe = self.exe
        for name, ch, chan_id, _ in PASSES:
            self.add_pass(name, ch, chan_id)
        if "sequence" in self.handoff:
            self._render_sequence_frame(exe, depsgraph, layer, full_w, full_h, w, h)
            return
        folder = self.handoff["folder"]
        out = os.path.join(folder, "render.exr")
        preview = os.path.join(folder, "preview.exr")
        s = scene.photonbridge
        result = self.begin_result(0, 0, w, h, layer=layer)
        argv = [exe, "render", self.handoff["path"], "-o", out, "--width", str(full_w), "--height", str(full_h),
                "--blender-layer", layer, "--blender-passes", result_passes(result), "--progress-lines",
                "--preview", preview, "--preview-interval", "%g" % s.preview_interval] + settings.cli_args(s)
        if (x, y, w, h) != (0, 0, full_w, full_h):
            argv += ["--crop", "%d,%d,%d,%d" % (x, y, w, h)]
        self._run(argv, out, result)

    def _run(self, argv, out, result):
        """Runs the CLI, showing its previews in `result`; loads the final
        EXR into it and ends it (cancelled on a failure or test_break)."""
        t0 = time.perf_counter()
        try:
            run = cli.start(argv)  # a job of the session kept between renders
        except OSError as e:
            self.end_result(result, cancel=True)
            self._fail("photonbridge: could not start %s: %s" % (argv[0], e))
            return
        try:
            while run.running():
                for ev in run.poll():
                    self._progress(ev, t0)
                    if ev.get("event") == "iteration" and ev.get("preview"):
                        result.load_from_file(ev["preview"])
                        self.update_result(result)
                if self.test_break():
                    rc = run.cancel()
                    self.end_result(result, cancel=True)
                    self.update_stats("", "photonbridge: cancelled (exit %d)" % rc)
                    return
                time.sleep(POLL_S)
            rc = run.finish()
        except KeyboardInterrupt:
            # Ctrl-C where Python owns SIGINT (Blender as a Python module,
            # whose test_break() nothing sets): a cancel, as Esc is in
            # Blender. Raised on into Blender's render callback it crashed
            # the module (SIGSEGV).
            # Reported as an error: with nothing setting Blender's break
            # flag, a silently cancelled result is still saved, and Blender
            # 4.5's module crashes writing it (measured: SIGSEGV in
            # render.render(write_still=True)).
            rc = run.cancel()
            self.end_result(result, cancel=True)
            self._remove_handoff()
            self._fail("photonbridge: cancelled (Ctrl-C; exit %d)" % rc)
            return
        except BaseException:
            run.cancel()
            self.end_result(result, cancel=True)
            self._remove_handoff()
            raise
        for m in run.warnings():
            self.report({'WARNING'}, m)
        if rc != 0 or not os.path.isfile(out):
            self.end_result(result, cancel=True)
            line = run.error_line() or "no message"
            self._fail("%s (exit %d)" % (line, rc) if rc else "photonbridge: no image was written: " + line)
            return
        result.load_from_file(out)
        self.end_result(result)
        self.update_progress(1.0)
        self.update_stats("", "photonbridge: done in %.1f s" % (time.perf_counter() - t0))

    def _progress(self, ev, t0):
        kind = ev.get("event")
        if kind == "stage":
            self.update_stats("", "photonbridge: scene %s (%.1f s)" % (ev.get("stage"), ev.get("elapsed_s", 0)))
        elif kind == "iteration":
            k, n = ev.get("iteration", 0), max(1, ev.get("iterations", 1))
            self.update_progress(min(1.0, k / n))
            self.update_stats("", "photonbridge: photon map %d/%d, %d/%d samples, %.1f s"
                              % (k, n, ev.get("samples", 0), ev.get("spp", 0), time.perf_counter() - t0))
        elif kind == "frame":
            self.update_stats("", "photonbridge: frame %d (%d/%d)" % (ev.get("frame", 0), ev.get("index", 0) + 1,
                                                                    ev.get("frames", 1)))

    # ---- animation as one sequence -------------------------------------------------

    def _render_sequence_frame(self, exe, depsgraph, layer, full_w, full_h, w, h):
        scene = depsgraph.scene
        key = self.handoff["sequence"]
        if self.handoff.get("new"):
            if (w, h) != (full_w, full_h):
                self._fail("photonbridge: a render border is not supported with 'Render Animation as One "
                           "Sequence'; turn one of them off")
                return
            try:
                report = anim.write_sequence_gltf(self, depsgraph, self.handoff["path"], self.camera_override)
            except Exception as e:
                self._fail("photonbridge: the animation could not be written: %s: %s" % (type(e).__name__, e))
                return
            for warning in report.warnings:
                self.report({'WARNING'}, "photonbridge: " + warning)
            seq = {"folder": self.handoff["folder"], "running": True, "frames": {}}
            first, last = scene.frame_start, scene.frame_end
            pattern = os.path.join(seq["folder"], "frame_######.exr")
            s = scene.photonbridge
            # Sequence frame i is at t = i fps_base / fps (anim.py's key
            # times from frame_start): Blender's frame first + i.
            probe = self.begin_result(0, 0, w, h, layer=layer)
            passes = result_passes(probe)
            self.end_result(probe, cancel=True)
            argv = [exe, "render", self.handoff["path"], "-o", pattern, "--width", str(full_w), "--height",
                    str(full_h), "--frames", "%d:%d" % (0, last - first),
                    "--fps", "%.9g" % (scene.render.fps / scene.render.fps_base), "--blender-layer", layer,
                    "--blender-passes", passes, "--progress-lines"] + settings.cli_args(s, sequence=True)
            try:
                seq["run"] = cli.Run(argv)
            except OSError as e:
                self._fail("photonbridge: could not start %s: %s" % (exe, e))
                return
            seq["first"] = first
            _sequence[key] = seq
        seq = _sequence.get(key)
        if not seq:
            self._fail("photonbridge: the animation sequence is not running")
            return
        run = seq["run"]
        index = scene.frame_current - seq["first"]
        t0 = time.perf_counter()
        while True:
            for ev in run.poll():
                if ev.get("event") == "frame":
                    seq["frames"][ev["index"]] = ev["output"]
                self._progress(ev, t0)
            if index in seq["frames"]:
                break
            if not run.running():
                run.finish()
                for ev in run.events:
                    if ev.get("event") == "frame":
                        seq["frames"][ev["index"]] = ev["output"]
                if index in seq["frames"]:
                    break
                seq["running"] = False
                self._fail("%s (exit %s)" % (run.error_line() or "photonbridge: the sequence stopped",
                                             run.proc.returncode))
                self._end_sequence(key)
                return
            if self.test_break():
                run.cancel()
                self._end_sequence(key)
                return
            time.sleep(POLL_S)
        result = self.begin_result(0, 0, w, h, layer=layer)
        result.load_from_file(seq["frames"][index])
        self.end_result(result)
        self.update_progress(1.0)
        if scene.frame_current + max(1, scene.frame_step) > scene.frame_end:  # Blender's last frame
            run.finish()
            self._end_sequence(key)

    def _end_sequence(self, key):
        seq = _sequence.pop(key, None)
        if seq:
            if seq["run"].running():
                seq["run"].cancel()
            shutil.rmtree(seq["folder"], ignore_errors=True)


def stop_sequences():
    """Ends every running sequence (the add-on unregistered, Blender
    exiting): no CLI outlives Blender."""
    for key in list(_sequence):
        seq = _sequence.pop(key)
        if seq.get("run") and seq["run"].running():
            seq["run"].cancel()
        shutil.rmtree(seq["folder"], ignore_errors=True)


classes = (PhotonbridgeRenderEngine,)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    atexit.register(stop_sequences)
    atexit.register(cli.stop_session)
    viewport.register()


def unregister():
    viewport.unregister()
    atexit.unregister(stop_sequences)
    stop_sequences()
    atexit.unregister(cli.stop_session)
    cli.stop_session()
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
