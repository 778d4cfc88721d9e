#!/usr/bin/env python3
"""Frame sequences, through the CLI:

  smoke     every animated sample renders a short sequence: one EXR per frame
            with its frame number and time, --json lists the frames, the
            moving ones are not "still", the temporal filter ran;
  flicker   cornell_box_moving_light, 64 px, 8 frames, few photons, against
            per-frame references (cached): temporal + A-Trous has at least 4x
            less excess flicker than no filter, and its mean per-frame error
            (relMSE) is no worse;
  still     cornell_box with a still camera converges: the error against the
            reference falls frame after frame (16 frames: >= 2 dB);
  orbit     --orbit moves the camera around a scene without animation;
  caustics  cornell_caustics_moving_sphere (48 px, 8 frames): the filters (the
            caustics' own clamped temporal filter included) cut the excess
            flicker at least 3x with per-frame error no worse;
  splat     cornell_box_moving_light (48 px, 8 frames) with --estimator splat
            (seed 001's screen-space splatting): the same, 3x;
  materials KHR_texture_transform with TEXCOORD_1 (tests/data/gltf_ext) through
            --frames: every frame equals the baked texture's (> 45 dB);
  deform    Blender's skinned and shape-keyed scene (tests/data/deform, 48 px,
            frames 12-19): the same, 3x (measured 6x), with no ghost of the
            deformation;
  errors    bad --frames, an output name without '#', --orbit without
            --frames: exit 2 with one line naming the option.

usage: sequence_check.py PHOTONBRIDGE ROOT WORKDIR [PART...]
Exit 77 when no Vulkan device is present."""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "pylib"))
from pbcheck import Checker  # noqa: E402

EXE, ROOT, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
PARTS = sys.argv[4:] or ["errors", "smoke", "orbit", "still", "flicker", "caustics", "splat", "materials", "deform", "vsch"]
T = Checker(EXE, WORK)
check, run, fresh = T.check, T.run, T.fresh


def sample(name):
    return os.path.join(ROOT, "samples", name, name + ".gltf")


def exr_attrs(path):
    """photonbridge/frame and /time from the EXR header (plain bytes scan)."""
    data = open(path, "rb").read(4096)
    out = {}
    for key in (b"photonbridge/frame", b"photonbridge/time"):
        i = data.find(key + b"\0string\0")
        if i >= 0:
            j = i + len(key) + 8
            n = int.from_bytes(data[j:j + 4], "little")
            out[key.decode()] = data[j + 4:j + 4 + n].decode()
    return out


if subprocess.run([EXE, "info", "--devices"], capture_output=True).returncode != 0:
    print("skip: no Vulkan device")
    sys.exit(77)

if "errors" in PARTS:
    d = fresh("errors")
    cases = [
        (["--frames", "3:1", "-o", d + "/f_#.exr"], "--frames '3:1'"),
        (["--frames", "x", "-o", d + "/f_#.exr"], "--frames 'x'"),
        (["--frames", "0:2", "-o", d + "/f.exr"], "needs '#'"),
        (["--orbit", "-o", d + "/f.exr"], "need --frames"),
        (["--frames", "0:1", "--fps", "-1", "-o", d + "/f_#.exr"], "--fps"),
    ]
    for args, want in cases:
        p = run(["render", sample("cornell_box"), "--width", "16"] + args, expect_rc=2)
        lines = [l for l in p.stderr.splitlines() if l.strip()]
        check(p.returncode == 2 and len(lines) == 1 and want in lines[0],
              "error %s: exit %d, %r" % (" ".join(args[:2]), p.returncode, lines[:2]))
    check(os.listdir(d) == [], "errors leave no output behind")

