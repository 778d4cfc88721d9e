"""What the CLI test scripts share (tests/render_drive.py, sequence_check.py,
scene_view.py): named checks collected into one verdict, photonbridge runs
that print their output only when the exit code is unexpected, fresh work
folders, and exr_probe's JSON.

    import sys, os; sys.path.insert(0, os.path.join(os.path.dirname(__file__), "pylib"))
    from pbcheck import Checker
    t = Checker(exe, work)
    t.check(cond, "what was checked")
    p = t.run(["render", ...], expect_rc=0)
    sys.exit(t.finish())
"""
import json
import os
import shutil
import subprocess

# Two renders of one scene and seed agree to float rounding, not bit for
# bit: photon_trace.comp stores each photon at the slot an atomic counter
# hands out, so the store's order (and the order of the gather's sums)
# follows the device's scheduling (tests/render_drive.py).
ROUNDING = 1e-5


def run_cmd(cmd, expect_rc=0, **kw):
    """Runs cmd; its stdout and stderr (last 3000 characters) are printed
    when the exit code is not expect_rc (None: any)."""
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if expect_rc is not None and p.returncode != expect_rc:
        print(" ".join(cmd))
        print(p.stdout[-3000:])
        print(p.stderr[-3000:])
    return p


def probe_exr(probe, path):
    """exr_probe's description of an EXR (width, height, channels) as JSON."""
    p = subprocess.run([probe, path], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError("%s: %s" % (path, p.stderr.strip()))
    return json.loads(p.stdout)


def worst_rel_exr(probe, a, b, channels=("R", "G", "B")):
    """Largest difference of two EXRs over the channels, relative to each
    channel's peak (inf when their sizes differ)."""
    ia, ib = probe_exr(probe, a), probe_exr(probe, b)
    if (ia["width"], ia["height"]) != (ib["width"], ib["height"]):
        return float("inf")
    worst = 0.0
    for ch in channels:
        x, y = ia["channels"][ch], ib["channels"][ch]
        peak = max(max((abs(v) for v in x), default=0.0), 1e-6)
        worst = max(worst, max((abs(u - v) for u, v in zip(x, y)), default=0.0) / peak)
    return worst


class Checker:
    def __init__(self, exe, work=None, probe=None):
        self.exe = exe
        self.work = work
        self.probe = probe
        self.failures = []
        self.passed = 0

    def check(self, cond, what):
        """Records and prints one named outcome; returns cond."""
        print(("ok   " if cond else "FAIL ") + what, flush=True)
        if cond:
            self.passed += 1
        else:
            self.failures.append(what)
        return cond

    def run(self, args, expect_rc=0):
        """photonbridge ARGS; stdout and stderr (their last 3000 characters)
        are printed when the exit code is not expect_rc (None: any)."""
        return run_cmd([self.exe] + list(args), expect_rc)

    def fresh(self, sub):
        """An empty folder WORK/sub (removed first if it exists)."""
        d = os.path.join(self.work, sub)
        shutil.rmtree(d, ignore_errors=True)
        os.makedirs(d)
        return d

    def exr(self, path):
        """exr_probe's description of an EXR (channels, pixels) as JSON."""
        return probe_exr(self.probe, path)

    def has_device(self):
        """A Vulkan device is there (else the caller skips with 77)."""
        p = subprocess.run([self.exe, "info", "--devices"], capture_output=True, text=True)
        return p.returncode == 0

    def finish(self):
        """Prints the verdict line and returns the exit code."""
        print("%d passed, %d failed" % (self.passed, len(self.failures)))
        for f in self.failures:
            print("  failed: " + f)
        return 1 if self.failures else 0
