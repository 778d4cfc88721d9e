"""The viewport (RENDERED shading) through `photonbridge serve`.

view_update (engine.py) hands the scene over once: the add-on's writer
writes the viewport depsgraph to glTF in a temporary folder and starts one
`photonbridge serve` on it, whose JSON lines are read on threads (never a
blocking read on Blender's thread). Later view_updates send what changed:
an object, mesh, material, light or world edit rewrites the file and sends
"reload"; a change of the photonbridge settings sends "settings". view_draw
sends the region's view and window matrices ("camera", Blender's axes) and
its size ("resolution", divided by the scene's viewport Pixel Size) when they
changed, turns streaming on, and draws the newest frame (a float RGBA file
in serve's private session folder, scene-linear; its path is the one the
frame reply names, never guessed) as a texture inside bind_display_space_shader /
unbind_display_space_shader, so Blender's view transform, look, exposure
and gamma apply as they do to Cycles' viewport. A timer (bpy.app.timers)
tags a redraw whenever serve's output has lines waiting, so the picture
refines pass after pass without a busy redraw loop. Errors become the viewport's status line and one
report; nothing here blocks or raises into Blender. The serve process ends
with the engine (free(), __del__), when its stdin closes, and at exit."""
import atexit
import json
import os
import queue
import shutil
import struct
import subprocess
import tempfile
import threading
import weakref

import bpy

from . import cli, settings, writer

# Still passes the viewport refines before it rests: Sampling > Viewport >
# Samples (viewport_samples, as Cycles' viewport samples; this without a
# scene); PHOTONBRIDGE_VIEWPORT_PASSES overrides it.
DEFAULT_PASSES = 1024
POLL_S = 0.1  # how often the redraw timer looks for serve's lines
HEADER = struct.Struct("<8sIIIIQ")  # protocol.h: "PBFRAME1", w, h, channels, 0, frame


_sessions = weakref.WeakSet()
# The last error the viewport showed (tests read it).
last_error = {}
# The last frame view_draw drew: serve's frame line with "width", "height",
# the serve process's "pid" and the "reloads" sent so far (tests read it).
last_drawn = {}


def max_passes(scene=None):
    default = DEFAULT_PASSES
    if scene is not None:
        default = int(getattr(scene.photonbridge, "viewport_samples", DEFAULT_PASSES))
    try:
        return max(0, int(os.environ.get("PHOTONBRIDGE_VIEWPORT_PASSES", default)))
    except ValueError:
        return default


def noise_threshold(scene):
    """The viewport's noise threshold (serve's stream rests at it), 0: none."""
    s = scene.photonbridge
    return float("%.6g" % s.viewport_noise_threshold) if s.use_viewport_noise_threshold else 0.0


def read_frame(path):
    """(width, height, frame number, float32 RGBA bytes bottom row first)
    of a frame file, or None when it is not one."""
    import numpy as np
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError:  # serve ended and removed it: the next poll says why
        return None
    if len(data) < HEADER.size:
        return None
    magic, w, h, ch, _, frame = HEADER.unpack_from(data)
    if magic != b"PBFRAME1" or ch != 4 or len(data) < HEADER.size + 16 * w * h:
        return None
    px = np.frombuffer(data, dtype=np.float32, count=w * h * 4, offset=HEADER.size).reshape(h, w, 4)
    px = np.nan_to_num(px[::-1], nan=0.0, posinf=0.0, neginf=0.0)  # GL textures start at the bottom row
    return w, h, frame, np.ascontiguousarray(px, dtype=np.float32)


