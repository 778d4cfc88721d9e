#!/usr/bin/env python3
"""Derives the built-in Filmic view (src/color/filmic_builtin.c) from Blender's
own Filmic files, so photonbridge shows Blender's default view transform even
where Blender is not installed.

    /usr/bin/python3 config/ocio/bake_filmic.py [BLENDER_COLORMANAGEMENT_DIR]

Blender 3.4's "Filmic" view (config.ocio, colour space "Filmic sRGB") is

    lg2 allocation [-12.473931188, 12.526068812]      (scene-linear -> log, 0..1)
    filmic_desat65cube.spi3d, tetrahedral            (65^3, 9 MB)
    uniform allocation [0, 0.66]                     (x / 0.66)
    filmic_to_0-70_1-03.spi1d, linear                (4096 entries, "Base Contrast")

The 65^3 cube has a closed form, found by reading it: in linear light every
channel is pulled towards the largest one by a factor that depends only on the
largest channel's grid index m,

    out_c = lin^-1( L_c + t[m] (L_max - L_c) ),   L = 2^(-12.473931188 + 25 x)

(identity below m = 41, every channel equal to the maximum at m = 64), with
entries floored at 0.000175781 and written to 6 digits. This script recovers
t[m] as the median over each shell, checks that the closed form reproduces
every entry of the file (worst entry below 2e-4 in the 0..1 log encoding, i.e.
0.003 stops), and keeps every 5th entry of the 1D curve (820 of 4096; linear
interpolation of the rest differs from the full curve by under 0.01 of an
8-bit step). test_color's color_filmic_vs_blender compares the result with
Blender's own Filmic render of a ramp EXR (within one 8-bit step).

Blender's Filmic looks ("Very High Contrast", ..., "Very Low Contrast"; the
same files and steps in 3.4 and 4.x) work in its "Filmic Log" colour space
(the first three steps above; back to scene-linear by an lg2 allocation
[-12.473931188, 4.026068812], inverse): each is another filmic_to_*.spi1d
curve, then the base curve inverted ("Medium Contrast": nothing). This script
reads them from config.ocio and keeps every 5th entry of each curve too.

Needs numpy (Debian's python3-numpy)."""
import os
import re
import sys

import numpy as np

LO, HI = -12.473931188, 12.526068812
FLOOR = 0.000175781
CURVE_STEP = 5


def read_cube(path):
    with open(path) as f:
        head = [next(f) for _ in range(3)]
        if not head[0].lower().startswith("spilut") or head[2].split() != ["65", "65", "65"]:
            sys.exit("bake_filmic: %s: not a 65^3 spi3d file" % path)
        d = np.loadtxt(f)
    cube = np.zeros((65, 65, 65, 3))
    i = d[:, :3].astype(int)
    cube[i[:, 0], i[:, 1], i[:, 2]] = d[:, 3:]
    return cube


def read_curve(path):
    vals, inside = [], False
    with open(path) as f:
        for line in f:
            s = line.strip()
            if s.startswith("From") and s.split()[1:] != ["0.000000", "1.000000"]:
                sys.exit("bake_filmic: %s: domain is not 0..1" % path)
            if s == "{":
                inside = True
            elif s == "}":
                break
            elif inside and s:
                vals.append(float(s))
    if len(vals) != 4096:
        sys.exit("bake_filmic: %s: %d entries (4096 expected)" % (path, len(vals)))
    return np.array(vals)


def filmic_looks(cm):
    """[(name, curve file or None)] of config.ocio's looks in Filmic Log."""
    text = open(os.path.join(cm, "config.ocio")).read()
    body = text[text.index("\nlooks:\n"):]
    out = []
    for lk in re.split(r"\n(?=  - !<Look>)", body)[1:]:
        if "process_space: Filmic Log" not in lk:
            continue
        name = re.search(r"^    name: (.*)$", lk, re.M).group(1).strip()
        files = re.findall(r"FileTransform> \{src: ([^,]*), interpolation: (?:linear|best)(, direction: inverse)?\}", lk)
        if not files:
            if "children:\n" not in lk or "!<" in lk.split("children:", 1)[1]:
                sys.exit("bake_filmic: look %s: not a pair of curves nor empty" % name)
            out.append((name, None))
        elif (len(files) == 2 and not files[0][1] and files[1] == ("filmic_to_0-70_1-03.spi1d", ", direction: inverse")
              and lk.count("!<") == 4):
            out.append((name, files[0][0]))
        else:
            sys.exit("bake_filmic: look %s: not a curve then the base curve inverted" % name)
    if len(out) != 7:
        sys.exit("bake_filmic: %d Filmic looks (7 expected)" % len(out))
    return out


