#!/usr/bin/env python3
"""photonbridge serve, one part a run:

  protocol  the session over stdin/stdout: the ready line; a camera (view and
            projection matrices) and a frame (its file: header, size,
            number, not black); a malformed line, an unknown command, an
            unknown field and a bad value each get an error reply naming it
            (the line number, the command) and the session goes on; a new
            resolution gives frames of that size; a reload of a missing file
            is an error and the old scene stays; a reload of the file works;
            stream gives refining frame events up to max_passes; EOF on stdin
            ends the process (exit 0) and removes its frame file
  still     after a camera request (a camera moved and turned from the
            file's), N frames are the last frame of `render --frames 0:N-1`
            of a copy of the file with that camera as its own (same settings
            and seed): every channel of display's PNGs within one 8-bit step
  tracer    the photon tracer (render --tracer): serve --tracer images
            renders with seed 003's environment maps (the frame reply names
            the tracer and its miss rate); a "settings" request switches to
            bvh and back, a bad tracer name is an error reply; the images
            frame's mean within 10 % of the bvh frame's (8 maps of 64^2)
  kill      a client that starts serve, streams and is SIGKILLed leaves no
            process (serve sees EOF, ends after the frame it was rendering)
            and no frame file; the same with --socket and a client that
            disconnects (the socket, bound under umask 000, is 0600)
  private   what a session leaves on the machine is the user's alone: the
            frames live in a folder of the session's own under the base
            (/dev/shm, else $TMPDIR, else /tmp), made by mkdtemp, 0700 and
            owned by the user; every file in it (frames, exr frames, a
            temporary held by PB_TEST_HOLD_OUTPUT) is 0600 with umask 000
            in serve's environment; symlinks planted at the old predictable
            names (photonbridge-serve-PID.rgba32f and its .tmp.PID) are not
            followed (their target is untouched); nothing is left after EOF,
            SIGINT or SIGTERM (the latter while a temporary exists); a base
            folder that is missing or not a folder is a one-line error naming
            it, a non-zero exit and no ready line

Exit 77 (skip) where no Vulkan device is usable.
usage: serve_check.py PHOTONBRIDGE ROOT OUTDIR PART
"""
import json
import math
import os
import select
import shutil
import signal
import socket
import stat
import subprocess
import sys
import time

from pbcheck import debian_python

try:
    import numpy as np
    from PIL import Image
except ImportError:  # pyenv's python without Debian's packages
    debian_python("serve_check")

EXE, ROOT, OUT, PART = sys.argv[1:5]
SCENE = os.path.join(ROOT, "samples/cornell_box/cornell_box.gltf")
W, H = 64, 64
SETTINGS = ["--width", str(W), "--height", str(H), "--photons", "32768", "--seed", "7"]
os.makedirs(OUT, exist_ok=True)


def fail(msg):
    print("serve_check %s: FAIL: %s" % (PART, msg))
    sys.exit(1)


class Serve:
    def __init__(self, args, env=None, wrap=()):
        self.p = subprocess.Popen(list(wrap) + [EXE, "serve"] + args, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True, bufsize=1, env=env)
        self.ready = self.read(120)
        if self.ready.get("event") != "ready":
            fail("no ready line: %r; stderr: %s" % (self.ready, self.p.stderr.read()))

    def send(self, obj_or_text):
        line = obj_or_text if isinstance(obj_or_text, str) else json.dumps(obj_or_text)
        self.p.stdin.write(line + "\n")
        self.p.stdin.flush()

    def read(self, timeout=120):
        r, _, _ = select.select([self.p.stdout], [], [], timeout)
        if not r:
            fail("no reply within %d s" % timeout)
        line = self.p.stdout.readline()
        if not line:
            fail("serve closed its output; stderr: %s" % self.p.stderr.read())
        return json.loads(line)

    def ask(self, obj_or_text, timeout=120):
        self.send(obj_or_text)
        return self.read(timeout)


