"""Running `photonbridge render` from Blender: finding the binary, and the
child process with its output read on threads (never a blocking read on
Blender's thread), progress lines parsed, and a cancel that lets the CLI
clean up (SIGINT, then SIGTERM, then SIGKILL if it does not exit). Still
renders run as jobs of a `photonbridge batch -` session kept between them
(Job), so a render after the first takes the compiled pipelines."""
import json
import os
import queue
import shlex
import shutil
import signal
import subprocess
import threading
import time

PROGRESS_PREFIX = "photonbridge progress: "
ENV_BIN = "PHOTONBRIDGE_BIN"


class BinaryNotFound(Exception):
    pass


def find_binary(pref_path):
    """The photonbridge executable: the add-on preferences' path, then
    $PHOTONBRIDGE_BIN, then PATH. Raises BinaryNotFound with one line
    saying where it looked and how to set it."""
    tried = []
    for where, path in (("the add-on preferences", pref_path), ("$" + ENV_BIN, os.environ.get(ENV_BIN, ""))):
        if path:
            path = os.path.expanduser(path)
            if os.path.isfile(path) and os.access(path, os.X_OK):
                return path
            tried.append("%s (%s: not an executable file)" % (where, path))
        else:
            tried.append("%s (not set)" % where)
    found = shutil.which("photonbridge")
    if found:
        return found
    tried.append("PATH (no 'photonbridge')")
    raise BinaryNotFound("photonbridge binary not found; looked in " + ", ".join(tried) +
                         ". Build it ('make build') and set its path in Preferences > Add-ons > photonbridge, "
                         "or set " + ENV_BIN)


def end_process(proc, signals, grace):
    """Sends each of `signals` in turn (None: only wait) until proc exits,
    waiting `grace` seconds after each."""
    for sig in signals:
        if proc.poll() is not None:
            break
        if sig is not None:
            try:
                proc.send_signal(sig)
            except ProcessLookupError:
                break
        try:
            proc.wait(grace)
        except subprocess.TimeoutExpired:
            continue


class Run:
    """A running CLI. lines(): the stderr and stdout lines so far (non-
    blocking); progress events come back parsed as dicts."""

    def __init__(self, argv, env=None):
        self.argv = argv
        self.q = queue.Queue()
        self.proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, env=env, text=True, bufsize=1,
                                     errors="replace")
        self.threads = [threading.Thread(target=self._read, args=(s,), daemon=True)
                        for s in (self.proc.stdout, self.proc.stderr)]
        for t in self.threads:
            t.start()
        self.messages = []   # non-progress lines, in order
        self.events = []

    def _read(self, stream):
        for line in stream:
            self.q.put(line.rstrip("\n"))
        stream.close()

    def _take(self, line, new):
        """One line of the CLI's: a progress event (parsed, added to
        self.events and `new`) or a message (self.messages)."""
        if line.startswith(PROGRESS_PREFIX):
            try:
                ev = json.loads(line[len(PROGRESS_PREFIX):])
            except ValueError:
                self.messages.append(line)
                return
            self.events.append(ev)
            new.append(ev)
        elif line:
            self.messages.append(line)

    def poll(self):
        """New progress events (dicts) since the last call; other lines are
        kept in self.messages."""
        new = []
        while True:
            try:
                line = self.q.get_nowait()
            except queue.Empty:
                break
            self._take(line, new)
        return new

    def running(self):
        return self.proc.poll() is None

    def finish(self, timeout=None):
        """Waits for the exit and the readers; returns the exit code."""
        rc = self.proc.wait(timeout)
        for t in self.threads:
            t.join(5)
        self.poll()
        return rc

    def cancel(self, grace=20.0):
        """SIGINT (the CLI removes its temporaries and exits 130), then
        SIGTERM and SIGKILL if it does not exit within `grace` seconds each;
        never leaves the process behind. Returns the exit code."""
        end_process(self.proc, (signal.SIGINT, signal.SIGTERM, signal.SIGKILL), grace)
        return self.finish()

    def error_line(self):
        """The CLI's one-line error ("photonbridge render: error: ..."), or
        the last line it printed."""
        for m in reversed(self.messages):
            if ": error: " in m:
                return m
        return self.messages[-1] if self.messages else ""

    def warnings(self):
        # The CLI repeats what the add-on's writer put in the extension
        # ("the Blender writer says: ..."); the engine reported those itself
        # when it wrote the scene, so they are not shown twice.
        return [m for m in self.messages
                if (": warning: " in m or "warning:" in m) and "the Blender writer says: " not in m]


# ---- a session kept between renders ------------------------------------------------

