#!/usr/bin/env python3
"""HDR-FLIP (NVIDIA FLIP 1.7, pip `flip-evaluator`) of one or more test
images against one reference, as JSON on stdout.

    tools/flip/bin/python bench/flip_mean.py REF.exr TEST.exr [TEST2.exr ...]

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
"stop_exposure", "exposures"}]}.
"""
import json
import sys

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


def main(argv):
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
            _, mean, params = flip.evaluate(ref, test, "HDR", inputsRGB=False, applyMagma=False)
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
