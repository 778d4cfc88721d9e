#!/usr/bin/env python3
"""Blender's viewport in photonbridge mode: Blender
with its window (not -b) under `xvfb-run -a` (Mesa's llvmpipe for OpenGL,
lavapipe for photonbridge), tests/blender/bl_viewport.py setting a 3D view
to RENDERED shading with the photonbridge engine. After the engine has drawn
its last still pass (PHOTONBRIDGE_VIEWPORT_PASSES), the window's screenshot,
cropped to the 3D view's region and box-filtered down to the size
photonbridge rendered (the region over the viewport's Pixel Size), is
compared with `photonbridge render --frames 0:N-1` of the same scene with a
camera made from the view's matrices (same settings and seed; its last
frame, through `display --view Standard`, the view transform the scene
uses, stretched and box-filtered back as the viewport's was): the picture is
not blank, and their mean difference is within the noise (at most 0.6 x the
difference between two seeds of the CLI render, and at most 2 8-bit steps).
Then the view orbits: the picture changes and refines again in the same
serve process without a reload; the cube moves: one reload, the picture
changes; the cube's material turns red: one reload, the picture reddens. Leaving Rendered shading ends the serve process (the engine's
free()) while Blender runs; none outlives Blender. A serve that dies at once
(a stand-in binary printing one error line, exit 3): the viewport's status
and Blender's report carry its line and exit code, and Blender goes on.

Exit 77 (skip) with one line where Blender, xvfb-run or a Vulkan device is
missing.
usage: viewport_check.py PHOTONBRIDGE ROOT WORKDIR"""
import json
import os
import shutil
import subprocess
import sys

try:
    import numpy as np
    from PIL import Image
except ImportError:  # pyenv's python without Debian's packages
    if sys.executable != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    print("viewport_check: needs numpy and Pillow (python3-numpy, python3-pil)")
    sys.exit(77)

EXE, ROOT, WORK = sys.argv[1:4]
EXE, WORK, ROOT = os.path.abspath(EXE), os.path.abspath(WORK), os.path.abspath(ROOT)
HERE = os.path.join(ROOT, "tests", "blender")  # after ROOT is absolute
PASSES = 3


def fail(msg):
    print("viewport_check: FAIL: %s" % msg)
    sys.exit(1)


def skip(msg):
    print("viewport_check: SKIP: %s" % msg)
    sys.exit(77)


def env():
    e = dict(os.environ)
    e["PATH"] = ":".join(p for p in e.get("PATH", "").split(":") if "pyenv" not in p)
    scripts = os.path.join(WORK, "scripts")
    os.makedirs(os.path.join(scripts, "addons"), exist_ok=True)
    link = os.path.join(scripts, "addons", "photonbridge")
    if not os.path.islink(link):
        os.symlink(os.path.join(ROOT, "exporters", "blender", "photonbridge"), link)
    e["BLENDER_USER_SCRIPTS"] = scripts
    e["PHOTONBRIDGE_BIN"] = EXE
    e["PHOTONBRIDGE_VIEWPORT_PASSES"] = str(PASSES)
    return e


def serve_pids():
    out = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open("/proc/%s/cmdline" % d, "rb") as f:
                    argv = f.read().split(b"\0")
            except OSError:
                continue
            if len(argv) > 2 and argv[0] == EXE.encode() and argv[1] == b"serve":
                out.append(int(d))
    return out


def png(path):
    return np.asarray(Image.open(path).convert("RGB")).astype(np.float64)


