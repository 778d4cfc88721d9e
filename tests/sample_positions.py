#!/usr/bin/env python3
"""Camera samples cover the whole pixel for every sample count: the
coverage (alpha) of cornell_box, whose box edges cut the pixels, rendered
with --spp 2, 3, 5 and 8 (counts that are not squares) must not be shifted
against --spp 16 (a 4 x 4 jittered grid, uniform over the pixel).

The shift is the least-squares displacement d of the spp-N coverage A_N
against A_16 along x and along y: A_N ~ A_16 - d dA_16/dy, so
d = -sum((A_N - A_16) g) / sum(g^2) with g the central difference of A_16.
Samples confined to part of the pixel shift the picture by the mean offset
of the cells they use: a ceil(sqrt(N))^2 grid of which only the first N
cells are sampled shifts it by 0.25 px at N = 2 (both samples in the upper
half), 0.083 px along both axes at 3 and 0.2 px at 5 (0.042 px at 8, below
what this test resolves); samples uniform over the pixel leave noise only,
|d| <= 0.032 px at 160 x 120 (two seeds, every N here). Limit: 0.06 px.

argv: photonbridge exr_probe WORKDIR
"""
import json, os, subprocess, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pbcheck import check, finish  # noqa: E402

exe, probe, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
LIMIT = 0.06
W, H = 160, 120




def alpha(spp):
    out = os.path.join(work, f"spp{spp}.exr")
    p = subprocess.run([exe, "render", "samples/cornell_box/cornell_box.gltf", "-o", out, "-q", "--direct-only",
                        "--width", str(W), "--height", str(H), "--spp", str(spp), "--seed", "3"],
                       capture_output=True, text=True, timeout=600)
    if p.returncode == 77 or "no usable Vulkan device" in p.stderr:
        print("skip: no Vulkan device")
        sys.exit(77)
    if p.returncode != 0:
        print(f"render --spp {spp}: exit {p.returncode}: {p.stderr.strip()}")
        sys.exit(1)
    j = json.loads(subprocess.run([probe, out], capture_output=True, text=True, check=True).stdout)
    return j["channels"]["A"]


ref = alpha(16)


def shift(a, axis):
    num = den = 0.0
    for y in range(1, H - 1):
        for x in range(1, W - 1):
            i = y * W + x
            g = (ref[i + W] - ref[i - W]) / 2 if axis == "y" else (ref[i + 1] - ref[i - 1]) / 2
            num += (a[i] - ref[i]) * g
            den += g * g
    return -num / den if den > 0 else 0.0


for spp in (2, 3, 5, 8):
    a = alpha(spp)
    for axis in ("x", "y"):
        d = shift(a, axis)
        print(f"--spp {spp}: coverage shifted {d:+.4f} px along {axis} against --spp 16")
        check(abs(d) <= LIMIT, f"--spp {spp}: the picture is shifted {d:+.4f} px along {axis} (limit {LIMIT})")

finish()
