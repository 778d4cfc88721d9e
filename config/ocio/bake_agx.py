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

Blender 4.x's AgX looks ("AgX - Punchy", ..., "AgX - Very Low Contrast")
work in its "AgX Log" colour space, from scene-linear Rec.709:

    Linear Rec.709 -> Linear FilmLight E-Gamut       (3x3, as above)
    lg2 allocation [-12.47393, 12.5260688117]
    luminance_compensation_bt2020.cube, tetrahedral  (37^3: "Luminance
                                                      Compensation Rec.2020")
    lg2 allocation, inverse
    Linear FilmLight E-Gamut -> Linear Rec.2020      (3x3)
    the inset / rotation 3x3 of "AgX Log"
    lg2 allocation [-12.47393, 12.5260688117]

and back (its to_scene_reference): lg2 inverse, the inset inverted, Linear
Rec.2020 -> Linear Rec.709. The 37^3 cube is embedded as the AgX cube is,
but scaled by 60000 instead of 65535 (its entries reach 1.0054). The looks
themselves use OpenColorIO 2.x's own transforms (GradingToneTransform,
CDLTransform, GradingPrimaryTransform, AllocationTransform, MatrixTransform),
so their YAML is copied verbatim from config.ocio and parsed by OpenColorIO
at run time (src/color/ocio_shim.cpp).

Needs numpy (Debian's python3-numpy)."""
import base64
import os
import re
import sys
import zlib

import numpy as np

AGX_LO, AGX_HI = -12.47393, 12.5260688117
LUMCOMP_SCALE = 60000.0
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


def pack_cube(n, cube, scale):
    """Cube entries x scale as uint16, differenced along red, zlib, base64."""
    if cube.max() * scale > 65535:
        sys.exit("bake_agx: cube entries above %g" % (65535 / scale))
    q = np.round(np.clip(cube, 0, None) * scale).astype(np.int64)
    qerr = np.abs(q / scale - cube).max()
    d = q.reshape(n, n, n, 3)  # [b][g][r]
    d = np.diff(d, axis=2, prepend=0).astype(np.int64) & 0xFFFF
    blob = zlib.compress(d.astype("<u2").tobytes(), 9)
    return blob, base64.b64encode(blob).decode(), qerr


def agx_looks(text):
    """The YAML of config.ocio's "AgX - ..." looks, verbatim."""
    body = text[text.index("\nlooks:\n") + len("\nlooks:\n"):]
    looks = re.split(r"\n(?=  - !<Look>)", body)
    out = [lk.rstrip() + "\n" for lk in looks if re.search(r"^    name: AgX - ", lk, re.M)]
    for lk in out:
        if "process_space: AgX Log" not in lk or "FileTransform" in lk:
            sys.exit("bake_agx: a look not in AgX Log or with a file:\n" + lk)
    return out


def c_string(name, text):
    lines = ["const char %s[] =" % name]
    for line in text.splitlines(keepends=True):
        lines.append('    "%s"' % line.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n"))
    lines[-1] += ";"
    return lines


def c_matrix(name, m):
    lines = ["const double %s[9] = {" % name]
    for row in m:
        lines.append("    " + " ".join("%.17g," % v for v in row))
    return lines + ["};", ""]


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
                  "pbrNeutral.cube, interpolation: tetrahedral", "{allocation: lg2, vars: [-9, 10]}",
                  "{src: Linear CIE-XYZ E, dst: Luminance Compensation Rec.2020}",
                  "luminance_compensation_bt2020.cube, interpolation: tetrahedral"):
        if probe not in text:
            sys.exit("bake_agx: %s: no '%s' (not Blender 4.x's config?)" % (cm, probe))
    m709 = config_matrix(text, "name: Linear Rec.709\n")          # XYZ D65 -> Rec.709
    mfl = config_matrix(text, "name: Linear FilmLight E-Gamut\n")  # E-Gamut -> XYZ D65 (used inverted)
    m2020 = config_matrix(text, "name: Linear Rec.2020\n")        # XYZ D65 -> Rec.2020
    inset = config_matrix(text, "name: AgX Log\n")                 # Rec.2020 -> AgX Log's primaries
    to_egamut = np.linalg.inv(mfl) @ np.linalg.inv(m709)
    egamut_to_2020 = m2020 @ mfl
    r2020_to_709 = m709 @ np.linalg.inv(m2020)

    n, cube = read_cube(os.path.join(cm, "luts/AgX_Base_sRGB.cube"))
    if cube.max() > 1:
        sys.exit("bake_agx: AgX_Base_sRGB.cube has entries above 1")
    blob, b64, qerr = pack_cube(n, cube, 65535.0)
    ln, lcube = read_cube(os.path.join(cm, "luts/luminance_compensation_bt2020.cube"))
    lblob, lb64, lqerr = pack_cube(ln, lcube, LUMCOMP_SCALE)
    if ln != 37:
        sys.exit("bake_agx: luminance_compensation_bt2020.cube is %d^3, not 37^3" % ln)
    looks = agx_looks(text)

    pn, pcube = read_cube(os.path.join(cm, "luts/pbrNeutral.cube"))
    t = 2.0 ** (PBR_LO + (PBR_HI - PBR_LO) * np.arange(pn) / (pn - 1))
    B, G, R = np.meshgrid(t, t, t, indexing="ij")
    pworst = np.abs(pbr_neutral(np.stack([R, G, B], -1)).reshape(-1, 3) - pcube).max()
    if pworst > 1e-6:
        sys.exit("bake_agx: the Khronos PBR Neutral formula misses pbrNeutral.cube by %.3g" % pworst)

    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    lines = [
        "/* Generated by config/ocio/bake_agx.py from Blender 4.x's AgX files",
        " * (config.ocio, luts/AgX_Base_sRGB.cube, luts/luminance_compensation_bt2020.cube);",
        " * do not edit. Entries rounded to 16 bits move by at most %.2g (AgX)" % qerr,
        " * and %.2g (luminance compensation); the Khronos PBR Neutral formula gives" % lqerr,
        " * pbrNeutral.cube within %.2g. See the script for the format. */" % pworst,
        '#include "color/agx_builtin.h"',
        "",
    ]
    lines += c_matrix("pb_agx_rec709_to_egamut", to_egamut)
    lines += c_matrix("pb_agx_egamut_to_rec2020", egamut_to_2020)
    lines += c_matrix("pb_agx_log_inset", inset)
    lines += c_matrix("pb_agx_rec2020_to_rec709", r2020_to_709)
    for name, bl, b in (("pb_agx_cube", blob, b64), ("pb_agx_lumcomp_cube", lblob, lb64)):
        lines += ["const unsigned long %s_deflated_size = %d;" % (name, len(bl)), "",
                  "const char %s_base64[] =" % name]
        for k in range(0, len(b), 96):
            lines.append('    "%s"' % b[k:k + 96])
        lines[-1] += ";"
        lines.append("")
    lines += ["/* Blender's \"AgX - ...\" looks (process space AgX Log), as in its config.ocio. */"]
    lines += c_string("pb_agx_looks_yaml", "looks:\n" + "\n".join(looks))
    lines.append("")
    out = os.path.join(root, "src/color/agx_builtin.c")
    with open(out, "w") as f:
        f.write("\n".join(lines))
    print("bake_agx: wrote %s (%d^3 cube, %d deflated bytes, rounding %.3g; luminance compensation "
          "%d^3, %d bytes, rounding %.3g; %d looks; PBR Neutral formula %.3g)"
          % (out, n, len(blob), qerr, ln, len(lblob), lqerr, len(looks), pworst))


if __name__ == "__main__":
    main()