def main():
    cm = sys.argv[1] if len(sys.argv) > 1 else "/usr/share/blender/datafiles/colormanagement"
    cube = read_cube(os.path.join(cm, "filmic/filmic_desat65cube.spi3d"))
    curve = read_curve(os.path.join(cm, "filmic/filmic_to_0-70_1-03.spi1d"))

    lin = lambda x: 2.0 ** (LO + (HI - LO) * x)
    x = np.arange(65) / 64.0
    I, J, K = np.meshgrid(np.arange(65), np.arange(65), np.arange(65), indexing="ij")
    L = lin(np.stack([x[I], x[J], x[K]], -1))
    Lmax = L.max(-1, keepdims=True)
    m = np.maximum(np.maximum(I, J), K)
    Lout = lin(np.maximum(cube, 1e-12))
    t = np.zeros(65)
    for k in range(65):
        sel = m == k
        gap = (Lmax - L)[sel]
        # Entries at the floor say nothing about t.
        ok = (gap > 1e-3 * np.broadcast_to(Lmax, L.shape)[sel]) & (cube[sel] > 1.5 * FLOOR)
        if ok.any():
            t[k] = np.median(((Lout - L)[sel])[ok] / gap[ok])
    t[t < 1e-6] = 0.0  # the shells below m = 41 are the identity to the file's 6 digits
    t[64] = 1.0
    rec = np.maximum((np.log2(L + t[m][..., None] * (Lmax - L)) - LO) / (HI - LO), FLOOR)
    worst = np.abs(rec - cube).max()
    if worst > 2e-4:
        sys.exit("bake_filmic: the closed form misses the cube by %.3g (more than 2e-4)" % worst)
    sub = curve[::CURVE_STEP]
    if (len(curve) - 1) % CURVE_STEP:
        sys.exit("bake_filmic: curve step does not divide 4095")
    looks = filmic_looks(cm)
    look_curves = [read_curve(os.path.join(cm, "filmic", f))[::CURVE_STEP] for _, f in looks if f]

    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    out = os.path.join(root, "src/color/filmic_builtin.c")
    first = int(np.argmax(t > 0))
    lines = [
        "/* Generated by config/ocio/bake_filmic.py from Blender 3.4's Filmic files",
        " * (filmic_desat65cube.spi3d, filmic_to_*.spi1d, config.ocio's looks); do not edit.",
        " * The closed form of the desaturation cube misses the file by at most",
        " * %.2g (0..1 log encoding). See the script for the derivation. */" % worst,
        '#include "color/filmic_builtin.h"',
        "",
        "const float pb_filmic_desat_t[PB_FILMIC_CUBE_SIZE] = {",
    ]
    for k in range(0, 65, 4):
        lines.append("    " + " ".join("%.9ef," % v for v in t[k:k + 4]))
    lines += ["};", "", "const float pb_filmic_curve[PB_FILMIC_CURVE_SIZE] = {"]
    for k in range(0, len(sub), 6):
        lines.append("    " + " ".join("%.9ef," % v for v in sub[k:k + 6]))
    lines += ["};", ""]
    lines += ["/* Blender's Filmic looks in config.ocio's order: name, the curve (index into",
              " * pb_filmic_look_curves; -1: none, the look is empty). */",
              "const pb_filmic_look pb_filmic_looks[PB_FILMIC_LOOK_COUNT] = {"]
    k = 0
    for name, f in looks:
        lines.append('    {"%s", %d}, /* %s */' % (name, k if f else -1, f or "no curve"))
        k += 1 if f else 0
    lines += ["};", "", "const float pb_filmic_look_curves[PB_FILMIC_LOOK_CURVES][PB_FILMIC_CURVE_SIZE] = {"]
    for c in look_curves:
        lines.append("  {")
        for k in range(0, len(c), 6):
            lines.append("    " + " ".join("%.9ef," % v for v in c[k:k + 6]))
        lines.append("  },")
    lines += ["};", ""]
    with open(out, "w") as f:
        f.write("\n".join(lines))
    print("bake_filmic: wrote %s (t > 0 from shell %d, %d curve entries, cube error %.3g, %d looks)"
          % (out, first, len(sub), worst, len(looks)))


if __name__ == "__main__":
    main()