def read_frame(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"PBFRAME1":
        fail("%s: no PBFRAME1 header" % path)
    w, h, ch, zero = np.frombuffer(data, "<u4", 4, 8)
    frame = int(np.frombuffer(data, "<u8", 1, 24)[0])
    px = np.frombuffer(data, "<f4", int(w * h * ch), 32).reshape(h, w, ch)
    return int(w), int(h), frame, px


def quat_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def camera_request(translation, rotation, yfov, znear, zfar, aspect):
    """The "camera" request of a glTF camera node (TRS) and its projection."""
    R = quat_matrix(rotation)
    V = np.eye(4)
    V[:3, :3] = R.T
    V[:3, 3] = -R.T @ np.asarray(translation, float)
    f = 1 / math.tan(yfov / 2)
    P = np.zeros((4, 4))
    P[0, 0], P[1, 1] = f / aspect, f
    P[2, 2], P[2, 3] = -(zfar + znear) / (zfar - znear), -2 * zfar * znear / (zfar - znear)
    P[3, 2] = -1
    return {"cmd": "camera", "view": V.ravel().tolist(), "projection": P.ravel().tolist()}


def check_device():
    p = subprocess.run([EXE, "info", "--devices"], capture_output=True, text=True, timeout=120)
    if p.returncode == 12:  # PB_ERR_NO_DEVICE (other failures are the test's to see)
        print("serve_check: SKIP: no usable Vulkan device (%s)" % (p.stderr.strip().splitlines() or ["?"])[-1])
        sys.exit(77)


def expect_error(s, line, needle):
    r = s.ask(line)
    if r.get("ok") is not False or needle not in r.get("error", ""):
        fail("%r: expected an error containing %r, got %r" % (line, needle, r))
    print("serve_check protocol: %s -> %s" % (line[:60] if isinstance(line, str) else line, r["error"]))
    return r


def part_protocol():
    s = Serve([SCENE] + SETTINGS + ["-q"])
    if s.ready.get("width") != W or s.ready.get("height") != H or s.ready.get("cameras") != 1:
        fail("ready line %r" % s.ready)
    cam = camera_request([0, 1, 3.9], [0, 0, 0, 1], 0.6911112070083618, 0.05, 200, 1.0)
    cam["id"] = 1
    r = s.ask(cam)
    if r != {"reply": "camera", "id": 1, "ok": True}:
        fail("camera reply %r" % r)
    r = s.ask({"cmd": "frame", "id": "f0"})
    if r.get("reply") != "frame" or r.get("id") != "f0" or not r.get("ok") or r.get("frame") != 0:
        fail("frame reply %r" % r)
    w, h, n, px = read_frame(r["path"])
    if (w, h, n) != (W, H, 0) or (r["width"], r["height"], r["passes"]) != (W, H, 1):
        fail("frame file %dx%d #%d, reply %r" % (w, h, n, r))
    if not (px[..., :3].mean() > 0.01) or not np.isfinite(px).all():
        fail("the frame is black or not finite (mean %g)" % px[..., :3].mean())
    print("serve_check protocol: frame 0, %dx%d, mean %.4f, %.0f ms, %d photons stored"
          % (w, h, px[..., :3].mean(), r["render_ms"], r["photons_stored"]))
    expect_error(s, "{not json", "line 3: malformed JSON at byte 2")
    expect_error(s, '{"cmd":"teleport","id":9}', 'unknown command "teleport"')
    r = expect_error(s, '{"cmd":"frame","colour":1}', 'unknown field "colour"')
    if r.get("reply") != "frame":
        fail("the error reply does not name its command: %r" % r)
    expect_error(s, '{"cmd":"resolution","width":0,"height":8}', '"width" must be an integer')
    expect_error(s, '{"cmd":"camera","view":[1,0,0],"projection":[]}', '"view" must be an array of 16')
    expect_error(s, [{"cmd": "frame"}] and '[{"cmd":"frame"}]', "JSON object")
    expect_error(s, {"cmd": "camera", "index": 3}, "the scene has 1 camera")
    expect_error(s, {"cmd": "reload", "scene": os.path.join(OUT, "missing.gltf")}, "the previous scene stays")
    # The session went on: a second frame refines the first (still camera).
    r = s.ask({"cmd": "frame"})
    if not r.get("ok") or r.get("frame") != 1 or r.get("passes") != 2 or not r.get("still"):
        fail("the frame after the errors: %r" % r)
    if s.ask({"cmd": "resolution", "width": 48, "height": 32}) != {"reply": "resolution", "ok": True}:
        fail("resolution")
    r = s.ask({"cmd": "frame"})
    w, h, n, px = read_frame(r["path"])
    if (w, h, r["passes"], n) != (48, 32, 1, 2):
        fail("after the resolution request: %dx%d passes %d frame %d" % (w, h, r["passes"], n))
    for req in ({"cmd": "time", "t": 0.5}, {"cmd": "settings", "photons": 16384, "atrous_iterations": 2},
                {"cmd": "reload"}, {"cmd": "camera", "index": 0}):
        r = s.ask(req)
        if r != {"reply": req["cmd"], "ok": True}:
            fail("%r -> %r" % (req, r))
    r = s.ask({"cmd": "stream", "on": True, "max_passes": 3})
    if r != {"reply": "stream", "ok": True}:
        fail("stream -> %r" % r)
    passes = [s.read()["passes"] for _ in range(3)]
    if passes != [1, 2, 3]:
        fail("streamed passes %r, expected [1, 2, 3]" % passes)
    # max_passes reached: nothing more comes until something changes.
    r, _, _ = select.select([s.p.stdout], [], [], 3)
    if r:
        fail("a frame after max_passes: %s" % s.p.stdout.readline())
    frame_path = s.ready["frame_path"]
    s.p.stdin.close()  # EOF ends the session
    try:
        rc = s.p.wait(60)
    except subprocess.TimeoutExpired:
        s.p.kill()
        fail("serve did not end within 60 s of EOF")
    if rc != 0:
        fail("exit %d after EOF; stderr: %s" % (rc, s.p.stderr.read()))
    if os.path.exists(frame_path):
        fail("%s is left behind" % frame_path)
    print("serve_check protocol: EOF ended the session (exit 0), frame file removed")


def part_tracer():
    s = Serve([SCENE] + SETTINGS + ["-q", "--tracer", "images", "--image-maps", "8", "--image-map-resolution", "64",
                                    "--atrous-iterations", "0"])
    means = {}
    for want in ("images", "bvh", "images"):
        if want == "bvh" or "images" in means:
            r = s.ask({"cmd": "settings", "tracer": want})
            if r != {"reply": "settings", "ok": True}:
                fail("settings tracer %s -> %r" % (want, r))
        r = s.ask({"cmd": "frame"}, timeout=300)
        if not r.get("ok") or r.get("tracer") != want:
            fail("frame with tracer %s: %r" % (want, r))
        rate = r.get("image_miss_rate")
        # 8 maps of 64^2: some of cornell_box's segments
        # meet only rejected points (its open front counts there too).
        if want == "images" and not (rate is not None and 0 <= rate < 0.5):
            fail("images tracer's miss rate %r (expected in [0, 0.5) on cornell_box)" % rate)
        if want == "bvh" and rate is not None:
            fail("the bvh tracer reports an image miss rate: %r" % r)
        _, _, _, px = read_frame(r["path"])
        means[want] = float(px[..., :3].mean())
        print("serve_check tracer: %s frame %d, mean %.4f, %d photons stored%s" %
              (want, r["frame"], means[want], r["photons_stored"],
               ", miss rate %.4f" % rate if rate is not None else ""))
    expect_error(s, {"cmd": "settings", "tracer": "kdtree"}, '"tracer" must be one of "bvh", "images"')
    # Every render setting reaches a running serve (the settings table,
    # render/settings.h): the estimator too, with its own option; a bad
    # value refuses the whole request, and the session goes on.
    r = s.ask({"cmd": "settings", "tracer": "bvh", "estimator": "knn", "knn_k": 16})
    if r != {"reply": "settings", "ok": True}:
        fail("settings estimator knn, knn_k 16 -> %r" % r)
    r = s.ask({"cmd": "frame"}, timeout=300)
    if not r.get("ok"):
        fail("frame with the knn estimator: %r" % r)
    _, _, _, px = read_frame(r["path"])
    knn = float(px[..., :3].mean())
    if not (abs(knn - means["bvh"]) / max(means["bvh"], 1e-9) < 0.10):
        fail("the knn estimator's frame mean %.4f is not within 10 %% of the LBVH gather's %.4f" % (knn, means["bvh"]))
    print("serve_check tracer: estimator knn (k 16) frame %d, mean %.4f" % (r["frame"], knn))
    expect_error(s, {"cmd": "settings", "estimator": "knn", "atrous_clip": 101}, '"atrous_clip" must be a number')
    rel = abs(means["images"] - means["bvh"]) / max(means["bvh"], 1e-9)
    # 8 maps of 64^2 store ~0.9 of the BVH's photons here (measured: the
    # mean 4 % below); 4 maps of 32^2 stored 0.45 and were 23 % below.
    if not (means["bvh"] > 0 and rel < 0.10):
        fail("the images frame's mean %.4f is %.1f %% from the bvh frame's %.4f" %
             (means["images"], 100 * rel, means["bvh"]))
    s.p.stdin.close()
    if s.p.wait(60) != 0:
        fail("exit after EOF; stderr: %s" % s.p.stderr.read())


def display(exr, png):
    p = subprocess.run([EXE, "display", exr, "-o", png], capture_output=True, text=True, timeout=300)
    if p.returncode != 0:
        fail("display %s: %s" % (exr, p.stderr))
    return np.asarray(Image.open(png).convert("RGB")).astype(np.int32)


def part_still():
    n = 3
    # The file's camera moved right, up and closer, turned 8 degrees about Y.
    t, a = [0.35, 1.1, 3.5], math.radians(8)
    q = [0, math.sin(a / 2), 0, math.cos(a / 2)]
    with open(SCENE) as f:
        doc = json.load(f)
    for node in doc["nodes"]:
        if "camera" in node:
            node["translation"], node["rotation"] = t, q
    for b in doc.get("buffers", []) + doc.get("images", []):  # the copy lives in OUT, with its files
        if "uri" in b and not b["uri"].startswith("data:"):
            shutil.copy(os.path.join(os.path.dirname(SCENE), b["uri"]), os.path.join(OUT, b["uri"]))
    moved = os.path.join(OUT, "moved.gltf")
    with open(moved, "w") as f:
        json.dump(doc, f)
    s = Serve([SCENE] + SETTINGS + ["--format", "exr", "-q"])
    r = s.ask(camera_request(t, q, 0.6911112070083618, 0.05, 200, 1.0))
    if not r.get("ok"):
        fail("camera: %r" % r)
    for i in range(n):
        r = s.ask({"cmd": "frame"})
        if not r.get("ok") or r["passes"] != i + 1:
            fail("frame %d: %r" % (i, r))
    served = os.path.join(OUT, "served.exr")
    shutil.copy(r["path"], served)
    s.ask({"cmd": "quit"})
    s.p.wait(60)
    p = subprocess.run([EXE, "render", moved] + SETTINGS +
                       ["--frames", "0:%d" % (n - 1), "-o", os.path.join(OUT, "f_#.exr"), "-q"],
                       capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        fail("render: %s" % p.stderr)
    a = display(served, os.path.join(OUT, "served.png"))
    b = display(os.path.join(OUT, "f_%d.exr" % (n - 1)), os.path.join(OUT, "render.png"))
    d = np.abs(a - b)
    print("serve_check still: %d still frames of a moved camera, %dx%d: max difference %d, mean %.4f (8-bit "
          "steps), mean level %.1f" % (n, W, H, d.max(), d.mean(), a.mean()))
    if d.max() > 1:
        fail("serve's frame %d differs from render --frames' by up to %d steps (at most 1)" % (n - 1, d.max()))
    if a.mean() < 20:
        fail("the picture is black (mean level %.1f)" % a.mean())
    # The file's own camera renders another picture: the request moved it.
    p = subprocess.run([EXE, "render", SCENE] + SETTINGS + ["--frames", "0:%d" % (n - 1), "-o",
                       os.path.join(OUT, "g_#.exr"), "-q"], capture_output=True, text=True, timeout=600)
    c = display(os.path.join(OUT, "g_%d.exr" % (n - 1)), os.path.join(OUT, "file_camera.png"))
    if np.abs(a - c).mean() < 5:
        fail("the moved camera's picture equals the file camera's (mean difference %.2f)" % np.abs(a - c).mean())


CLIENT = r"""
import json, os, subprocess, sys, time
p = subprocess.Popen(sys.argv[1:], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1)
ready = json.loads(p.stdout.readline())
p.stdin.write('{"cmd":"stream","on":true}\n'); p.stdin.flush()
p.stdout.readline(); p.stdout.readline()   # the stream reply and a first frame: serve is busy streaming
print(json.dumps({"pid": p.pid, "frame_path": ready["frame_path"]}), flush=True)
time.sleep(600)
"""


def gone(pid, timeout):
    t0 = time.time()
    while time.time() - t0 < timeout:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return True
        # A zombie is gone too: its parent (the killed client) was reaped and
        # init reaps it; /proc/PID/stat says Z until then.
        try:
            with open("/proc/%d/stat" % pid) as f:
                if f.read().split(")")[-1].split()[0] == "Z":
                    return True
        except OSError:
            return True
        time.sleep(0.2)
    return False


def part_kill():
    c = subprocess.Popen([sys.executable, "-c", CLIENT, EXE, "serve", SCENE] + SETTINGS + ["-q"],
                         stdout=subprocess.PIPE, text=True)
    r, _, _ = select.select([c.stdout], [], [], 180)
    if not r:
        c.kill()
        fail("the client got no frame")
    info = json.loads(c.stdout.readline())
    c.send_signal(signal.SIGKILL)
    c.wait()
    t0 = time.time()
    if not gone(info["pid"], 120):
        os.kill(info["pid"], signal.SIGKILL)
        fail("serve (pid %d) outlived its killed client by 120 s" % info["pid"])
    print("serve_check kill: serve ended %.1f s after its client was killed" % (time.time() - t0))
    if os.path.exists(os.path.dirname(info["frame_path"])):
        fail("%s is left behind" % os.path.dirname(info["frame_path"]))
    # --socket: one client; its disconnect ends the session.
    path = os.path.join(OUT, "serve.sock")
    p = subprocess.Popen([EXE, "serve", SCENE, "--socket", path] + SETTINGS + ["-q"], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, preexec_fn=lambda: os.umask(0))
    k = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    for _ in range(600):
        try:
            k.connect(path)
            break
        except OSError:
            time.sleep(0.1)
    else:
        p.kill()
        fail("no socket at %s" % path)
    mode = os.lstat(path).st_mode
    if not stat.S_ISSOCK(mode) or stat.S_IMODE(mode) != 0o600:
        p.kill()
        fail("the socket %s is mode %o under umask 000 (expected a socket, 0600)" % (path, stat.S_IMODE(mode)))
    f = k.makefile("rw")
    ready = json.loads(f.readline())
    f.write('{"cmd":"frame"}\n')
    f.flush()
    r = json.loads(f.readline())
    if ready.get("event") != "ready" or not r.get("ok") or r.get("frame") != 0:
        fail("socket session: %r, %r" % (ready, r))
    f.close()
    k.close()
    try:
        rc = p.wait(60)
    except subprocess.TimeoutExpired:
        p.kill()
        fail("serve --socket did not end within 60 s of the client's disconnect")
    if rc != 0 or os.path.exists(path) or os.path.exists(os.path.dirname(ready["frame_path"])):
        fail("serve --socket: exit %d, socket left %s, frame left %s" % (rc, os.path.exists(path),
                                                                       os.path.exists(ready["frame_path"])))
    print("serve_check kill: --socket session ended with its client (exit 0, socket and frame removed)")


def serve_base():
    """The base serve picks without --frame-dir (serve.c's frame_dir)."""
    if os.path.isdir("/dev/shm") and os.access("/dev/shm", os.W_OK):
        return "/dev/shm"
    return os.environ.get("TMPDIR") or "/tmp"


def check_private_dir(base, frame_path):
    """The session folder of `frame_path`: a fresh folder in `base`, 0700,
    the user's; every entry a regular file, 0600, the user's. The folder."""
    d = os.path.dirname(frame_path)
    if os.path.realpath(os.path.dirname(d)) != os.path.realpath(base):
        fail("the frame %s is not in a folder of its own in %s" % (frame_path, base))
    if not os.path.basename(d).startswith("photonbridge-serve-"):
        fail("the session folder %s" % d)
    st = os.lstat(d)
    if not stat.S_ISDIR(st.st_mode) or stat.S_IMODE(st.st_mode) != 0o700 or st.st_uid != os.getuid():
        fail("the session folder %s: mode %o, owner %d (expected a folder, 0700, %d)"
             % (d, stat.S_IMODE(st.st_mode), st.st_uid, os.getuid()))
    names = os.listdir(d)
    for n in names:
        st = os.lstat(os.path.join(d, n))
        if not stat.S_ISREG(st.st_mode) or stat.S_IMODE(st.st_mode) != 0o600 or st.st_uid != os.getuid():
            fail("%s/%s: mode %o, owner %d (expected a regular file, 0600, %d)"
                 % (d, n, stat.S_IMODE(st.st_mode), st.st_uid, os.getuid()))
    return d, names


def end_with(s, how, want_rc, d):
    if how == "eof":
        s.p.stdin.close()
    else:
        s.p.send_signal(how)
    try:
        rc = s.p.wait(60)
    except subprocess.TimeoutExpired:
        s.p.kill()
        fail("serve did not end within 60 s (%s)" % how)
    if rc != want_rc:
        fail("exit %d after %s (expected %d); stderr: %s" % (rc, how, want_rc, s.p.stderr.read()))
    if os.path.exists(d):
        fail("%s is left behind after %s: %r" % (d, how, os.listdir(d)))


def part_private():
    base = serve_base()
    victim = os.path.join(OUT, "victim.txt")
    with open(victim, "w") as f:
        f.write("untouched\n")
    # The wrapper shell plants symlinks at the names serve used to write
    # (its PID is serve's: exec keeps it) and sets umask 000 for serve.
    plant = ('umask 000; ln -s "$1" "$2/photonbridge-serve-$$.rgba32f"; '
             'ln -s "$1" "$2/photonbridge-serve-$$.rgba32f.tmp.$$"; shift 2; exec "$@"')
    s = Serve([SCENE] + SETTINGS + ["-q"], wrap=["sh", "-c", plant, "sh", victim, base])
    planted = [os.path.join(base, "photonbridge-serve-%d.rgba32f" % s.p.pid),
               os.path.join(base, "photonbridge-serve-%d.rgba32f.tmp.%d" % (s.p.pid, s.p.pid))]
    try:
        d, _ = check_private_dir(base, s.ready["frame_path"])
        for i in range(2):
            r = s.ask({"cmd": "frame"})
            if not r.get("ok") or r.get("path") != s.ready["frame_path"]:
                fail("frame %d: %r" % (i, r))
            read_frame(r["path"])
        _, names = check_private_dir(base, s.ready["frame_path"])
        print("serve_check private: session folder %s (0700) holds %r (0600) under umask 000" % (d, names))
        with open(victim) as f:
            if f.read() != "untouched\n":
                fail("the symlink target %s was written through" % victim)
        for link in planted:
            if not os.path.islink(link) or os.readlink(link) != victim:
                fail("the planted symlink %s was replaced or removed" % link)
        print("serve_check private: symlinks at the old names not followed, their target untouched")
        end_with(s, "eof", 0, d)
    finally:
        for link in planted:
            if os.path.islink(link):
                os.unlink(link)
    print("serve_check private: EOF removed the session folder")

    # exr frames (OpenEXR writes the temporary): 0600 too; SIGINT cleans up.
    s = Serve([SCENE] + SETTINGS + ["-q", "--format", "exr"], wrap=["sh", "-c", 'umask 000; exec "$@"', "sh"])
    r = s.ask({"cmd": "frame"})
    if not r.get("ok") or not r["path"].endswith(".exr"):
        fail("exr frame: %r" % r)
    d, names = check_private_dir(base, r["path"])
    end_with(s, signal.SIGINT, 130, d)
    print("serve_check private: exr frames %r 0600; SIGINT removed the session folder" % names)

    # SIGTERM while a frame's temporary exists (the test hook holds it).
    env = dict(os.environ, PB_TEST_HOLD_OUTPUT="1")
    s = Serve([SCENE] + SETTINGS + ["-q"], env=env, wrap=["sh", "-c", 'umask 000; exec "$@"', "sh"])
    s.send({"cmd": "frame"})
    r, _, _ = select.select([s.p.stderr], [], [], 120)
    line = s.p.stderr.readline() if r else ""
    if "holding " not in line:
        s.p.kill()
        fail("no test-hook line on stderr: %r" % line)
    tmp = line.split("holding ", 1)[1].strip()
    d, names = check_private_dir(base, s.ready["frame_path"])
    if os.path.dirname(tmp) != d or os.path.basename(tmp) not in names:
        s.p.kill()
        fail("the temporary %s is not in the session folder %s (%r)" % (tmp, d, names))
    end_with(s, signal.SIGTERM, 143, d)
    print("serve_check private: temporary %s 0600; SIGTERM removed the session folder" % os.path.basename(tmp))

    # A base that cannot hold the folder: one line naming it, no session.
    not_dir = os.path.join(OUT, "a_file")
    open(not_dir, "w").close()
    for bad in (os.path.join(OUT, "missing"), not_dir):
        p = subprocess.run([EXE, "serve", SCENE, "--frame-dir", bad] + SETTINGS + ["-q"], capture_output=True,
                           text=True, timeout=300, stdin=subprocess.DEVNULL)
        err = p.stderr.strip().splitlines()
        if p.returncode == 0 or len(err) != 1 or bad not in err[0] or '"event":"ready"' in p.stdout:
            fail("--frame-dir %s: exit %d, stderr %r, stdout %r" % (bad, p.returncode, p.stderr, p.stdout))
        print("serve_check private: --frame-dir %s: exit %d, %s" % (os.path.basename(bad), p.returncode, err[0]))
    if os.listdir(OUT) and any(n.startswith("photonbridge-serve-") for n in os.listdir(OUT)):
        fail("a session folder was left in %s" % OUT)


def part_noise():
    """A stream with a noise threshold rests once the still run's own noise
    estimate reaches it: every frame says "noise" (null before two passes),
    the last one at most the threshold, then nothing until something
    changes; a camera move starts the estimate afresh. The threshold is
    serve's --noise-threshold, which a stream request without one takes."""
    t = 0.06
    s = Serve([SCENE] + SETTINGS + ["--noise-threshold", str(t), "-q"])
    expect_error(s, {"cmd": "stream", "on": True, "noise_threshold": 0.9}, '"noise_threshold" must be a number in')
    r = s.ask({"cmd": "stream", "on": True})
    if r != {"reply": "stream", "ok": True}:
        fail("stream -> %r" % r)
    frames = []
    while True:
        f = s.read()
        frames.append(f)
        if f.get("noise") is not None and f["noise"] <= t:
            break
        if len(frames) > 200:
            fail("no rest after 200 passes: noise %r" % [x.get("noise") for x in frames[-5:]])
    if "noise" not in frames[0] or frames[0]["noise"] is not None or frames[-1]["passes"] < 2:
        fail("frames %r" % [(x.get("passes"), x.get("noise")) for x in frames])
    r, _, _ = select.select([s.p.stdout], [], [], 3)
    if r:
        fail("a frame after the noise threshold was reached: %s" % s.p.stdout.readline())
    print("serve_check noise: rested after %d passes at noise %.4f (threshold %g); estimates %s"
          % (frames[-1]["passes"], frames[-1]["noise"], t,
             [round(x["noise"], 4) for x in frames if x.get("noise") is not None]))
    cam = camera_request([0, 1.1, 3.9], [0, 0, 0, 1], 0.69, 0.05, 200, 1.0)
    if s.ask(cam) != {"reply": "camera", "ok": True}:
        fail("camera")
    f = s.read()
    if f.get("passes") != 1 or f.get("noise", 0) is not None:
        fail("after the camera moved: %r" % f)
    s.p.stdin.close()
    s.p.wait(60)


check_device()
{"noise": part_noise, "protocol": part_protocol, "still": part_still, "tracer": part_tracer, "kill": part_kill,
 "private": part_private}[PART]()
print("serve_check %s: OK" % PART)
