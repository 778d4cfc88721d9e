#!/usr/bin/env python3
"""compare's HDR-FLIP (src/metrics/flip.c) against NVIDIA's FLIP 1.7
(flip-evaluator in tools/flip, through validation/flip_mean.py's cleaning)
on pairs of images made from committed EXRs and one CPU reference render:

    tests/flip_agreement.py PHOTONBRIDGE OUTDIR

Per pair: |C - FLIP| <= 0.002 and <= 2 % of FLIP's mean; the same start
and stop exposures (to 1e-4) and the same number of exposures; the pixels
taken as 0 counted. One pair's --heatmap-metric flip PNG against FLIP's
own map (flip_mean.py --map). tools/flip is installed by
scripts/install-deps.sh: without it this test FAILS (PB_FLIP_PYTHON names
another interpreter that has flip_evaluator).

The pairs are made by this same script run under FLIP's interpreter
(--pairs OUTDIR: numpy and flip_evaluator are there only)."""
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import imgmini  # noqa: E402

ABS_TOL, REL_TOL, EXP_TOL = 0.002, 0.02, 1e-4


def make_pairs(out):
    """Under tools/flip's Python: writes the pairs' EXRs and FLIP's numbers
    for them to OUT/pairs.json."""
    import numpy as np
    import flip_evaluator as flip
    sys.path.insert(0, os.path.join(ROOT, "validation"))
    import flip_mean

    def load(rel):
        return np.asarray(flip.load(os.path.join(ROOT, rel)), dtype=np.float32)[:, :, :3]

    def save(name, img):
        img = np.ascontiguousarray(img, dtype=np.float32)
        path = os.path.join(out, name + ".exr")
        imgmini.write_rgb(path, img.shape[1], img.shape[0],
                          *(img[:, :, c].astype("<f4").tobytes() for c in range(3)))
        return path

    rng = np.random.default_rng(7)
    ring64 = load("tests/data/ring/ring_64_ref.exr")
    r128 = load("tests/data/ring/ring_128_ref.exr")
    spot = load("tests/data/lights/spot_soft/cycles.exr")
    world = load("tests/data/lights/world_hdri/cycles.exr")
    diffuse = load("tests/data/principled2/diffuse/cycles.exr")
    plastic = load("samples/blender/metal_plastic/cycles.exr")
    glass_old, glass_new = load("samples/blender/glass_ball/cycles.exr"), load("samples/blender45/glass_ball/cycles.exr")
    hdri_old, hdri_new = load("samples/blender/hdri/cycles.exr"), load("samples/blender45/hdri/cycles.exr")
    noise = lambda img, s: img * np.exp(rng.normal(0.0, s, img.shape)).astype(np.float32)  # noqa: E731
    bad = noise(plastic, 0.1)
    bad[3, 5, 0], bad[10, 20, 1], bad[30, 40, :] = -0.5, np.nan, np.inf
    bad_ref = plastic.copy()
    bad_ref[50, 60, 2] = -1.0
    pairs = [
        # name, reference, test, why
        ("ring_biased", save("ring64", ring64),
         save("ring128_down", r128.reshape(36, 2, 64, 2, 3).mean(axis=(1, 3))),
         "the ring's 64 px reference against its 128 px one box-filtered"),
        ("ring_noisy", save("ring64", ring64), os.path.join(out, "ring_noisy.exr"),
         "the ring's reference against a 1-sample CPU reference render"),
        ("self", save("spot", spot), save("spot", spot), "an image against itself"),
        ("scaled", save("world", world), save("world_x1.25", world * 1.25), "against a copy 1.25 times as bright"),
        ("dark", save("spot_dark", spot * 1e-3), save("spot_dark_noisy", noise(spot * 1e-3, 0.3)),
         "a dark pair (1/1000)"),
        ("bright", save("glass45_bright", glass_new * 1e3), save("glass_bright", glass_old * 1e3),
         "a very bright pair (x1000), two Cycles versions"),
        ("mostly_black", save("diffuse", diffuse), save("diffuse_noisy", noise(diffuse, 0.2)),
         "a reference whose median luminance is 0"),
        ("bad_values", save("plastic_badref", bad_ref), save("plastic_bad", bad),
         "negative, NaN and Inf values in both images"),
        ("tiny", save("hdri45_7x5", hdri_new[30:35, 40:47]), save("hdri_7x5", hdri_old[30:35, 40:47]),
         "a 7x5 crop, smaller than FLIP's filters"),
    ]
    result = []
    for name, ref, test, why in pairs:
        r, _ = flip_mean.load(ref)
        t, _ = flip_mean.load(test)
        _, mean, params = flip.evaluate(r, t, "HDR", inputsRGB=False, applyMagma=False)
        raw_r = np.asarray(flip.load(ref), dtype=np.float32)[:, :, :3]
        raw_t = np.asarray(flip.load(test), dtype=np.float32)[:, :, :3]
        zeroed = int(((~np.isfinite(raw_r) | (raw_r < 0)).any(axis=2) |
                      (~np.isfinite(raw_t) | (raw_t < 0)).any(axis=2)).sum())
        result.append({"name": name, "why": why, "reference": ref, "test": test, "flip": float(mean),
                       "start": params["startExposure"], "stop": params["stopExposure"],
                       "exposures": params["numExposures"], "zeroed": zeroed})
    with open(os.path.join(out, "pairs.json"), "w") as f:
        json.dump(result, f, indent=1)
    return 0


