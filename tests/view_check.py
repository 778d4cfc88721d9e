#!/usr/bin/env python3
"""photonbridge view under Xvfb (item 4's viewer tests), one part a run:

  still      after N still frames the window's screenshot is `photonbridge
             display` of `render --frames 0:N-1` (the same camera, settings
             and seed; the last frame of that still run), also after + + (one
             stop of exposure, display --exposure 1), every channel within
             one 8-bit step (the photon store's slot order follows the
             device's scheduling, so the sums may differ in the last float
             bits); validation layers on (zero messages, or the exit code is
             14)
  input      synthetic input through --script (the handlers the GLFW callbacks
             call): a left drag orbits, the wheel dollies, W flies, F7 shows
             the normal AOV; each changes the picture, a move restarts the
             still run, and the view refines again afterwards
  resize     the window resized twice mid-run: the swapchain is recreated and
             the run goes on (exit 0), presenting through the render device
             (one VkDevice: lavapipe's one queue family computes, blits and
             presents; --json present_shared_device)
  nodisplay  no DISPLAY / WAYLAND_DISPLAY: one line saying so and naming
             `photonbridge render`, exit 15 (PB_ERR_NOT_AVAILABLE)
  errors     a bad --script line: exit 2 naming the file and the line
  in_flight  the still part with --frames-in-flight 2 (frames in flight: the
             window one frame behind the renderer): the same screenshots;
             the ring slot keeps the shown AOV's planes alone (ring_bytes:
             the beauty's 16 bytes a pixel, the normal's 12 after F7)
  noise      --noise-threshold T: the still run refines until its own
             noise estimate is at most T, then rests (frames counted, nothing
             rendered; the screenshot while it rests is display of `render
             --frames` of the frames it refined, within one 8-bit step); a
             dolly restarts it and it rests again; --json reports the
             estimate of each frame, and its fall reached T
  tracer     view --tracer images (seed 003's environment maps): the
             screenshot after 2 still frames is display of `render --frames
             0:1 --tracer images` with the same maps (within one 8-bit step)
             and differs from the bvh tracer's render by more (the option
             reaches the view's frames)

Exit 77 (skip) where xvfb-run is missing or the binary was built without
GLFW; CI's install script installs both, so there they run.
usage: view_check.py PHOTONBRIDGE ROOT OUTDIR PART
"""
import json
import os
import shutil
import subprocess
import sys

from pbcheck import debian_python

try:
    import numpy as np
    from PIL import Image
except ImportError:  # pyenv's python without Debian's packages
    debian_python("view_check")

EXE, ROOT, OUT, PART = sys.argv[1:5]
SCENE = os.path.join(ROOT, "samples/cornell_box/cornell_box.gltf")
# Small and quick: 64 px, 2^15 photon paths a frame (the still part's two
# renders take a few seconds each on lavapipe).
SETTINGS = ["--width", "64", "--photons", "32768", "--seed", "7"]
os.makedirs(OUT, exist_ok=True)


def fail(msg):
    print("view_check %s: FAIL: %s" % (PART, msg))
    sys.exit(1)


def run(args, env=None, xvfb=True, expect=0):
    cmd = ([shutil.which("xvfb-run"), "-a", "-s", "-screen 0 1024x768x24"] if xvfb else []) + [EXE] + args
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    # xvfb-run exits 5 of its own when it cannot remove its temporary folder
    # after the program ended (seen once under a loaded 2-core CI run); the
    # program's own exit status is then lost, so it runs once more.
    if xvfb and p.returncode == 5 and "problem while cleaning up temporary directory" in p.stderr:
        p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    if expect is not None and p.returncode != expect:
        fail("%s: exit %d, expected %d\nstdout: %s\nstderr: %s" % (" ".join(args), p.returncode, expect, p.stdout,
                                                                  p.stderr))
    return p


def png(path):
    return np.asarray(Image.open(path).convert("RGB")).astype(np.int32)


def env_without_display():
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    env.pop("WAYLAND_DISPLAY", None)
    return env


def check_available():
    p = run(["view", SCENE], env=env_without_display(), xvfb=False, expect=None)
    if "built without GLFW" in p.stderr:
        print("view_check: SKIP: photonbridge was built without GLFW (libglfw3-dev)")
        sys.exit(77)
    if PART != "nodisplay" and not shutil.which("xvfb-run"):
        print("view_check: SKIP: xvfb-run is not installed (apt-get install xvfb xauth)")
        sys.exit(77)


