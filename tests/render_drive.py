#!/usr/bin/env python3
"""The render options a program driving photonbridge uses (the Blender
add-on), through the CLI:

  crop      --crop X,Y,W,H of a --width x --height frame equals that part of
            the full render to float rounding (same seed; photons, jitter, emitters);
  blender   --blender-layer NAME writes exactly Blender's multilayer EXR
            channels (NAME.Combined.R..A, NAME.Depth.Z, ...), Depth 1e10
            where nothing is hit, Combined equal to the plain beauty;
  progress  --progress-lines: JSON lines (stages, one per iteration, done);
            --preview written after each iteration but the last, a whole EXR;
            --time-limit stops the refinement early (fewer spp in the file);
            a sequence reports each frame;
  errors    bad --crop, a crop outside the frame, --crop with --frames, a
            --blender-layer with '.': exit 2 with one line naming the option.

usage: render_drive.py PHOTONBRIDGE EXR_PROBE ROOT WORKDIR [PART...]
Exit 77 when no Vulkan device is present."""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "pylib"))
import pbcheck  # noqa: E402
from pbcheck import Checker  # noqa: E402

EXE, PROBE, ROOT, WORK = sys.argv[1:5]
PARTS = sys.argv[5:] or ["errors", "crop", "blender", "progress"]
SCENE = os.path.join(ROOT, "samples", "cornell_box", "cornell_box.gltf")
T = Checker(EXE, WORK, PROBE)
check, run, fresh, exr = T.check, T.run, T.fresh, T.exr


# Two renders of one scene and seed agree to float rounding, not bit for bit
# (pbcheck.ROUNDING says why): on a device running workgroups in parallel
# (lavapipe on several threads, any GPU) the photon store's order, the order
# of Morton-code ties after the stable sort and so the order of the gather's
# sums follow the scheduling. A channel mix-up or a missing pass differs by
# far more.
ROUNDING = pbcheck.ROUNDING


def worst_rel(a, b):
    peak = max(max((abs(v) for v in a), default=0.0), 1e-6)
    return max((abs(x - y) for x, y in zip(a, b)), default=0.0) / peak


# Small and quick: 48 x 40, 4 jittered samples over 2 photon maps.
COMMON = ["--width", "48", "--height", "40", "--spp", "4", "--iterations", "2", "--photons", "8192",
          "--seed", "3", "-q"]


def part_errors():
    d = fresh("errors")
    out = d + "/x.exr"
    for args, needle in [(["--crop", "1,2,3"], "--crop '1,2,3'"), (["--crop", "0,0,0,4"], "--crop '0,0,0,4'"),
                         (["--crop", "40,0,16,8"], "does not fit"),
                         (["--crop", "0,0,8,8", "--frames", "0:1", "-o", d + "/f_#.exr"], "not with --frames"),
                         (["--blender-layer", "View.Layer"], "--blender-layer 'View.Layer'"),
                         (["--time-limit", "-1"], "--time-limit")]:
        argv = ["render", SCENE, "-o", out] + COMMON + args if "-o" not in args else ["render", SCENE] + COMMON + args
        p = run(argv, 2)
        lines = p.stderr.strip().splitlines()
        check(p.returncode == 2 and len(lines) == 1 and needle in lines[0],
              "%s: exit 2, one line naming it (%s)" % (" ".join(args), lines[-1] if lines else ""))
        check(not os.path.exists(out), "%s: no output" % " ".join(args))


def part_crop():
    d = fresh("crop")
    run(["render", SCENE, "-o", d + "/full.exr"] + COMMON)
    run(["render", SCENE, "-o", d + "/crop.exr", "--crop", "11,7,20,17"] + COMMON)
    full, crop = exr(d + "/full.exr"), exr(d + "/crop.exr")
    check(crop["width"] == 20 and crop["height"] == 17, "the crop is 20 x 17")
    worst, total = 0.0, 0.0
    names = ["R", "G", "B", "A", "indirect.R", "caustic.G", "direct.B", "depth.Z"]
    for ch in names:
        a = [full["channels"][ch][(y + 7) * 48 + x + 11] for y in range(17) for x in range(20)]
        b = crop["channels"][ch]
        worst = max(worst, worst_rel(a, b))
        total += sum(abs(v) for v in a)
    print("crop vs full frame: largest difference %g of the channel's peak over %s" % (worst, ", ".join(names)))
    check(total > 0 and worst <= ROUNDING,
          "the crop equals the full render there, channel for channel, to float rounding")