class Session:
    """One `photonbridge serve` and its reader threads."""

    def __init__(self, argv):
        self.argv = argv
        self.q = queue.Queue()
        self.proc = subprocess.Popen(argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True, bufsize=1, errors="replace")
        self.stderr = []
        self.ready = False
        self.cpu_device = None
        self.frame = None      # the newest frame line
        self.error = None      # the newest error (a reply with ok false, or the process's last line)
        self.threads = [threading.Thread(target=t, args=(st,), daemon=True)
                        for t, st in ((self._read_out, self.proc.stdout), (self._read_err, self.proc.stderr))]
        for t in self.threads:
            t.start()
        _sessions.add(self)

    def _read_out(self, stream):
        for line in stream:
            try:
                self.q.put(json.loads(line))
            except ValueError:
                self.q.put({"ok": False, "error": "photonbridge serve: not a JSON line: " + line.strip()[:200]})
        stream.close()

    def _read_err(self, stream):
        for line in stream:
            line = line.rstrip("\n")
            if line:
                self.stderr.append(line)
                del self.stderr[:-50]
        stream.close()

    def alive(self):
        return self.proc.poll() is None

    def send(self, msg):
        if not self.alive():
            return False
        try:
            self.proc.stdin.write(json.dumps(msg) + "\n")
            self.proc.stdin.flush()
            return True
        except (BrokenPipeError, OSError, ValueError):
            return False

    def poll(self):
        """Takes the lines that came; True when a new frame is among them."""
        new = False
        while True:
            try:
                m = self.q.get_nowait()
            except queue.Empty:
                break
            if m.get("event") == "ready":
                self.ready = True
                # A CPU Vulkan device (lavapipe): said in the status line.
                self.cpu_device = m.get("device") if m.get("device_type") == "cpu" else None
            elif not m.get("ok", False):
                self.error = m.get("error", "photonbridge serve: error")
            elif m.get("reply") == "frame" or m.get("event") == "frame":
                self.frame, new = m, True
        if not self.alive() and not self.error:
            for t in self.threads:  # its last lines may still be in the pipes
                t.join(1.0)
            last = [s for s in self.stderr if ": error: " in s] or self.stderr[-1:]
            self.error = (last[-1] if last else "photonbridge serve ended") + " (exit %s)" % self.proc.returncode
        return new

    def stop(self):
        """EOF on its stdin ends it (after the frame it is rendering); then
        SIGTERM, SIGKILL. Never leaves the process behind."""
        try:
            self.proc.stdin.close()
        except (OSError, ValueError):
            pass
        for sig in (None, self.proc.terminate, self.proc.kill):
            if sig:
                try:
                    sig()
                except ProcessLookupError:
                    break
            try:
                self.proc.wait(5.0)
                break
            except subprocess.TimeoutExpired:
                continue
        _sessions.discard(self)