def main(argv):
    from pbcheck import check, debian_python, finish
    try:
        from PIL import Image
    except ImportError:  # pyenv's python without Debian's packages
        debian_python("flip_agreement")
    exe, out = argv[0], argv[1]
    os.makedirs(out, exist_ok=True)
    fpy = os.environ.get("PB_FLIP_PYTHON") or os.path.join(ROOT, "tools", "flip", "bin", "python")
    ok = os.path.isfile(fpy) and subprocess.run([fpy, "-c", "import flip_evaluator"],
                                                capture_output=True).returncode == 0
    if not check(ok, "NVIDIA FLIP is not installed: %s cannot import flip_evaluator (run "
                 "scripts/install-deps.sh, which puts flip-evaluator 1.7 in tools/flip, or set "
                 "PB_FLIP_PYTHON)" % fpy):
        finish("flip_agreement")
    noisy = os.path.join(out, "ring_noisy.exr")
    p = subprocess.run([exe, "reference", os.path.join(ROOT, "samples/ring/ring.gltf"), "-o", noisy,
                        "--width", "64", "--spp", "1", "--seed", "3", "-q"], capture_output=True, text=True)
    check(p.returncode == 0, "the ring's CPU reference render: %s" % p.stderr.strip())
    p = subprocess.run([fpy, os.path.abspath(__file__), "--pairs", out], capture_output=True, text=True)
    if not check(p.returncode == 0, "making the pairs under FLIP's Python: %s" % p.stderr.strip()[-2000:]):
        finish("flip_agreement")
    with open(os.path.join(out, "pairs.json")) as f:
        pairs = json.load(f)
    print("%-13s %10s %10s %9s  %s" % ("pair", "C", "FLIP 1.7", "diff", "exposures C / FLIP"))
    for q in pairs:
        p = subprocess.run([exe, "compare", q["test"], q["reference"], "--json", "-"], capture_output=True, text=True)
        if not check(p.returncode == 0, "%s: compare exit %d: %s" % (q["name"], p.returncode, p.stderr.strip())):
            continue
        j = json.loads(p.stdout)
        c, ref = j.get("hdr_flip"), q["flip"]
        print("%-13s %10.6f %10.6f %+9.2e  %s %s %s / %.6f %.6f %d" % (
            q["name"], c if c is not None else float("nan"), ref, (c or 0.0) - ref,
            j.get("hdr_flip_start_exposure"), j.get("hdr_flip_stop_exposure"), j.get("hdr_flip_exposures"),
            q["start"], q["stop"], q["exposures"]))
        if not check(isinstance(c, (int, float)) and not isinstance(c, bool), "%s: hdr_flip is %r" % (q["name"], c)):
            continue
        check(abs(c - ref) <= ABS_TOL and abs(c - ref) <= REL_TOL * ref + 1e-9,
              "%s (%s): C %.6f, FLIP %.6f" % (q["name"], q["why"], c, ref))
        check(abs(j["hdr_flip_start_exposure"] - q["start"]) <= EXP_TOL and
              abs(j["hdr_flip_stop_exposure"] - q["stop"]) <= EXP_TOL and
              j["hdr_flip_exposures"] == q["exposures"],
              "%s: exposures %s .. %s (%s), FLIP's %s .. %s (%s)" % (
                  q["name"], j["hdr_flip_start_exposure"], j["hdr_flip_stop_exposure"],
                  j["hdr_flip_exposures"], q["start"], q["stop"], q["exposures"]))
        check(j["hdr_flip_zeroed_pixels"] == q["zeroed"],
              "%s: %s pixels taken as 0, expected %d" % (q["name"], j["hdr_flip_zeroed_pixels"], q["zeroed"]))
        if q["name"] == "self":
            check(c == 0.0, "an image against itself: FLIP %r, not 0" % c)

    # The error map: FLIP's own PNG (flip_mean.py --map) and compare's.
    q = next(q for q in pairs if q["name"] == "ring_noisy")
    mine, theirs = os.path.join(out, "map_c.png"), os.path.join(out, "map_flip.png")
    p = subprocess.run([exe, "compare", q["test"], q["reference"], "--heatmap", mine,
                        "--heatmap-metric", "flip", "-q"], capture_output=True, text=True)
    check(p.returncode == 0, "compare --heatmap-metric flip: %s" % p.stderr.strip())
    p = subprocess.run([fpy, os.path.join(ROOT, "validation/flip_mean.py"), q["reference"], q["test"],
                        "--map", theirs], capture_output=True, text=True)
    check(p.returncode == 0, "flip_mean.py --map: %s" % p.stderr.strip())
    if os.path.isfile(mine) and os.path.isfile(theirs):
        a, b = Image.open(mine), Image.open(theirs)
        check((a.size, a.mode) == (b.size, b.mode), "map %s %s and FLIP's %s %s" % (a.size, a.mode, b.size, b.mode))
        diffs = [abs(x - y) for x, y in zip(a.tobytes(), b.tobytes())]
        same = sum(1 for d in diffs if d == 0) / max(1, len(diffs))
        print("map: %.2f %% of values the same as FLIP's, largest difference %d" % (100 * same, max(diffs)))
        check(same >= 0.98 and max(diffs) <= 8, "the map differs from FLIP's: %.2f %% the same, "
              "largest difference %d" % (100 * same, max(diffs)))
    finish("flip_agreement")


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--pairs":
        sys.exit(make_pairs(sys.argv[2]))
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    main(sys.argv[1:])
