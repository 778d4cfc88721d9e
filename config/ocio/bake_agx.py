#!/usr/bin/env python3
"""Derives the built-in AgX view (src/color/agx_builtin.c) from Blender 4.x's
own files, so photonbridge shows Blender 4's default view transform even where
no Blender 4 is installed.

    /usr/bin/python3 config/ocio/bake_agx.py [BLENDER_COLORMANAGEMENT_DIR]

(e.g. .../bpy/4.5/datafiles/colormanagement of the bpy 4.5 module).
Blender 4.x's "AgX" view on the sRGB display (config.ocio, colour space
"AgX Base sRGB") is, from scene-linear Rec.709:

    Linear Rec.709 -> Linear FilmLight E-Gamut       (3x3, via CIE XYZ)
    lg2 allocation [-12.47393, 12.5260688117]        (log, 0..1)
    AgX_Base_sRGB.cube, tetrahedral                  (57^3, 2.7 MB of text)
    exponent 2.4                                     (display-linear Rec.709)
    Linear Rec.709 -> sRGB                           (piecewise sRGB encode)

Unlike Filmic's desaturation cube, AgX's cube (EaryChow's formation: inset,
log sigmoid, outset, a 40% per-channel / hue-preserving mix, the guard rails)
has no closed form small enough to recover by reading it, and a coarser grid
misses by tens of 8-bit steps in saturated darks. So its data is embedded:
every entry rounded to 16 bits (x 65535; the file has 7 decimals), differenced
along red (the file's fastest axis), little-endian, zlib-compressed and
base64-encoded (about 0.36 MB of source). The rounding moves the display
value by at most 0.003 of an 8-bit step. The 3x3 matrix is composed here from
the config's own Rec.709 and E-Gamut matrices (the XYZ E -> D65 step cancels).

Khronos PBR Neutral needs no data: Blender's pbrNeutral.cube (on an lg2
allocation [-9, 10]) is the Khronos formula evaluated on its grid, which
src/color/ocio_shim.cpp recomputes; this script checks that the formula gives
the file's every entry (to the file's 7 decimals).

Needs numpy (Debian's python3-numpy)."""
import base64
import os
import re
import sys
import zlib

import numpy as np

AGX_LO, AGX_HI = -12.47393, 12.5260688117
PBR_LO, PBR_HI = -9.0, 10.0


def read_cube(path):
    rows, n = [], None
    with open(path) as f:
        for line in f:
            s = line.split()
            if not s or s[0].startswith("#") or s[0] in ("TITLE", "DOMAIN_MIN", "DOMAIN_MAX"):
                if s and s[0] in ("DOMAIN_MIN", "DOMAIN_MAX") and s[1:] != (["0"] * 3 if s[0] == "DOMAIN_MIN" else ["1"] * 3):
                    sys.exit("bake_agx: %s: domain is not 0..1" % path)
                continue
            if s[0] == "LUT_3D_SIZE":
                n = int(s[1])
                continue
            rows.append([float(v) for v in s])
    a = np.array(rows)
    if n is None or a.shape != (n ** 3, 3):
        sys.exit("bake_agx: %s: not a 3D .cube file" % path)
    return n, a  # file order: red fastest


def config_matrix(text, after):
    """The first MatrixTransform after the line containing `after`."""
    i = text.index(after)
    m = re.search(r"MatrixTransform> \{matrix: \[([^\]]*)\]", text[i:])
    v = [float(x) for x in m.group(1).split(",")]
    return np.array(v).reshape(4, 4)[:3, :3]


def pbr_neutral(c):
    start, desat = 0.8 - 0.04, 0.15
    x = c.min(-1, keepdims=True)
    off = np.where(x < 0.08, x - 6.25 * x * x, 0.04)
    c = c - off
    peak = c.max(-1, keepdims=True)
    d = 1.0 - start
    newpeak = 1.0 - d * d / (peak + d - start)
    scaled = c * newpeak / peak
    g = 1.0 - 1.0 / (desat * (peak - newpeak) + 1.0)
    return np.where(peak < start, c, scaled * (1.0 - g) + newpeak * g)


def main():
    cm = sys.argv[1] if len(sys.argv) > 1 else "/usr/share/blender/datafiles/colormanagement"
    text = open(os.path.join(cm, "config.ocio")).read()
    for probe in ("AgX_Base_sRGB.cube, interpolation: tetrahedral",
                  "{allocation: lg2, vars: [-12.47393, 12.5260688117]}",
                  "pbrNeutral.cube, interpolation: tetrahedral", "{allocation: lg2, vars: [-9, 10]}"):
        if probe not in text:
            sys.exit("bake_agx: %s: no '%s' (not Blender 4.x's config?)" % (cm, probe))
    m709 = config_matrix(text, "name: Linear Rec.709\n")          # XYZ D65 -> Rec.709
    mfl = config_matrix(text, "name: Linear FilmLight E-Gamut\n")  # E-Gamut -> XYZ D65 (used inverted)
    to_egamut = np.linalg.inv(mfl) @ np.linalg.inv(m709)

    n, cube = read_cube(os.path.join(cm, "luts/AgX_Base_sRGB.cube"))
    q = np.round(np.clip(cube, 0, 1) * 65535).astype(np.int64)
    qerr = np.abs(q / 65535.0 - cube).max()
    d = q.reshape(n, n, n, 3)  # [b][g][r]
    d = np.diff(d, axis=2, prepend=0).astype(np.int64) & 0xFFFF
    blob = zlib.compress(d.astype("<u2").tobytes(), 9)
    b64 = base64.b64encode(blob).decode()

    pn, pcube = read_cube(os.path.join(cm, "luts/pbrNeutral.cube"))
    t = 2.0 ** (PBR_LO + (PBR_HI - PBR_LO) * np.arange(pn) / (pn - 1))
    B, G, R = np.meshgrid(t, t, t, indexing="ij")
    pworst = np.abs(pbr_neutral(np.stack([R, G, B], -1)).reshape(-1, 3) - pcube).max()
    if pworst > 1e-6:
        sys.exit("bake_agx: the Khronos PBR Neutral formula misses pbrNeutral.cube by %.3g" % pworst)

    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    lines = [
        "/* Generated by config/ocio/bake_agx.py from Blender 4.x's AgX files",
        " * (config.ocio, luts/AgX_Base_sRGB.cube); do not edit. Entries rounded to",
        " * 16 bits move by at most %.2g; the Khronos PBR Neutral formula gives" % qerr,
        " * pbrNeutral.cube within %.2g. See the script for the format. */" % pworst,
        '#include "color/agx_builtin.h"',
        "",
        "const double pb_agx_rec709_to_egamut[9] = {",
    ]
    for row in to_egamut:
        lines.append("    " + " ".join("%.17g," % v for v in row))
    lines += ["};", "", "const unsigned long pb_agx_cube_deflated_size = %d;" % len(blob), "",
              "const char pb_agx_cube_base64[] ="]
    for k in range(0, len(b64), 96):
        lines.append('    "%s"' % b64[k:k + 96])
    lines[-1] += ";"
    lines.append("")
    out = os.path.join(root, "src/color/agx_builtin.c")
    with open(out, "w") as f:
        f.write("\n".join(lines))
    print("bake_agx: wrote %s (%d^3 cube, %d deflated bytes, rounding %.3g, PBR Neutral formula %.3g)"
          % (out, n, len(blob), qerr, pworst))


if __name__ == "__main__":
    main()
