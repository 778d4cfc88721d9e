#!/usr/bin/env python3
"""render --noise-threshold: the render refines photon maps until its own
noise estimate (render/frame/noise.h: the RMS noise of the display image, from two
groups of independent maps) reaches the threshold, and the estimate is
honest: against a converged reference (Embree, its own noise from its two
halves taken out) the true display error lies within a factor 1.5 of the
estimate on cornell_box (a bright room) and spot_room (a spot, a dim
floor), at two thresholds. A sample pattern whose first samples all sit in
one corner of the pixel (an m x m grid over an open-ended count) shifts the
whole image by half a pixel, an error two groups of maps share: the estimate
then reads 3 to 10 times too low and this test fails. Also: --json reports
the stop reason and the estimate; --iterations bounds the maps; a bare
render refines to the default threshold, --iterations, --spp and
--time-limit set the work instead; the option's range and its conflicts
are usage errors."""
import json, math, os, subprocess, sys, tempfile

exe, root = sys.argv[1], sys.argv[2]
problems, checks = [], 0
W = "64"


def check(ok, what):
    global checks
    checks += 1
    if not ok:
        problems.append(what)
    print(("ok   " if ok else "FAIL ") + what, flush=True)


def run(args):
    return subprocess.run([exe] + args, capture_output=True, text=True, timeout=900)


def psnr(test, ref):
    p = run(["compare", test, ref, "--ocio-config", "built-in", "--view", "Standard", "--json", "-"])
    return json.loads(p.stdout)["psnr_db"]


with tempfile.TemporaryDirectory() as d:
    for name, spp in (("cornell_box", 1024), ("spot_room", 1024)):
        scene = os.path.join(root, "samples", name, name + ".gltf")
        ref = os.path.join(d, name + "_ref.exr")
        p = run(["reference", scene, "--width", W, "--height", W, "--spp", str(spp), "--estimate-noise", "-o", ref,
                 "--json", ref + ".json", "-q"])
        check(p.returncode == 0, "%s: reference (%d) %s" % (name, p.returncode, p.stderr[-300:]))
        e_ref = 10 ** (-json.load(open(ref + ".json"))["noise"]["psnr_db"] / 20)
        for t in (0.04, 0.025):
            out = os.path.join(d, "%s_%g.exr" % (name, t))
            p = run(["render", scene, "--width", W, "--height", W, "--noise-threshold", str(t), "--seed", "3", "-o",
                     out, "--json", out + ".json", "-q"])
            if p.returncode != 0:
                check(False, "%s T %g: render exit %d %s" % (name, t, p.returncode, p.stderr[-300:]))
                continue
            j = json.load(open(out + ".json"))
            est, maps = j["noise"]["estimate"], j["photons"]["iterations"]
            check(j["stop"] == "noise_threshold" and est is not None and est <= t and maps >= 2 and
                  j["noise"]["checks"] >= 2 and j["noise"]["threshold"] == t,
                  "%s T %g: stopped by the threshold (%s, estimate %s, %d maps, %d checks)" %
                  (name, t, j["stop"], est, maps, j["noise"]["checks"]))
            e = 10 ** (-psnr(out, ref) / 20)
            e_true = math.sqrt(max(e * e - e_ref * e_ref, 1e-12))
            ratio = est / e_true if est else 0
            check(1 / 1.5 <= ratio <= 1.5, "%s T %g: estimate %.4f (%.1f dB) against the true error %.4f (%.1f dB; "
                  "measured %.1f dB, reference noise %.1f dB): ratio %.2f within [0.67, 1.5]" %
                  (name, t, est, -20 * math.log10(est), e_true, -20 * math.log10(e_true), -20 * math.log10(e),
                   -20 * math.log10(e_ref), ratio))
    scene = os.path.join(root, "samples", "cornell_box", "cornell_box.gltf")
    small = ["--width", "16", "--photons", "16384", "-o", os.path.join(d, "s.exr"), "--json", "-", "-q"]
    p = run(["render", scene, "--noise-threshold", "0.0001", "--iterations", "3"] + small)
    j = json.loads(p.stdout) if p.returncode == 0 else {}
    check(j.get("stop") == "planned" and j.get("photons", {}).get("iterations") == 3 and
          (j.get("noise", {}).get("estimate") or 0) > 0.0001,
          "--iterations 3 bounds the maps; the estimate is still reported (%d, %s)" %
          (p.returncode, {k: j.get(k) for k in ("stop", "noise")}))
    p = run(["render", scene] + small)
    j = json.loads(p.stdout) if p.returncode == 0 else {}
    n = j.get("noise", {})
    check(n.get("threshold") == 0.03 and j.get("stop") == "noise_threshold" and (n.get("estimate") or 1) <= 0.03 and
          j.get("photons", {}).get("iterations", 0) >= 2,
          "a bare render refines to the default threshold 0.03 (%d, %s, %s maps)" %
          (p.returncode, {k: j.get(k) for k in ("stop", "noise")}, j.get("photons", {}).get("iterations")))
    for work in (["--iterations", "2"], ["--spp", "2"], ["--time-limit", "600", "--iterations", "2"]):
        p = run(["render", scene] + work + small)
        j = json.loads(p.stdout) if p.returncode == 0 else {}
        check(j.get("noise", {}).get("threshold", 1) is None and j.get("stop") == "planned",
              "%s sets the work: no threshold, stop 'planned' (%d, %s)" % (" ".join(work), p.returncode,
                                                                         j.get("stop")))
    for args, msg in ((["--noise-threshold", "0.7"], "render: error: --noise-threshold: 0.7 is outside [0, 0.5]"),
                      (["--noise-threshold", "0.02", "--frames", "1:2"],
                       "render: error: --noise-threshold refines photon maps of one frame: not with "
                       "--direct-only or --frames"),
                      (["--noise-threshold", "0.02", "--direct-only"], "not with --direct-only")):
        p = run(["render", scene, "-o", os.path.join(d, "u_#.exr"), "--width", "8"] + args)
        check(p.returncode == 2 and msg in p.stderr and p.stderr.count("\n") == 1,
              "%s: exit 2, one line (%d %r)" % (" ".join(args), p.returncode, p.stderr))

print("%d passed, %d failed" % (checks - len(problems), len(problems)))
sys.exit(1 if problems else 0)