def main():
    if not shutil.which("blender"):
        skip("Blender is not installed (apt-get install blender)")
    if not shutil.which("xvfb-run"):
        skip("xvfb-run is not installed (apt-get install xvfb xauth)")
    p = subprocess.run([EXE, "info", "--devices"], capture_output=True, text=True, timeout=120)
    if p.returncode != 0:
        skip("no usable Vulkan device")
    shutil.rmtree(WORK, ignore_errors=True)
    out = os.path.join(WORK, "out")
    os.makedirs(out)
    e = env()
    before = set(serve_pids())
    # A saved factory file, opened with the window: no splash over the view.
    blend = os.path.join(WORK, "start.blend")
    p = subprocess.run(["blender", "-b", "--factory-startup", "--python-expr",
                        "import bpy; bpy.ops.wm.save_as_mainfile(filepath=%r)" % blend],
                       capture_output=True, text=True, env=e, timeout=300)
    if p.returncode != 0 or not os.path.exists(blend):
        fail("could not save the start file: %s" % p.stderr[-2000:])
    argv = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "blender", "--factory-startup", blend,
            "--python", os.path.join(HERE, "bl_viewport.py"), "--", out, str(PASSES)]
    try:
        p = subprocess.run(argv, capture_output=True, text=True, env=e, timeout=600)
    except subprocess.TimeoutExpired:
        fail("Blender did not quit within 600 s")
    log = p.stdout + p.stderr
    with open(os.path.join(WORK, "blender.log"), "w") as f:
        f.write(log)
    if os.path.exists(os.path.join(out, "error.txt")):
        with open(os.path.join(out, "error.txt")) as f:
            fail("Blender side: %s\n%s" % (f.read().strip(), log[-3000:]))
    if not os.path.exists(os.path.join(out, "view.json")):
        fail("Blender wrote no result (exit %d)\n%s" % (p.returncode, log[-3000:]))
    with open(os.path.join(out, "after_solid.json")) as f:
        solid = json.load(f)
    if solid["alive"]:
        fail("serve (pid %s) still ran %.1f s after the view left Rendered shading" % (solid["pid"], solid["seconds"]))
    print("viewport_check: the view left Rendered shading: serve (pid %s) had ended %.1f s later, Blender still "
          "running" % (solid["pid"], solid["seconds"]))
    left = set(serve_pids()) - before
    if left:
        fail("serve processes outlived Blender: %s" % sorted(left))
    with open(os.path.join(out, "view.json")) as f:
        info = json.load(f)
    d = info["drawn"]
    w, h = d["width"], d["height"]
    P = info["projection"]
    if abs(P[0][2]) > 1e-6 or abs(P[1][2]) > 1e-6:
        fail("the user view has a lens shift (%g, %g): the CLI camera has none" % (P[0][2], P[1][2]))
    rx, ry, rw, rh = info["region"]

    def region_of(name):
        shot = Image.open(os.path.join(out, name)).convert("RGB")
        top = shot.height - (ry + rh)
        crop = shot.crop((rx, top, rx + rw, top + rh)).resize((w, h), Image.BOX)
        crop.save(os.path.join(out, name.replace(".png", "_region.png")))
        return np.asarray(crop).astype(np.float64)

    a = region_of("viewport.png")
    print("viewport_check: Blender drew pass %d of a %dx%d frame over a %dx%d region (Pixel Size %s), %.0f s "
          "after start" % (d["passes"], w, h, rw, rh, info["pixel_size"], info["seconds"]))
    if d["passes"] != PASSES:
        fail("the screenshot is of pass %d, not %d" % (d["passes"], PASSES))
    if a.std() < 8 or a.mean() < 10:
        fail("the viewport is blank (mean %.1f, standard deviation %.1f)" % (a.mean(), a.std()))
    args = info["cli_args"]

    def render(seed, tag):
        a2 = list(args)
        a2[a2.index("--seed") + 1] = str(seed)
        pattern = os.path.join(out, tag + "_#.exr")
        r = subprocess.run([EXE, "render", os.path.join(out, "view.gltf"), "--width", str(w), "--height", str(h),
                            "--frames", "0:%d" % (PASSES - 1), "-o", pattern, "-q"] + a2,
                           capture_output=True, text=True, timeout=600)
        if r.returncode != 0:
            fail("render: %s" % r.stderr)
        pngp = os.path.join(out, tag + ".png")
        r = subprocess.run([EXE, "display", pattern.replace("#", str(PASSES - 1)), "-o", pngp, "--view",
                            "Standard"], capture_output=True, text=True, timeout=300)
        if r.returncode != 0:
            fail("display: %s" % r.stderr)
        return png(pngp)

    def as_drawn(img):
        # Blender draws the frame stretched over the region with linear
        # filtering; the screenshot was box-filtered back: the same here.
        im = Image.fromarray(img.astype(np.uint8))
        return np.asarray(im.resize((rw, rh), Image.BILINEAR).resize((w, h), Image.BOX)).astype(np.float64)

    seed = int(args[args.index("--seed") + 1])
    b = as_drawn(render(seed, "cli"))
    c = as_drawn(render(seed + 1, "cli_seed"))
    diff, noise = np.abs(a - b).mean(), np.abs(b - c).mean()
    print("viewport_check: viewport against the CLI render of that view (same seed): mean difference %.2f "
          "8-bit steps (99th percentile %.0f); two seeds of the CLI render: %.2f; mean levels %.1f and %.1f"
          % (diff, np.percentile(np.abs(a - b), 99), noise, a.mean(), b.mean()))
    if diff > 2.0 or diff > 0.6 * noise:
        fail("the viewport differs from the CLI render of its view by %.2f steps on average (seeds differ by %.2f)"
             % (diff, noise))
    # Orbiting refines the new view without a reload; moving the cube
    # reloads the scene in the same serve process.
    shots = info["shots"]
    o, m = shots["orbit.png"]["drawn"], shots["edit.png"]["drawn"]
    first = shots["viewport.png"]["drawn"]
    ao, am = region_of("orbit.png"), region_of("edit.png")
    o0 = info["orbit_from"]
    print("viewport_check: orbit: pass %d, reloads %d -> %d, picture changed by %.1f steps; cube moved: pass %d, "
          "reloads %d -> %d, picture changed by %.1f steps; one serve process (pid %s)"
          % (o["passes"], o0["reloads"], o["reloads"], np.abs(ao - a).mean(), m["passes"], o["reloads"],
             m["reloads"], np.abs(am - ao).mean(), first["pid"]))
    if o["reloads"] != o0["reloads"]:
        fail("orbiting reloaded the scene (%d reloads)" % (o["reloads"] - o0["reloads"]))
    if o["pid"] != first["pid"] or m["pid"] != first["pid"]:
        fail("serve was restarted (pids %s, %s, %s)" % (first["pid"], o["pid"], m["pid"]))
    if o["passes"] != PASSES or m["passes"] != PASSES:
        fail("the orbit and edit screenshots are of passes %d and %d" % (o["passes"], m["passes"]))
    if m["reloads"] != o["reloads"] + 1:
        fail("moving the cube sent %d reloads" % (m["reloads"] - o["reloads"]))
    if np.abs(ao - a).mean() < 3 or np.abs(am - ao).mean() < 1:
        fail("the orbit or the edit did not change the picture")
    mt = shots["material.png"]["drawn"]
    ar = region_of("material.png")
    red = lambda img: (img[..., 0] - img[..., 1]).mean()  # noqa: E731
    print("viewport_check: the cube's material made red: pass %d, reloads %d -> %d, red minus green %.2f -> %.2f "
          "steps" % (mt["passes"], m["reloads"], mt["reloads"], red(am), red(ar)))
    if mt["pid"] != first["pid"] or mt["reloads"] != m["reloads"] + 1 or not red(ar) > red(am) + 1:
        fail("the material edit: pid %s, %d reloads, red minus green %.2f -> %.2f"
             % (mt["pid"], mt["reloads"] - m["reloads"], red(am), red(ar)))
    # A serve that dies at once (a stand-in binary: one error line, exit 3):
    # the viewport's status and Blender's report carry that line, and Blender
    # goes on and quits normally.
    broken = os.path.join(WORK, "broken_photonbridge")
    with open(broken, "w") as f:
        f.write("#!/bin/sh\necho 'photonbridge serve: error: test: the GPU caught fire' >&2\nexit 3\n")
    os.chmod(broken, 0o755)
    out2 = os.path.join(WORK, "broken")
    os.makedirs(out2)
    e2 = dict(e, PHOTONBRIDGE_BIN=broken)
    argv2 = argv[:-2] + [out2, "0"]
    p = subprocess.run(argv2, capture_output=True, text=True, env=e2, timeout=300)
    with open(os.path.join(out2, "broken.json")) as f:
        b2 = json.load(f)
    print("viewport_check: a serve that dies at once: the viewport says %r (Blender exit %d)"
          % (b2["error"], p.returncode))
    if p.returncode != 0 or not b2["error"] or "the GPU caught fire" not in b2["error"] or "exit 3" not in b2["error"]:
        fail("the dead serve's error did not reach the viewport: %r, Blender exit %d\n%s"
             % (b2, p.returncode, (p.stdout + p.stderr)[-2000:]))
    print("viewport_check: OK")


main()