def part_blender():
    d = fresh("blender")
    run(["render", SCENE, "-o", d + "/plain.exr"] + COMMON)
    run(["render", SCENE, "-o", d + "/bl.exr", "--blender-layer", "ViewLayer"] + COMMON)
    plain, bl = exr(d + "/plain.exr"), exr(d + "/bl.exr")
    want = sorted(["ViewLayer.Combined." + c for c in "RGBA"] + ["ViewLayer.Depth.Z"] +
                  ["ViewLayer.Normal." + c for c in "XYZ"] +
                  ["ViewLayer.%s.%s" % (p, c) for p in ("Emit", "Direct", "Indirect", "Caustic", "Albedo")
                   for c in "RGB"])
    check(sorted(bl["channels"]) == want, "Blender's channel names, exactly: %s" % sorted(bl["channels"]))
    worst = max(worst_rel(plain["channels"][a], bl["channels"]["ViewLayer.Combined." + a]) for a in "RGBA")
    print("Combined vs the plain beauty: largest difference %g of the channel's peak" % worst)
    check(worst <= ROUNDING, "Combined is the beauty (to float rounding)")
    depth, alpha = bl["channels"]["ViewLayer.Depth.Z"], plain["channels"]["A"]
    misses = [z for z, a in zip(depth, alpha) if a == 0]
    hits = [(z, p) for z, p, a in zip(depth, plain["channels"]["depth.Z"], alpha) if a > 0]
    # Depth is the primary hit, traced without photons: exact in both runs.
    check(all(z == 1e10 for z in misses), "Depth is 1e10 where nothing is hit (%d pixels)" % len(misses))
    check(hits and all(z == p for z, p in hits), "Depth is the camera depth elsewhere")


def progress_lines(stderr):
    prefix = "photonbridge progress: "
    return [json.loads(l[len(prefix):]) for l in stderr.splitlines() if l.startswith(prefix)]


def part_progress():
    d = fresh("progress")
    args = ["render", SCENE, "-o", d + "/x.exr", "--progress-lines", "--preview", d + "/prev.exr",
            "--width", "32", "--height", "32", "--iterations", "3", "--photons", "4096"]
    p = run(args)
    ev = progress_lines(p.stderr)
    kinds = [e["event"] for e in ev]
    check(kinds == ["stage", "stage", "iteration", "iteration", "iteration", "done"], "events: %s" % kinds)
    its = [e for e in ev if e["event"] == "iteration"]
    check([e["iteration"] for e in its] == [1, 2, 3] and all(e["iterations"] == 3 for e in its),
          "one line per iteration, 1..3 of 3")
    check([e["preview"] is not None for e in its] == [True, True, False], "a preview after each but the last")
    check(ev[-1].get("output") == d + "/x.exr" and os.path.exists(d + "/x.exr"), "done names the output")
    prev = exr(d + "/prev.exr")
    check(prev["width"] == 32 and sum(prev["channels"]["G"]) > 0, "the preview is a whole EXR with light in it")
    left = sorted(f for f in os.listdir(d) if ".tmp" in f)
    check(not left, "no temporaries left (%s)" % left)
    # The time limit: 40 planned iterations, at most a few run in 0.5 s.
    p = run(["render", SCENE, "-o", d + "/t.exr", "--progress-lines", "--time-limit", "0.5", "--width", "16",
             "--iterations", "40", "--photons", "4096"])
    its = [e for e in progress_lines(p.stderr) if e["event"] == "iteration"]
    check(its and len(its) < 40 and its[-1]["iterations"] == len(its),
          "--time-limit 0.5 stopped after %d of 40 iterations" % len(its))
    with open(d + "/t.exr", "rb") as f:
        head = f.read(4096)
    key = b"photonbridge/spp\x00string\x00"
    spp = b""
    if key in head:  # an EXR string attribute: name, type, int32 size, value
        rest = head.split(key)[1]
        spp = rest[4:4 + int.from_bytes(rest[:4], "little")]
    check(spp.isdigit() and int(spp) == its[-1]["spp"] and int(spp) < 40,
          "the file records the samples it averaged (%s)" % spp)
    # A sequence reports its frames.
    p = run(["render", os.path.join(ROOT, "samples", "cornell_box_moving_light", "cornell_box_moving_light.gltf"),
             "--frames", "0:1", "-o", d + "/f_#.exr", "--progress-lines", "--width", "16", "--photons", "4096"])
    fr = [e for e in progress_lines(p.stderr) if e["event"] == "frame"]
    check([(e["frame"], e["index"], e["frames"]) for e in fr] == [(0, 0, 2), (1, 1, 2)] and
          all(os.path.exists(e["output"]) for e in fr), "a sequence reports each frame with its file")


def main():
    if not T.has_device():
        print("skip: no Vulkan device")
        return 77
    for part in PARTS:
        globals()["part_" + part]()
    return T.finish()


if __name__ == "__main__":
    sys.exit(main())