def validation_env():
    env = dict(os.environ)
    layer = any(os.path.exists(os.path.join(d, "VkLayer_khronos_validation.json"))
                for d in ("/usr/share/vulkan/explicit_layer.d", "/etc/vulkan/explicit_layer.d"))
    if layer:
        env["PB_VK_VALIDATION"] = "1"
    return env


def part_still(extra=(), tag="still"):
    # Frames 0-3 still; the screenshot event at frame 3 (before it renders)
    # shows frame 2; two presses of + at frame 3 raise the exposure by one
    # stop, so the final screenshot is frame 3 at +1 EV: both are compared
    # with display's PNGs of those frames' EXRs (--exposure 1 for the second).
    n = 4
    early, shot = os.path.join(OUT, "view_2.png"), os.path.join(OUT, "view_3_ev1.png")
    script = os.path.join(OUT, "still.txt")
    stats = os.path.join(OUT, "view.json")
    with open(script, "w") as f:
        f.write("3 screenshot %s\n3 key plus\n3 key plus\n" % early)
    run(["view", SCENE] + SETTINGS + list(extra) + ["--exit-after", str(n), "--script", script, "--screenshot", shot,
                                                    "--json", stats, "-q"], env=validation_env())
    shown = len(json.load(open(stats))["frames"])
    if shown != n:
        fail("%d frames shown, expected %d" % (shown, n))
    run(["render", SCENE] + SETTINGS + ["--frames", "0:%d" % (n - 1), "-o", os.path.join(OUT, "f_#.exr"), "-q"],
        env=validation_env(), xvfb=False)
    for frame, view_png, ev in ((n - 2, early, 0), (n - 1, shot, 1)):
        ref = os.path.join(OUT, "display_%d.png" % frame)
        run(["display", os.path.join(OUT, "f_%d.exr" % frame), "-o", ref, "--exposure", str(ev)], xvfb=False)
        a, b = png(view_png), png(ref)
        if a.shape != b.shape:
            fail("screenshot %s, display %s" % (a.shape, b.shape))
        d = np.abs(a - b)
        print("view_check %s: frame %d (%d still frames), 64 px, exposure %+d: max difference %d, mean %.4f "
              "(8-bit steps), mean level %.1f" % (tag, frame, frame + 1, ev, d.max(), d.mean(), a.mean()))
        if d.max() > 1:
            fail("the screenshot of frame %d differs from display's PNG by up to %d steps (at most 1)"
                 % (frame, d.max()))
        if a.mean() < 20:
            fail("the picture is black (mean level %.1f)" % a.mean())


def part_in_flight():
    # The still part with --frames-in-flight 2: the window shows frame k - 1
    # while frame k renders (its last GPU pass running as the host makes the
    # picture and presents), --exit-after and --script count shown frames, so
    # the same screenshots are the same frames of `render --frames`.
    part_still(["--frames-in-flight", "2"], "in_flight")
    # The ring slot keeps only the shown AOV's planes (viewer.c set_keep):
    # the beauty's 16 bytes a pixel, after F7 the normal's 12 (every plane
    # was 104); the switch shows on the next frame.
    script = os.path.join(OUT, "aov.txt")
    beauty, normal = os.path.join(OUT, "fif_beauty.png"), os.path.join(OUT, "fif_normal.png")
    with open(script, "w") as f:
        f.write("1 screenshot %s\n2 key F7\n" % beauty)
    stats = os.path.join(OUT, "aov.json")
    run(["view", SCENE] + SETTINGS + ["--frames-in-flight", "2", "--exit-after", "6", "--script", script,
                                      "--screenshot", normal, "--json", stats, "-q"], env=validation_env())
    frames = json.load(open(stats))["frames"]
    a, b = png(beauty), png(normal)
    px = a.shape[0] * a.shape[1]
    ring = [f.get("ring_bytes") for f in frames]
    print("view_check in_flight: ring bytes per frame %s (%d px)" % (ring, px))
    if ring[0] != 16 * px or ring[1] != 16 * px:
        fail("the beauty frames' ring slots hold %s bytes, expected the beauty plane's %d" % (ring[:2], 16 * px))
    if ring[-1] != 12 * px:
        fail("after F7 the ring slot holds %s bytes, expected the normal plane's %d" % (ring[-1], 12 * px))
    d = np.abs(a - b).mean()
    print("view_check in_flight: beauty -> normal AOV: mean change %.2f steps" % d)
    if d < 3:
        fail("F7 did not show the normal AOV with frames in flight (mean change %.2f steps)" % d)


