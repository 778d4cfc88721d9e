#!/usr/bin/env python3
"""render --frames A:B --warmup N, through the CLI:

  errors  --warmup without --frames, a negative or too large warm-up: exit 2
          with one line naming --warmup;
  seeds   the photon seeds follow the frame number alone: without the
          temporal filter, frame 3 of `--frames 3:3` equals frame 3 of
          `--frames 1:3` (to float rounding);
  chunks  a shot 0..5 of an animated sample in 3 chunks of 2 frames with a
          warm-up of 2: each chunk writes only its own frames (the warm-up
          frames not), its --json lists them, and its frames equal those of
          one run of the same frames after the same warm-up, i.e. frames
          a..b of `--frames a-2:b` (to float rounding).

usage: chunks_check.py PHOTONBRIDGE EXR_PROBE ROOT WORKDIR [PART...]
Exit 77 when no Vulkan device is present."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import RENDER, check, fresh, failures, has_device, run, sample, worst_rel, ROUNDING  # noqa: E402

EXE, PROBE, ROOT, WORK = [os.path.abspath(a) for a in sys.argv[1:5]]
PARTS = sys.argv[5:] or ["errors", "seeds", "chunks"]
SCENE = sample(ROOT)


def part_errors():
    d = fresh(os.path.join(WORK, "errors"))
    for args, needle in [
        (["--warmup", "2", "-o", d + "/f.exr"], "--warmup"),
        (["--frames", "0:1", "--warmup", "-1", "-o", d + "/f_#.exr"], "--warmup"),
        (["--frames", "0:1", "--warmup", "20000", "-o", d + "/f_#.exr"], "--warmup"),
        (["--frames=-999999:-999998", "--warmup", "5", "-o", d + "/f_#.exr"], "--warmup"),
    ]:
        p = run([EXE, "render", SCENE, "--width", "16"] + args, expect_rc=2)
        lines = [l for l in p.stderr.splitlines() if l.strip()]
        check(p.returncode == 2 and len(lines) == 1 and needle in lines[0],
              "%s: exit 2 naming %s (%d, %r)" % (" ".join(args), needle, p.returncode, p.stderr.strip()[:200]))
    check(not os.listdir(d), "errors: nothing written")


def part_seeds():
    d = fresh(os.path.join(WORK, "seeds"))
    common = [EXE, "render", SCENE, "--no-temporal"] + RENDER
    p1 = run(common + ["--frames", "3:3", "-o", d + "/one_#.exr"])
    p2 = run(common + ["--frames", "1:3", "-o", d + "/run_#.exr"])
    check(p1.returncode == 0 and p2.returncode == 0, "seeds: both runs render")
    if p1.returncode == 0 and p2.returncode == 0:
        w = worst_rel(PROBE, d + "/one_3.exr", d + "/run_3.exr")
        check(w <= ROUNDING, "seeds: frame 3 alone equals frame 3 of 1..3 (largest difference %.3g of the peak)" % w)
        w = worst_rel(PROBE, d + "/run_2.exr", d + "/run_3.exr")
        check(w > 100 * ROUNDING, "seeds: frames 2 and 3 differ (%.3g of the peak)" % w)


def part_chunks():
    d = fresh(os.path.join(WORK, "chunks"))
    warm = 2
    common = [EXE, "render", SCENE] + RENDER
    for a, b in [(0, 1), (2, 3), (4, 5)]:
        sub = fresh(os.path.join(d, "c%d" % a))
        p = run(common + ["--frames", "%d:%d" % (a, b), "--warmup", str(warm), "-o", sub + "/f_##.exr",
                          "--json", sub + "/seq.json"])
        check(p.returncode == 0, "chunk %d:%d --warmup %d renders" % (a, b, warm))
        if p.returncode != 0:
            continue
        names = sorted(os.listdir(sub))
        want = sorted(["f_%02d.exr" % f for f in range(a, b + 1)] + ["seq.json"])
        check(names == want, "chunk %d:%d writes only its frames (%s)" % (a, b, " ".join(names)))
        js = json.load(open(sub + "/seq.json"))
        check([f["frame"] for f in js["frames"]] == list(range(a, b + 1)) and js.get("warmup_frames") == warm,
              "chunk %d:%d: --json lists frames %d..%d and warmup_frames %d" % (a, b, a, b, warm))
        ref = fresh(os.path.join(d, "r%d" % a))
        p = run(common + ["--frames=%d:%d" % (a - warm, b), "-o", ref + "/f_##.exr"])
        check(p.returncode == 0, "one run %d:%d renders" % (a - warm, b))
        if p.returncode != 0:
            continue
        for f in range(a, b + 1):
            w = worst_rel(PROBE, sub + "/f_%02d.exr" % f, ref + "/f_%02d.exr" % f)
            check(w <= ROUNDING, "frame %d of chunk %d:%d equals frame %d of one run %d:%d (%.3g of the peak)" %
                  (f, a, b, f, a - warm, b, w))


if not has_device(EXE):
    print("skip: no Vulkan device")
    sys.exit(77)
for part in PARTS:
    globals()["part_" + part]()
if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("all checks passed")
