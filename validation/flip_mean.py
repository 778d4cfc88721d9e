#!/usr/bin/env python3
"""HDR-FLIP (NVIDIA FLIP 1.7, pip `flip-evaluator`) of one or more test
images against one reference, as JSON on stdout.

    tools/flip/bin/python validation/flip_mean.py REF.exr TEST.exr [TEST2.exr ...] [--map OUT.png]

Both are scene-linear float RGB EXRs (photonbridge's beauty, a peer's
render): HDR-FLIP takes linear sRGB/Rec.709 radiance, tone-maps it at a range
of exposures chosen from the reference (FLIP's default ACES tone mapper,
start and stop exposures computed by FLIP from the reference, 67 pixels per
degree) and reports the mean over pixels of the largest LDR-FLIP over those
exposures: 0 = indistinguishable, 1 = maximal. The exposures depend on the
reference only, so every test image of one reference is judged alike.
Non-finite or negative test pixels are set to 0 (FLIP needs non-negative
values) and counted. Output: {"flip": "HDR", "version", "reference",
"results": [{"test", "hdr_flip_mean", "nonfinite", "start_exposure",
"stop_exposure", "exposures"}]}. --map (one test image): FLIP's error map
as an 8-bit PNG in FLIP's own magma colours (black 0 to light yellow 1), for
the validation report.
"""
import json
import struct
import sys
import zlib

import numpy as np
import flip_evaluator as flip


def load(path):
    img = np.asarray(flip.load(path), dtype=np.float32)
    if img.ndim == 2:
        img = np.repeat(img[:, :, None], 3, axis=2)
    img = img[:, :, :3]
    bad = ~np.isfinite(img)
    img = np.where(bad | (img < 0), 0.0, img).astype(np.float32)
    return np.ascontiguousarray(img), int(bad.any(axis=2).sum())


def write_png(path, rgb):
    """rgb: H x W x 3 floats in [0, 1], as an 8-bit PNG (no other writer in
    this venv)."""
    a = (np.clip(rgb, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)
    h, w = a.shape[:2]
    raw = b"".join(b"\x00" + a[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def main(argv):
    map_png = None
    if "--map" in argv:
        i = argv.index("--map")
        map_png = argv[i + 1] if i + 1 < len(argv) else None
        argv = argv[:i] + argv[i + 2:]
        if not map_png or len(argv) != 2:
            print("flip_mean: --map OUT.png takes one test image", file=sys.stderr)
            return 2
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    ref, _ = load(argv[0])
    out = {"flip": "HDR", "reference": argv[0], "results": []}
    try:
        import importlib.metadata as md
        out["version"] = md.version("flip-evaluator")
    except Exception:
        out["version"] = None
    for t in argv[1:]:
        try:
            test, nonfinite = load(t)
            if test.shape != ref.shape:
                raise ValueError("size %s differs from the reference's %s" % (test.shape, ref.shape))
            fmap, mean, params = flip.evaluate(ref, test, "HDR", inputsRGB=False, applyMagma=map_png is not None)
            if map_png:
                write_png(map_png, np.asarray(fmap, dtype=np.float32))
            out["results"].append({"test": t, "hdr_flip_mean": float(mean), "nonfinite": nonfinite,
                                   "start_exposure": params.get("startExposure"),
                                   "stop_exposure": params.get("stopExposure"),
                                   "exposures": params.get("numExposures")})
        except Exception as e:  # one bad image must not hide the others
            out["results"].append({"test": t, "error": str(e)})
    json.dump(out, sys.stdout)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