def part_input():
    script = os.path.join(OUT, "input.txt")
    shots = {k: os.path.join(OUT, k + ".png") for k in ("before", "orbit", "dolly", "fly", "normal")}
    with open(script, "w") as f:
        f.write("# frame action args\n"
                "2 screenshot %(before)s\n"
                "2 cursor 20 30\n2 press left\n2 cursor 23 30\n2 cursor 26 31\n2 release left\n"
                "4 screenshot %(orbit)s\n"
                "4 scroll 3\n"
                "5 screenshot %(dolly)s\n"
                "5 keydown w\n7 keyup w\n"
                "8 screenshot %(fly)s\n"
                "8 key F7\n"
                "9 screenshot %(normal)s\n" % shots)
    stats = os.path.join(OUT, "input.json")
    run(["view", SCENE] + SETTINGS + ["--exit-after", "9", "--script", script, "--json", stats, "-q"],
        env=validation_env())
    frames = json.load(open(stats))["frames"]
    still = [f["still"] for f in frames]
    print("view_check input: still per frame", still, "run lengths", [f["run_frames"] for f in frames])
    # Frames 0, 1 still run; 2 moved (orbit), 3 still; 4 moved (dolly); 5, 6
    # move (flying), 7 still again, 8 still (an AOV is only a display change).
    if still[2] or not still[3] or still[4] or still[5] or not still[7] or not still[8]:
        fail("frames moved/still as %s; expected the orbit at 2, the dolly at 4, the flight at 5-6" % still)
    if frames[8]["run_frames"] < 2:
        fail("the view did not refine after the flight")
    pics = {k: png(v) for k, v in shots.items()}
    for a, b in (("before", "orbit"), ("orbit", "dolly"), ("dolly", "fly"), ("fly", "normal")):
        d = np.abs(pics[a] - pics[b]).mean()
        print("view_check input: %s -> %s: mean change %.2f steps" % (a, b, d))
        if d < 3:
            fail("%s did not change the picture (mean %.2f steps)" % (b, d))


def part_resize():
    script = os.path.join(OUT, "resize.txt")
    with open(script, "w") as f:
        f.write("1 resize 200 120\n3 resize 48 300\n4 resize 640 480\n")
    stats = os.path.join(OUT, "resize.json")
    shot = os.path.join(OUT, "resize.png")
    run(["view", SCENE] + SETTINGS + ["--exit-after", "6", "--script", script, "--json", stats, "--screenshot", shot,
                                      "-q"], env=validation_env())
    j = json.load(open(stats))
    print("view_check resize: %d frames, %d swapchain recreations" % (len(j["frames"]), j["swapchain_recreations"]))
    if len(j["frames"]) != 6 or j["swapchain_recreations"] < 2:
        fail("expected 6 frames and at least 2 swapchain recreations: %s" % j)
    if j.get("present_shared_device") is not True:
        fail("the window does not present through the render device: %s" % j.get("present_shared_device"))
    # The fallback (PB_PRESENT_OWN_DEVICE=1: as where the render device's
    # queue family cannot present): a second VkDevice, its reason logged.
    env = validation_env()
    env["PB_PRESENT_OWN_DEVICE"] = "1"
    p = run(["view", SCENE] + SETTINGS + ["--exit-after", "2", "--json", stats], env=env)
    j = json.load(open(stats))
    if j.get("present_shared_device") is not False or "second Vulkan device" not in (p.stderr or ""):
        fail("the fallback presenter: shared %s, stderr %r" % (j.get("present_shared_device"), (p.stderr or "")[-300:]))
    if png(shot).shape != (64, 64, 3):
        fail("the screenshot is not the 64 px frame")


def part_nodisplay():
    p = run(["view", SCENE] + SETTINGS, env=env_without_display(), xvfb=False, expect=15)
    lines = p.stderr.strip().splitlines()
    print("view_check nodisplay:", lines)
    if len(lines) != 1 or "no display" not in lines[0] or "photonbridge render" not in lines[0]:
        fail("expected one line naming the missing display and 'photonbridge render': %r" % p.stderr)


def part_errors():
    script = os.path.join(OUT, "bad.txt")
    with open(script, "w") as f:
        f.write("1 cursor 3 4\n2 jump 5\n")
    p = run(["view", SCENE] + SETTINGS + ["--script", script], expect=2)
    if "bad.txt: line 2" not in p.stderr:
        fail("the error does not name the file and line: %r" % p.stderr)
    print("view_check errors:", p.stderr.strip())


