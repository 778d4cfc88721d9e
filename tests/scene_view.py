#!/usr/bin/env python3
"""A scene's own colour management (PHOTONBRIDGE_blender.colorManagement,
written by the Blender render engine from the Colour Management panel) is
the default of its display images:

  scene     `render --png` and `reference --png` of a scene set to Standard,
            exposure 1.5 equal `display` of their EXR with --view Standard
            --exposure 1.5, byte for byte, and differ from the config's
            default view (Filmic);
  cli       a --view on the command line wins over the scene's view (the
            scene's exposure still applies, as Blender's does);
  unknown   a view the config lacks: exit 0, one warning naming the file and
            the view, the config's default view used (with the scene's
            exposure and gamma);
  info      `info` names the view the scene's pictures use.

usage: scene_view.py PHOTONBRIDGE ROOT WORKDIR
Exit 77 when no Vulkan device is present (the GPU part only)."""
import filecmp
import json
import os
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "pylib"))
from pbcheck import Checker  # noqa: E402

EXE, ROOT, WORK = sys.argv[1:4]
SRC = os.path.join(ROOT, "tests", "corpus", "valid", "blender_color_management")
SMALL = ["--width", "32", "--height", "24", "-q"]
T = Checker(EXE, WORK)
check = T.check


def run(args):
    return T.run(args, expect_rc=None)


def scene(sub, view=None):
    d = os.path.join(WORK, sub)
    shutil.rmtree(d, ignore_errors=True)
    shutil.copytree(SRC, d)
    path = os.path.join(d, "blender_color_management.gltf")
    if view:
        doc = json.load(open(path))
        doc["extensions"]["PHOTONBRIDGE_blender"]["colorManagement"]["view"] = view
        with open(path, "w") as f:
            json.dump(doc, f)
    return d, path


def display(exr, png, *opts):
    p = run(["display", exr, "-o", png] + list(opts))
    check(p.returncode == 0, "display %s %s (exit %d)" % (os.path.basename(exr), " ".join(opts), p.returncode))


d, path = scene("scene")
for renderer, opts in (("reference", ["--spp", "4"]), ("render", ["--photons", "4096", "--spp", "1"])):
    exr, png = os.path.join(d, renderer + ".exr"), os.path.join(d, renderer + ".png")
    p = run([renderer, path, "-o", exr, "--png", png] + SMALL + opts)
    if renderer == "render" and p.returncode == 77:
        print("skip render: no Vulkan device")
        continue
    check(p.returncode == 0, "%s --png of the Standard, exposure 1.5 scene (exit %d)" % (renderer, p.returncode))
    if p.returncode != 0:
        print(p.stderr[-2000:])
        continue
    display(exr, exr[:-4] + "_std.png", "--view", "Standard", "--exposure", "1.5")
    display(exr, exr[:-4] + "_default.png")
    check(filecmp.cmp(png, exr[:-4] + "_std.png", shallow=False),
          "%s: its PNG is the EXR through Standard at exposure 1.5" % renderer)
    check(not filecmp.cmp(png, exr[:-4] + "_default.png", shallow=False),
          "%s: and not the config's default view" % renderer)

exr = os.path.join(d, "reference.exr")
p = run(["reference", path, "-o", os.path.join(d, "cli.exr"), "--png", os.path.join(d, "cli.png"), "--spp", "4",
         "--view", "Filmic"] + SMALL)
check(p.returncode == 0, "reference --view Filmic (exit %d)" % p.returncode)
display(exr, os.path.join(d, "cli_want.png"), "--view", "Filmic", "--exposure", "1.5")
check(p.returncode == 0 and filecmp.cmp(os.path.join(d, "cli.png"), os.path.join(d, "cli_want.png"), shallow=False),
      "--view on the command line wins; the scene's exposure stays")

d, path = scene("unknown", view="No Such View")
p = run(["reference", path, "-o", os.path.join(d, "u.exr"), "--png", os.path.join(d, "u.png"), "--spp", "4"] +
        SMALL[:-1])  # not -q: the warning is the point
lines = [l for l in p.stderr.splitlines() if "warning" in l]
check(p.returncode == 0, "a scene view the config lacks still renders (exit %d)" % p.returncode)
check(len(lines) == 1 and path in lines[0] and "'No Such View'" in lines[0],
      "one warning naming the file and the view: %s" % (lines[0] if lines else "(none)"))
display(os.path.join(d, "u.exr"), os.path.join(d, "u_default.png"), "--exposure", "1.5")
check(p.returncode == 0 and filecmp.cmp(os.path.join(d, "u.png"), os.path.join(d, "u_default.png"), shallow=False),
      "the config's default view is used (with the scene's exposure)")

p = run(["info", os.path.join(SRC, "blender_color_management.gltf")])
line = [l for l in p.stdout.splitlines() if l.startswith("display")]
check(p.returncode == 0 and line and "/ Standard, look None, exposure 1.5" in line[0],
      "info: %s" % (line[0] if line else "(no display line)"))

sys.exit(T.finish())
