"""Shared by the farm tests: the scene and render settings they
use; the generic helpers (checks, runs, EXR comparison to float rounding)
are tests/pylib/pbcheck.py's."""
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pylib"))
import pbcheck  # noqa: E402
from pbcheck import ROUNDING, run_cmd as run  # noqa: E402,F401

_T = pbcheck.Checker(None, "")
check, failures = _T.check, _T.failures
fresh = _T.fresh  # an absolute path: emptied and created

# Small and quick: an animated sample at 32 x 32, few photons.
SCENE = "cornell_box_moving_light"
RENDER = ["--width", "32", "--height", "32", "--spp", "1", "--iterations", "1", "--photons", "4096",
          "--seed", "5", "-q"]


def sample(root, name=SCENE):
    return os.path.join(root, "samples", name, name + ".gltf")


def exr(probe, path):
    return pbcheck.probe_exr(probe, path)


def worst_rel(probe, a, b):
    """Largest difference of two EXRs over R, G, B, relative to each
    channel's peak."""
    return pbcheck.worst_rel_exr(probe, a, b)


def has_device(exe):
    return subprocess.run([exe, "info", "--devices"], capture_output=True).returncode == 0
