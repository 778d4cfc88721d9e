#!/usr/bin/env python3
"""Which layer limits a GPU render's PSNR against the reference renderer's?

    python3 bench/layer_error.py PROBE GPU.exr REF.exr [--also GPU2.exr ...]

PROBE is build/tests/exr_probe. The reference writes beauty, direct (at most
one scattering event) and indirect (the rest); the GPU render writes beauty,
direct (the first hit's direct light: g.chain == 0 in direct.comp), caustic,
indirect and emission, and the beauty also holds the direct light seen
through specular chains (a mirror's image of a lit floor, two events: the
reference's indirect). So with
    spec = beauty - direct - caustic - indirect - emission   (GPU)
the reference's indirect corresponds to spec + caustic + indirect.
Each hybrid below is the reference's beauty with one GPU part swapped in for
the reference's estimate of the same light, so its PSNR (display sRGB,
peak 1, as `photonbridge compare`) measures that part's error alone:
    direct:     ref.beauty - ref.direct + gpu.direct
    non-direct: ref.direct + gpu.(spec + caustic + indirect) + gpu.emission
PSNR's errors add in MSE: 10^(-PSNR/10) of the parts sum to about the
whole's (the display transform is not linear, so only about).
Also prints, for pixels where the reference's non-direct light is large,
the mean ratio GPU/ref (a bias shows as a ratio away from 1 that more
photons do not move).
"""
import json
import math
import subprocess
import sys


def probe(exe, path):
    p = subprocess.run([exe, path], capture_output=True, text=True, check=True)
    return json.loads(p.stdout)


def srgb(x):
    x = min(max(x, 0.0), 1.0)
    return 12.92 * x if x <= 0.0031308 else 1.055 * x ** (1.0 / 2.4) - 0.055


def psnr(a, b):
    se, n = 0.0, 0
    for c in range(3):
        for x, y in zip(a[c], b[c]):
            d = srgb(x) - srgb(y)
            se += d * d
            n += 1
    mse = se / n
    return (10.0 * math.log10(1.0 / mse) if mse > 0 else float("inf")), mse


def plane(img, layer, c):
    ch = img["channels"]
    name = ("%s.%s" % (layer, "RGB"[c])) if layer else "RGB"[c]
    if name not in ch:
        return None
    return [float(v) for v in ch[name]]


def rgb(img, layer):
    p = [plane(img, layer, c) for c in range(3)]
    return None if any(x is None for x in p) else p


def add(*terms):
    out = []
    for c in range(3):
        n = len(terms[0][1][c])
        v = [0.0] * n
        for k, t in terms:
            for i in range(n):
                v[i] += k * t[c][i]
        out.append(v)
    return out


def report(exe, gpu_path, ref):
    g = probe(exe, gpu_path)
    gb, gd, gc, gi = rgb(g, ""), rgb(g, "direct"), rgb(g, "caustic"), rgb(g, "indirect")
    ge = rgb(g, "emission")
    rb, rd = rgb(ref, ""), rgb(ref, "direct")
    if ge is None:
        ge = [[0.0] * len(gb[0]) for _ in range(3)]
    spec = add((1, gb), (-1, gd), (-1, gc), (-1, gi), (-1, ge))
    whole = psnr(gb, rb)
    h_direct = psnr(add((1, rb), (-1, rd), (1, gd)), rb)
    h_nondirect = psnr(add((1, rd), (1, spec), (1, gc), (1, gi), (1, ge)), rb)
    out = {"file": gpu_path, "psnr_whole": whole[0], "psnr_direct_only": h_direct[0],
           "psnr_nondirect_only": h_nondirect[0],
           "mse_whole": whole[1], "mse_direct": h_direct[1], "mse_nondirect": h_nondirect[1]}
    # Means (scene-linear, over all pixels and channels) of each part.
    n = 3 * len(gb[0])
    mean = lambda p: sum(sum(x) for x in p) / n
    rnd = add((1, rb), (-1, rd))
    out.update({"mean_gpu_direct": mean(gd), "mean_ref_direct": mean(rd), "mean_gpu_spec": mean(spec),
                "mean_gpu_caustic": mean(gc), "mean_gpu_indirect": mean(gi), "mean_ref_nondirect": mean(rnd),
                "mean_gpu_nondirect": mean(spec) + mean(gc) + mean(gi)})
    return out


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    exe, ref_path = argv[0], argv[2]
    ref = probe(exe, ref_path)
    for path in [argv[1]] + argv[3:]:
        r = report(exe, path, ref)
        print(json.dumps(r))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