if "smoke" in PARTS:
    for name in ("cornell_box_moving_light", "cornell_caustics_moving_sphere", "sun_atrium_flythrough"):
        d = fresh("smoke_" + name)
        p = run(["render", sample(name), "--frames", "10:12", "--width", "32", "--photons", "8192",
                 "-o", d + "/f_###.exr", "--png", d + "/f_###.png", "--json", d + "/seq.json"])
        check(p.returncode == 0, "%s: 3 frames render (exit %d)" % (name, p.returncode))
        if p.returncode:
            continue
        files = sorted(os.listdir(d))
        check(files == ["f_010.exr", "f_010.png", "f_011.exr", "f_011.png", "f_012.exr", "f_012.png", "seq.json"],
              "%s: one EXR and PNG per frame: %s" % (name, files))
        a = exr_attrs(d + "/f_011.exr")
        check(a.get("photonbridge/frame") == "11" and abs(float(a.get("photonbridge/time", "nan")) - 11 / 24) < 1e-6,
              "%s: frame 11's EXR says frame 11 at t = 11/24 s: %s" % (name, a))
        js = json.load(open(d + "/seq.json"))
        fr = js["frames"]
        check(len(fr) == 3 and [f["frame"] for f in fr] == [10, 11, 12], "%s: --json lists the frames" % name)
        check(all(not f["still"] for f in fr[1:]), "%s: the moving frames are not still" % name)
        moved = {"cornell_box_moving_light": "lights_moved", "cornell_caustics_moving_sphere": "geometry_moved",
                 "sun_atrium_flythrough": "camera_moved"}[name]
        check(all(f[moved] for f in fr[1:]), "%s: %s in every frame after the first" % (name, moved))
        check(js["filters"]["temporal"] and js["filters"]["atrous_iterations"] == 4
              and all("temporal" in f for f in fr), "%s: temporal + 4 A-Trous passes by default" % name)

if "orbit" in PARTS:
    d = fresh("orbit")
    p = run(["render", sample("cornell_box"), "--frames", "0:3", "--orbit", "--width", "32", "--photons", "8192",
             "-o", d + "/o_#.exr", "--json", d + "/o.json"])
    check(p.returncode == 0, "orbit renders (exit %d)" % p.returncode)
    if p.returncode == 0:
        fr = json.load(open(d + "/o.json"))["frames"]
        check(all(f["camera_moved"] and not f["still"] for f in fr[1:]), "orbit: the camera moves every frame")
        # A quarter turn per frame: about a quarter of the pixels keep a surface
        # seen before, the rest reset; never all history kept.
        check(all(f["temporal"]["reset_fraction"] > 0.05 for f in fr[1:]), "orbit: disocclusions reset history")

cache = os.path.join(WORK, "reference_cache")
os.makedirs(cache, exist_ok=True)

if "still" in PARTS:
    d = fresh("still")
    p = run(["render", sample("cornell_box"), "--frames", "0:15", "--width", "48", "--height", "48",
             "--photons", "16384", "--reference-spp", "1024", "--reference-cache", cache,
             "-o", d + "/s_#.exr", "--json", d + "/s.json"])
    check(p.returncode == 0, "still view renders (exit %d)" % p.returncode)
    if p.returncode == 0:
        fr = json.load(open(d + "/s.json"))["frames"]
        ps = [f["reference"]["psnr_db"] for f in fr]
        print("still: PSNR per frame " + " ".join("%.2f" % x for x in ps))
        check(all(f["still"] for f in fr[1:]), "still: frames after the first are still")
        # Since r_max follows the photon density the first
        # frame is less noisy (24.3 dB, was 23.4 at the old 5 % clamp) and the
        # run ends at the same bias-limited 26.7-26.9 dB, so 16 frames gain
        # about 2.4 dB (3.3 at the old clamp); frames alternate by up to
        # 0.31 dB with the jitter pattern.
        check(all(b >= a - 0.4 for a, b in zip(ps, ps[1:])), "still: the error never grows by more than noise")
        check(ps[-1] >= ps[0] + 2.0, "still: 16 frames gain >= 2 dB over the first (%.2f -> %.2f)" % (ps[0], ps[-1]))
        check(fr[-1]["temporal"]["mean_history"] > 15.5, "still: history length 16 after 16 frames (%.2f)" %
              fr[-1]["temporal"]["mean_history"])