class Viewport:
    """An engine's viewport state (engine.viewport)."""

    def __init__(self):
        self.session = None
        self.folder = None
        self.path = None
        self.failed = None       # a message: nothing more is tried until the next edit
        self.reported = None
        self.sent_camera = None
        self.sent_size = None
        self.sent_settings = None
        self.started_fixed = None
        self.streaming = False
        self.sent_passes = None
        self.reloads = 0         # scene edits sent since the start
        self.texture = None
        self.texture_frame = None
        self.status = ""

    # ---- the hand-off ---------------------------------------------------------

    def _write(self, depsgraph):
        if self.folder is None:
            self.folder = tempfile.mkdtemp(prefix="photonbridge_view_")
            self.path = os.path.join(self.folder, "scene.gltf")
        return writer.write_gltf(depsgraph, self.path)

    def update(self, engine, context, depsgraph):
        scene = depsgraph.scene
        try:
            if self.session is None or not self.session.alive():
                self.stop()
                self.failed = None
                self._start(engine, context, depsgraph)
                return
            if fixed_args(scene) != self.started_fixed:
                # a setting serve's "settings" request does not take (first
                # bounce, bounces limit, caustic filter, device): a new serve
                self.stop()
                self.failed = None
                self._start(engine, context, depsgraph)
                return
            if scene_edited(depsgraph):
                self._write(depsgraph)
                self.session.send({"cmd": "reload"})
                self.reloads += 1
            self._send_settings(scene)
        except Exception as e:  # never raise into Blender: the viewport says what went wrong
            self._fail(engine, "photonbridge viewport: %s: %s" % (type(e).__name__, e))

    def _start(self, engine, context, depsgraph):
        scene = depsgraph.scene
        try:
            exe = cli.find_binary(_prefs_binary(context))
        except cli.BinaryNotFound as e:
            self._fail(engine, str(e))
            return
        report = self._write(depsgraph)
        for w in report.warnings:
            engine.report({'WARNING'}, "photonbridge: " + w)
        w, h = self._size(context, scene)
        argv = [exe, "serve", self.path, "--width", str(w), "--height", str(h)] + serve_args(scene)
        self.session = Session(argv)
        self.sent_size = (w, h)
        self.sent_settings = self._settings(scene)
        self.started_fixed = fixed_args(scene)
        bpy.app.timers.register(_redraw_timer(self), first_interval=POLL_S)

    def _settings(self, scene):
        """serve's "settings" request of the scene's photonbridge settings:
        every setting the table offers to requests (settings.request_settings)."""
        return dict(settings.request_settings(scene.photonbridge)[0], seed=int(scene.photonbridge.seed))

    def _send_settings(self, scene):
        st = self._settings(scene)
        if st != self.sent_settings:
            self.session.send(dict(cmd="settings", **st))
            self.sent_settings = st

    @staticmethod
    def _size(context, scene):
        px = scene.render.preview_pixel_size
        div = 1 if px == 'AUTO' else int(px)
        return max(1, context.region.width // div), max(1, context.region.height // div)

    # ---- drawing ----------------------------------------------------------------

    def draw(self, engine, context, depsgraph):
        import gpu
        from gpu_extras.presets import draw_texture_2d
        scene = depsgraph.scene
        s = self.session
        if s is None:
            if self.failed:
                engine.update_stats("", self.failed)
            return
        try:
            size = self._size(context, scene)
            if size != self.sent_size:
                s.send({"cmd": "resolution", "width": size[0], "height": size[1]})
                self.sent_size = size
            r3d = context.region_data
            cam = ([v for row in r3d.view_matrix for v in row], [v for row in r3d.window_matrix for v in row])
            if cam != self.sent_camera:
                s.send({"cmd": "camera", "view": cam[0], "projection": cam[1], "axes": "blender"})
                self.sent_camera = cam
            limit = (max_passes(scene), noise_threshold(scene))
            if not self.streaming or limit != self.sent_passes:
                s.send({"cmd": "stream", "on": True, "max_passes": limit[0], "noise_threshold": limit[1]})
                self.streaming, self.sent_passes = True, limit
            if s.poll() and s.frame.get("path"):
                f = read_frame(s.frame["path"])
                if f:
                    w, h, frame, px = f
                    buf = gpu.types.Buffer('FLOAT', w * h * 4, px.ravel())
                    self.texture = gpu.types.GPUTexture((w, h), format='RGBA16F', data=buf)
                    self.texture_frame = dict(s.frame, width=w, height=h, file_frame=frame)
            if s.error and s.error != self.reported:
                self.reported = s.error
                last_error["message"] = s.error
                engine.report({'ERROR'}, s.error)
            if self.texture is not None:
                gpu.state.blend_set('ALPHA_PREMULT')
                engine.bind_display_space_shader(scene)
                draw_texture_2d(self.texture, (0, 0), context.region.width, context.region.height)
                engine.unbind_display_space_shader()
                gpu.state.blend_set('NONE')
                last_drawn.clear()
                last_drawn.update(self.texture_frame, pid=s.proc.pid, reloads=self.reloads)
            passes = self.texture_frame["passes"] if self.texture_frame else 0
            if s.error:
                engine.update_stats("", "photonbridge: " + s.error)
            elif not s.ready:
                engine.update_stats("", "photonbridge: loading the scene")
            else:
                ms = self.texture_frame.get("render_ms", 0) if self.texture_frame else 0
                cpu = " (on %s, a CPU Vulkan device: slow)" % s.cpu_device if s.cpu_device else ""
                engine.update_stats("", "photonbridge: pass %d%s, %.0f ms%s" % (passes, "/%d" % limit if limit else "",
                                                                              ms, cpu))
        except Exception as e:
            self._fail(engine, "photonbridge viewport: %s: %s" % (type(e).__name__, e))

    # ---- errors and the end ---------------------------------------------------------

    def _fail(self, engine, message):
        self.failed = message
        last_error["message"] = message
        if message != self.reported:
            self.reported = message
            try:
                engine.report({'ERROR'}, message)
                engine.update_stats("", message)
            except Exception:
                pass

    def stop(self):
        if self.session is not None:
            self.session.stop()
            self.session = None
        self.streaming = False
        self.sent_passes = None
        self.sent_camera = None
        if self.folder:
            shutil.rmtree(self.folder, ignore_errors=True)
            self.folder = None


def _redraw_timer(vp):
    """A timer that tags the 3D views for a redraw when serve's output has
    lines waiting (a new frame), so that view_draw, which takes them, runs
    only when there is something to draw: no busy redraw loop on Blender's
    thread while the GPU renders. It holds no reference to the engine (a
    cycle would keep the engine's Python object, and so serve, alive after
    Blender frees the engine) and ends with the session."""
    ref = weakref.ref(vp)

    def tick():
        v = ref()
        if v is None or v.session is None:
            return None
        alive = v.session.alive()
        if not v.session.q.empty() or not alive:
            for win in bpy.context.window_manager.windows:
                for area in win.screen.areas:
                    if area.type == 'VIEW_3D':
                        area.tag_redraw()
        return POLL_S if alive else None
    return tick


def serve_args(scene):
    """serve's frame options from the photonbridge panel: render's (as a
    sequence: no time limit) with the filter passes always given, so that
    the panel's 0 is off here too (a sequence's own default is 4)."""
    args = settings.cli_args(scene.photonbridge, sequence=True, serve=True)
    if "--atrous-iterations" not in args:
        args += ["--atrous-iterations", str(scene.photonbridge.filter_passes)]
    return args


def live_options():
    """serve's options that its "settings" request changes (the table's
    rows offered to requests), and which of them are flags."""
    opts = {"--" + t["cli"]: t["kind"] == "bool" for t in settings.SETTINGS if "request" in t["surfaces"]}
    opts["--seed"] = False
    return opts


def fixed_args(scene):
    """serve_args(scene) less the options a "settings" request changes,
    plus the settings left to the renderer's own choice (a value such as
    Photon Bounces 0 cannot be sent: a change to or from it starts a new
    serve)."""
    live = live_options()
    args, out, i = serve_args(scene), [], 0
    while i < len(args):
        n = 1 if live.get(args[i], False) else 2
        if args[i] not in live:
            out += args[i:i + n]
        i += n
    return out + ["automatic:" + a for a in settings.request_settings(scene.photonbridge)[1]]


def scene_edited(depsgraph):
    """An edit that changes the picture (a move of the view never reaches
    view_update): an object, mesh, material, light, world, node tree,
    image, curve, metaball or texture whose
    geometry, transform or shading changed, or a collection changed (an
    object added, removed, hidden). Selecting, or a change of the scene's
    own settings (sent as "settings"), is none."""
    if _has_type('COLLECTION') and depsgraph.id_type_updated('COLLECTION'):
        return True
    types = tuple(getattr(bpy.types, n) for n in ("Object", "Mesh", "Material", "Light", "World", "NodeTree",
                                                  "Image", "Curve", "MetaBall", "Texture") if hasattr(bpy.types, n))
    for u in depsgraph.updates:
        if isinstance(u.id, types) and (u.is_updated_geometry or u.is_updated_transform or u.is_updated_shading):
            return True
    return False


def _has_type(t):
    # id types Blender 3.4 knows (CURVES, POINTCLOUD are newer than some builds)
    try:
        return t in bpy.types.ID.bl_rna.properties["id_type"].enum_items.keys()
    except Exception:
        return True


def _prefs_binary(context):
    addon = context.preferences.addons.get(__package__) if context else None
    return addon.preferences.binary if addon else ""


def stop_all():
    for s in list(_sessions):
        s.stop()


def register():
    atexit.register(stop_all)


def unregister():
    atexit.unregister(stop_all)
    stop_all()