class _Session:
    """`photonbridge batch -` kept between the still renders (F12) of one
    Blender session: the Vulkan device and its compiled pipelines stay, so a
    render after the first skips pipeline creation (about 10 s of a Blender
    material scene's start on lavapipe; a pause on GPU drivers). One job at a
    time. Its stderr comes in on its stdout (one pipe: a job's messages
    arrive before its closing {"job":...} line)."""

    def __init__(self, exe, key):
        self.key = key
        self.q = queue.Queue()
        self.proc = subprocess.Popen([exe, "batch", "-"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, text=True, bufsize=1, errors="replace")
        self.thread = threading.Thread(target=self._read, daemon=True)
        self.thread.start()
        self.busy = False

    def _read(self):
        for line in self.proc.stdout:
            self.q.put(line.rstrip("\n"))
        self.proc.stdout.close()
        self.q.put(None)  # the session ended

    def alive(self):
        return self.proc.poll() is None

    def stop(self, grace=5.0):
        """Ends the session: EOF on its input (it exits when idle), then
        SIGTERM and SIGKILL if it does not."""
        try:
            self.proc.stdin.close()
        except OSError:
            pass
        end_process(self.proc, (None, signal.SIGTERM, signal.SIGKILL), grace)


_session = None
_session_lock = threading.Lock()


def _session_key(exe):
    """What a kept session must match: the binary (path, size, time) and the
    environment it was started with."""
    try:
        st = os.stat(exe)
        stamp = (st.st_size, st.st_mtime_ns, st.st_ino)
    except OSError:
        stamp = None
    return (os.path.realpath(exe), stamp, tuple(sorted(os.environ.items())))


def stop_session():
    """Ends the kept session (the add-on's unregister; a cancelled render)."""
    global _session
    with _session_lock:
        s, _session = _session, None
    if s is not None:
        s.stop()


class Job(Run):
    """A render run in the kept session (`batch -`), with Run's interface:
    poll(), running(), finish(), cancel(), error_line(), warnings().
    argv is the render's command line, argv[0] the binary. A new session
    is started when none runs, when the kept one ended or is busy, or when
    the binary or the environment changed. cancel() ends the session (the
    CLI's SIGINT clean-up, as for a process of its own); the next render
    starts another."""

    def __init__(self, argv):
        self.argv = argv
        self.messages = []
        self.events = []
        self._new = []  # events drained by running() for the next poll()
        self.rc = None
        line = " ".join(shlex.quote(a) for a in argv[1:]) + "\n"
        for attempt in (0, 1):  # a kept session that ended between jobs: one more, new
            self._attach(argv[0], fresh=attempt > 0)
            try:
                self.session.proc.stdin.write(line)
                self.session.proc.stdin.flush()
                break
            except OSError as e:
                self._drop()
                if attempt:
                    raise OSError("the photonbridge session ended: %s" % e)
        self.proc = self.session.proc

    def _attach(self, exe, fresh):
        """The kept session, or a new one (none, ended, busy, another binary
        or environment, or `fresh`)."""
        global _session
        key = _session_key(exe)
        with _session_lock:
            old = _session
            if old is not None and (fresh or old.key != key or old.busy or not old.alive()):
                _session = None
            else:
                old = None
            if _session is None:
                _session = _Session(exe, key)
            self.session = _session
            self.session.busy = True
        if old is not None:
            old.stop()

    def _drop(self):
        global _session
        with _session_lock:
            if _session is self.session:
                _session = None
        self.session.busy = False

    def _drain(self, block=0.0):
        new = []
        while self.rc is None:
            try:
                line = self.session.q.get(timeout=block) if block else self.session.q.get_nowait()
            except queue.Empty:
                break
            if line is None:  # the session died mid-job (a crash, a kill)
                self.rc = self.session.proc.wait()
                self._drop()
                break
            if line.startswith('{"job":'):
                try:
                    self.rc = int(json.loads(line)["exit"])
                except (ValueError, KeyError, TypeError):
                    self.rc = 70
                self.session.busy = False
                break
            self._take(line, new)
        self._new += new

    def poll(self):
        self._drain()
        new, self._new = self._new, []
        return new

    def running(self):
        self._drain()
        return self.rc is None

    def finish(self, timeout=None):
        t0 = time.monotonic()
        while self.rc is None:
            if timeout is not None and time.monotonic() - t0 > timeout:
                raise subprocess.TimeoutExpired(self.argv, timeout)
            self._drain(block=0.2)
        return self.rc

    def cancel(self, grace=20.0):
        """SIGINT to the session (the CLI removes its temporaries and exits
        130), then SIGTERM and SIGKILL; the session is not kept."""
        if self.rc is None:
            end_process(self.session.proc, (signal.SIGINT, signal.SIGTERM, signal.SIGKILL), grace)
            self._drain(block=0.2)
            if self.rc is None:
                self.rc = self.session.proc.wait()
        self._drop()
        self.session.stop()
        return self.rc


def start(argv):
    """A still render: a job of the kept session, or a process of its own
    when an argument holds a line break (a job is one line)."""
    if any("\n" in a for a in argv):
        return Run(argv)
    return Job(argv)