def filtered_vs_raw(part, scene, size, ref_spp, factor, frames="0:7", extra=()):
    """The same 8 frames with the filters off and with the defaults, against
    cached references: the filtered excess flicker at least `factor` times
    lower, the mean per-frame relMSE no worse (a ghost of a moving or
    deforming object would raise it)."""
    d = fresh(part)
    path = scene if scene.endswith(".gltf") else sample(scene)
    common = ["render", path, "--frames", frames, "--width", str(size), "--height", str(size),
              "--photons", "16384", "--reference-spp", str(ref_spp), "--reference-cache", cache] + list(extra)
    p0 = run(common + ["--no-temporal", "--atrous-iterations", "0", "-o", d + "/raw_#.exr", "--json", d + "/raw.json"])
    p1 = run(common + ["-o", d + "/filt_#.exr", "--json", d + "/filt.json"])
    check(p0.returncode == 0 and p1.returncode == 0, "%s: both sequences render" % part)
    if p0.returncode or p1.returncode:
        return
    raw = json.load(open(d + "/raw.json"))["summary"]
    filt = json.load(open(d + "/filt.json"))["summary"]
    for name, s in (("unfiltered", raw), ("filtered  ", filt)):
        print("%s: %s excess flicker %.5f (result %.5f, reference %.5f), relMSE %.5f, %.2f dB" %
              (part, name, s["flicker_excess"], s["flicker_result"], s["flicker_reference"], s["mean_relmse"],
               s["mean_psnr_db"]))
    check(raw["flicker_excess"] > 0, "%s: the unfiltered sequence flickers more than the reference" % part)
    check(filt["flicker_excess"] * factor <= raw["flicker_excess"],
          "%s: filtered excess flicker at least %gx below unfiltered" % (part, factor))
    check(filt["mean_relmse"] <= raw["mean_relmse"], "%s: filtered per-frame error no worse" % part)


if "flicker" in PARTS:
    filtered_vs_raw("flicker", "cornell_box_moving_light", 64, 1024, 4)

if "vsch" in PARTS:
    # The view-sample cluster hierarchy (seed 004) under the same temporal
    # filter and A-Trous: the filters follow the estimator's accumulator.
    filtered_vs_raw("vsch", "cornell_box_moving_light", 64, 1024, 4, extra=["--estimator", "vsch"])

if "caustics" in PARTS:
    filtered_vs_raw("caustics", "cornell_caustics_moving_sphere", 48, 256, 3)

if "splat" in PARTS:
    # The screen-space splatting estimator (seed 001 24.3) under the same
    # temporal + A-Trous filters (its chapter's 24.4): they accept its
    # estimate as they do the LBVH gather's.
    filtered_vs_raw("splat", "cornell_box_moving_light", 48, 256, 3, extra=["--estimator", "splat"])
    js = json.load(open(os.path.join(WORK, "splat", "filt.json")))
    est = js.get("estimator") or (js.get("frames") or [{}])[0].get("estimator") or {}
    check(est.get("name") == "splat", "splat: --json names the estimator (%r)" % est.get("name"))

if "materials" in PARTS:
    # KHR_texture_transform with TEXCOORD_1 through --frames (the frame
    # context keeps the uv sets between frames): every frame of the
    # transformed texture's sequence equals the baked texture's.
    d = fresh("materials")
    ext = os.path.join(ROOT, "tests", "data", "gltf_ext")
    for name in ("texture_transform", "texture_baked"):
        p = run(["render", os.path.join(ext, name + ".gltf"), "--frames", "0:2", "--width", "32", "--photons", "8192",
                 "-o", os.path.join(d, name + "_#.exr"), "-q"])
        check(p.returncode == 0, "materials: %s renders 3 frames (exit %d)" % (name, p.returncode))
    for f in range(3):
        p = run(["compare", os.path.join(d, "texture_transform_%d.exr" % f), os.path.join(d, "texture_baked_%d.exr" % f),
                 "--json", "-"])
        db = json.loads(p.stdout)["psnr_db"] if p.returncode == 0 else 0
        db = float("inf") if db is None else db  # identical pictures: no finite PSNR
        check(db > 45, "materials: frame %d, transformed texture against the baked one: %.1f dB (> 45)" % (f, db))

if "deform" in PARTS:
    # Blender's skinned cylinder and shape-key cube (tests/data/deform), frames
    # 12-19 of their bending: the motion vectors follow the deformed vertices.
    filtered_vs_raw("deform", os.path.join(ROOT, "tests", "data", "deform", "deform.gltf"), 48, 256, 3, "12:19")

sys.exit(T.finish())
