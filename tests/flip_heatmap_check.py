#!/usr/bin/env python3
"""compare's HDR-FLIP output and --heatmap-metric flip, structurally (no
FLIP installation needed; tests/flip_agreement.py checks the numbers):

    tests/flip_heatmap_check.py PHOTONBRIDGE OUTDIR

A smooth 96x64 reference and a test that differs from it in one 8x8 block:
the map is a 96x64 RGB PNG, FLIP's magma black (0, 0, 4) wherever the
filters do not reach the block, brighter on it; the JSON's FLIP keys and
its heat map metric; the text's FLIP line. A reference black everywhere:
FLIP n/a (null), and a FLIP map refused with exit 2. Error paths keep
their codes: an unknown metric 2, sizes that differ 9."""
import json
import os
import struct
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import imgmini  # noqa: E402
from pbcheck import check, debian_python, finish  # noqa: E402

try:
    from PIL import Image
except ImportError:  # pyenv's python without Debian's packages
    debian_python("flip_heatmap_check")

W, H = 96, 64
BX, BY, BS = 70, 40, 8  # the block that differs
REACH = 12              # beyond FLIP's filter radii at 67 pixels per degree (10 and 9)


def image(path, w, h, f):
    planes = [struct.pack("<%df" % (w * h), *(f(x, y)[c] for y in range(h) for x in range(w))) for c in range(3)]
    imgmini.write_rgb(path, w, h, *planes)


def run(*args):
    return subprocess.run([EXE] + list(args), capture_output=True, text=True)


EXE, OUT = sys.argv[1], sys.argv[2]
os.makedirs(OUT, exist_ok=True)
ref, test = os.path.join(OUT, "ref.exr"), os.path.join(OUT, "test.exr")
black, small = os.path.join(OUT, "black.exr"), os.path.join(OUT, "small.exr")
smooth = lambda x, y: (0.2 + 0.6 * x / W, 0.3 + 0.4 * y / H, 0.5)  # noqa: E731
image(ref, W, H, smooth)
image(test, W, H, lambda x, y: (4.0, 0.1, 0.1) if BX <= x < BX + BS and BY <= y < BY + BS else smooth(x, y))
image(black, W, H, lambda x, y: (0.0, 0.0, 0.0))
image(small, 32, 16, smooth)

png = os.path.join(OUT, "flip.png")
p = run("compare", test, ref, "--heatmap", png, "--heatmap-metric", "flip", "--json", "-")
check(p.returncode == 0, "compare --heatmap-metric flip: exit %d %s" % (p.returncode, p.stderr.strip()))
j = json.loads(p.stdout) if p.returncode == 0 else {}
f = j.get("hdr_flip")
check(isinstance(f, float) and 0 < f < 1, "hdr_flip %r" % f)
check(isinstance(j.get("hdr_flip_exposures"), int) and j["hdr_flip_exposures"] >= 2 and
      j.get("hdr_flip_start_exposure") <= j.get("hdr_flip_stop_exposure"),
      "exposures %r %r %r" % (j.get("hdr_flip_start_exposure"), j.get("hdr_flip_stop_exposure"),
                              j.get("hdr_flip_exposures")))
check(j.get("hdr_flip_zeroed_pixels") == 0, "hdr_flip_zeroed_pixels %r" % j.get("hdr_flip_zeroed_pixels"))
check(j.get("heatmap") == {"file": png, "metric": "flip", "scale_max": 1},
      "the JSON's heatmap: %r" % j.get("heatmap"))
if check(os.path.isfile(png), "no PNG written"):
    im = Image.open(png)
    w, h = im.size
    data = im.tobytes()
    rows = [data[3 * w * y:3 * w * (y + 1)] for y in range(h)]
    check((w, h, im.mode) == (W, H, "RGB"), "the map is %dx%d in mode %s" % (w, h, im.mode))
    far = [rows[y][3 * x:3 * x + 3] for y in range(h) for x in range(w)
           if not (BX - REACH <= x < BX + BS + REACH and BY - REACH <= y < BY + BS + REACH)]
    check(far and all(px == b"\x00\x00\x04" for px in far),
          "the map is not FLIP's black where the images are the same")
    centre = rows[BY + BS // 2][3 * (BX + BS // 2):3 * (BX + BS // 2) + 3]
    check(sum(centre) > 200, "the map is dark where the images differ: %r" % list(centre))

p = run("compare", test, ref)
check(p.returncode == 0 and any(line.startswith("FLIP       0.") and "exposures" in line
                                for line in p.stdout.splitlines()), "the text's FLIP line: %r" % p.stdout)

# A black reference: FLIP is undefined, the other numbers are there.
p = run("compare", test, black, "--json", "-")
j = json.loads(p.stdout) if p.returncode == 0 else {}
check(p.returncode == 0 and "hdr_flip" in j and j["hdr_flip"] is None and j["hdr_flip_exposures"] is None
      and isinstance(j.get("rmse"), float), "a black reference: exit %d, %r" % (p.returncode, p.stdout[-300:]))
p = run("compare", test, black)
check(p.returncode == 0 and "FLIP       n/a" in p.stdout, "a black reference's FLIP line: %r" % p.stdout)
nomap = os.path.join(OUT, "nomap.png")
p = run("compare", test, black, "--heatmap", nomap, "--heatmap-metric", "flip")
check(p.returncode == 2 and "black everywhere" in p.stderr and not os.path.exists(nomap),
      "a FLIP map of a black reference: exit %d %r" % (p.returncode, p.stderr))

# Error paths and their codes.
p = run("compare", test, ref, "--heatmap", nomap, "--heatmap-metric", "flop")
check(p.returncode == 2 and "flop" in p.stderr, "an unknown metric: exit %d %r" % (p.returncode, p.stderr))
p = run("compare", small, ref, "--heatmap", nomap, "--heatmap-metric", "flip")
check(p.returncode == 9 and "32x16" in p.stderr and not os.path.exists(nomap),
      "sizes that differ: exit %d %r" % (p.returncode, p.stderr))
p = run("compare", test, os.path.join(OUT, "missing.exr"), "--heatmap-metric", "flip")
check(p.returncode == 3, "a missing file: exit %d" % p.returncode)
p = run("compare", test, "--heatmap-metric", "flip")
check(p.returncode == 2, "one file: exit %d" % p.returncode)
finish("flip_heatmap")
