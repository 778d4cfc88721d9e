"""Shared by the farm tests (issue 23): running photonbridge, reading EXRs
through exr_probe, comparing frames to float rounding."""
import json
import os
import shutil
import subprocess

failures = []

# Two renders of one scene and seed agree to float rounding, not bit for
# bit: the photon store's order follows the device's scheduling
# (tests/render_drive.py says why).
ROUNDING = 1e-5

# Small and quick: an animated sample at 32 x 32, few photons.
SCENE = "cornell_box_moving_light"
RENDER = ["--width", "32", "--height", "32", "--spp", "1", "--iterations", "1", "--photons", "4096",
          "--seed", "5", "-q"]


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def fresh(path):
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def sample(root, name=SCENE):
    return os.path.join(root, "samples", name, name + ".gltf")


def run(cmd, expect_rc=0, **kw):
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if expect_rc is not None and p.returncode != expect_rc:
        print(" ".join(cmd))
        print(p.stdout[-3000:])
        print(p.stderr[-3000:])
    return p


def exr(probe, path):
    p = subprocess.run([probe, path], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError("%s: %s" % (path, p.stderr.strip()))
    return json.loads(p.stdout)


def worst_rel(probe, a, b):
    """Largest difference of two EXRs over R, G, B, relative to each
    channel's peak."""
    ia, ib = exr(probe, a), exr(probe, b)
    if (ia["width"], ia["height"]) != (ib["width"], ib["height"]):
        return float("inf")
    worst = 0.0
    for ch in ("R", "G", "B"):
        x, y = ia["channels"][ch], ib["channels"][ch]
        peak = max(max((abs(v) for v in x), default=0.0), 1e-6)
        worst = max(worst, max((abs(u - v) for u, v in zip(x, y)), default=0.0) / peak)
    return worst


def has_device(exe):
    return subprocess.run([exe, "info", "--devices"], capture_output=True).returncode == 0