def part_noise():
    T, n, moved = 0.05, 40, 20
    script = os.path.join(OUT, "noise.txt")
    rest_shot = os.path.join(OUT, "rested.png")
    with open(script, "w") as f:
        f.write("%d screenshot %s\n%d scroll 2\n" % (moved - 1, rest_shot, moved))
    stats = os.path.join(OUT, "noise.json")
    run(["view", SCENE] + SETTINGS + ["--noise-threshold", str(T), "--exit-after", str(n), "--script", script,
                                      "--json", stats, "-q"], env=validation_env())
    j = json.load(open(stats))
    frames = j["frames"]
    rested = [f["rested"] for f in frames]
    print("view_check noise: rested per frame", "".join("r" if r else "." for r in rested),
          "estimates", ["%.3f" % f.get("noise", -1) for f in frames if not f["rested"]])
    if len(frames) != n or j.get("noise_threshold") != T:
        fail("expected %d frames and noise_threshold %g: %d, %s" % (n, T, len(frames), j.get("noise_threshold")))
    first = rested.index(True) if True in rested else n
    if first >= moved - 1:
        fail("the view did not rest before frame %d (threshold %g)" % (moved - 1, T))
    if not all(rested[first:moved]) or rested[moved]:
        fail("expected a rest from frame %d to the dolly at %d, then a new frame: %s" % (first, moved, rested))
    last = frames[first - 1]
    if not (0 <= last.get("noise", -1) <= T) or any(0 <= f.get("noise", -1) <= T for f in frames[:first - 1]):
        fail("the view rested with estimate %s (threshold %g)" % (last.get("noise"), T))
    if frames[moved]["still"] or frames[moved]["run_frames"] != 1:
        fail("the dolly did not restart the still run: %s" % frames[moved])
    if True not in rested[moved + 1:]:
        fail("the view did not rest again after the dolly")
    # The picture it rests on: the last frame it refined.
    run(["render", SCENE] + SETTINGS + ["--frames", "0:%d" % (first - 1), "-o", os.path.join(OUT, "n_#.exr"), "-q"],
        xvfb=False)
    ref = os.path.join(OUT, "display_rest.png")
    run(["display", os.path.join(OUT, "n_%d.exr" % (first - 1)), "-o", ref], xvfb=False)
    d = np.abs(png(rest_shot) - png(ref))
    print("view_check noise: rested on frame %d (estimate %.4f <= %g): max difference %d against display of "
          "render --frames 0:%d" % (first - 1, last["noise"], T, d.max(), first - 1))
    if d.max() > 1:
        fail("the rested picture differs from the last refined frame by up to %d steps" % d.max())


def part_tracer():
    n = 2
    images = ["--tracer", "images", "--image-maps", "4", "--image-map-resolution", "32"]
    shot = os.path.join(OUT, "view_images.png")
    run(["view", SCENE] + SETTINGS + images + ["--exit-after", str(n), "--screenshot", shot, "-q"],
        env=validation_env())
    diffs = {}
    for name, extra in (("images", images), ("bvh", [])):
        pat = os.path.join(OUT, name + "_#.exr")
        run(["render", SCENE] + SETTINGS + extra + ["--frames", "0:%d" % (n - 1), "-o", pat, "-q"],
            env=validation_env(), xvfb=False)
        ref = os.path.join(OUT, "display_%s.png" % name)
        run(["display", pat.replace("#", str(n - 1)), "-o", ref], xvfb=False)
        a, b = png(shot), png(ref)
        if a.shape != b.shape:
            fail("screenshot %s, display %s" % (a.shape, b.shape))
        diffs[name] = int(np.abs(a - b).max())
        print("view_check tracer: the view's --tracer images frame %d against render --tracer %s: max difference "
              "%d (8-bit steps), mean level %.1f" % (n - 1, name, diffs[name], a.mean()))
    if diffs["images"] > 1:
        fail("view --tracer images differs from render --tracer images by %d steps (at most 1)" % diffs["images"])
    if diffs["bvh"] <= 1:
        fail("view --tracer images equals the bvh tracer's render: the option did not reach the frames")


check_available()
{"still": part_still, "input": part_input, "resize": part_resize, "nodisplay": part_nodisplay,
 "errors": part_errors, "in_flight": part_in_flight, "tracer": part_tracer,
 "noise": part_noise}[PART]()
print("view_check %s: ok" % PART)
