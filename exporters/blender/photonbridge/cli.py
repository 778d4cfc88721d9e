"""Running `photonbridge render` from Blender: finding the binary, and the
child process with its output read on threads (never a blocking read on
Blender's thread), progress lines parsed, and a cancel that lets the CLI
clean up (SIGINT, then SIGTERM, then SIGKILL if it does not exit)."""
import json
import os
import queue
import shutil
import signal
import subprocess
import threading

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

    def poll(self):
        """New progress events (dicts) since the last call; other lines are
        kept in self.messages."""
        new = []
        while True:
            try:
                line = self.q.get_nowait()
            except queue.Empty:
                break
            if line.startswith(PROGRESS_PREFIX):
                try:
                    ev = json.loads(line[len(PROGRESS_PREFIX):])
                except ValueError:
                    self.messages.append(line)
                    continue
                self.events.append(ev)
                new.append(ev)
            elif line:
                self.messages.append(line)
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
        for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGKILL):
            if self.proc.poll() is not None:
                break
            try:
                self.proc.send_signal(sig)
            except ProcessLookupError:
                break
            try:
                self.proc.wait(grace)
            except subprocess.TimeoutExpired:
                continue
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
