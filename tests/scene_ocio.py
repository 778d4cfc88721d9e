#!/usr/bin/env python3
"""The OCIO config a scene names (PHOTONBRIDGE_blender.colorManagement.
ocioConfig: Blender's own config.ocio, or $OCIO, as the add-on found it) is
the config of its display images, seen through `info`'s display line and
its warnings (no rendering):

  present   a config that exists here is used, with the scene's view;
  view      a view that config lacks: one warning naming the view and the
            view used instead (the config's default), exit 0;
  missing   a config not on this machine: one warning naming it, the
            built-in config used, which has Blender 4's AgX and Khronos
            PBR Neutral views;
  look      Blender's AgX and Filmic looks, which the built-in config has
            too, applied without a warning; a look the config lacks: one
            warning naming it, the scene's view kept without it;
  unknown   a view neither has: one warning naming it and the view used;
  cli       --ocio-config on the command line wins over the scene's (a
            tiny `reference --png`, the one render here).

usage: scene_ocio.py PHOTONBRIDGE ROOT WORKDIR"""
import filecmp
import json
import os
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "pylib"))
from pbcheck import Checker  # noqa: E402

EXE, ROOT, WORK = sys.argv[1:4]
SRC = os.path.join(ROOT, "tests", "corpus", "valid", "blender_color_management")
ON_DISK = os.path.join(ROOT, "config", "ocio", "photonbridge.ocio")  # views Standard, ACES 1.0 - SDR Video, Raw
os.environ.pop("OCIO", None)
os.environ["PB_BLENDER_OCIO"] = ""  # no installed Blender's config in the defaults
T = Checker(EXE, WORK)
check = T.check


def scene(sub, **cm):
    d = os.path.join(WORK, sub)
    shutil.rmtree(d, ignore_errors=True)
    shutil.copytree(SRC, d)
    path = os.path.join(d, "blender_color_management.gltf")
    doc = json.load(open(path))
    doc["extensions"]["PHOTONBRIDGE_blender"]["colorManagement"].update(cm, exposure=0.0)
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def info(path, *opts):
    p = T.run(["info", path] + list(opts), expect_rc=None)
    line = [ln for ln in p.stdout.splitlines() if ln.startswith("display")]
    warns = [ln for ln in p.stderr.splitlines() if "warning" in ln]
    return p.returncode, (line[0] if line else "(no display line)"), warns


rc, line, w = info(scene("present", view="Standard", ocioConfig=ON_DISK))
check(rc == 0 and "sRGB / Standard" in line and "OCIO config " + ON_DISK in line and not w,
      "present: the scene's config and view: %s %s" % (line, w))

rc, line, w = info(scene("view", view="AgX", ocioConfig=ON_DISK))
check(rc == 0 and "OCIO config " + ON_DISK in line and "/ Standard," in line, "view: the config's default: " + line)
check(len(w) == 1 and "'AgX'" in w[0] and "sRGB / Standard is used instead" in w[0],
      "view: one warning naming the view and the one used: %s" % w)

missing = os.path.join(WORK, "no", "such", "config.ocio")
for view in ("AgX", "Khronos PBR Neutral"):
    rc, line, w = info(scene("missing", view=view, ocioConfig=missing))
    check(rc == 0 and ("sRGB / %s, look None" % view) in line and "OCIO config built-in" in line,
          "missing: the built-in config's %s: %s" % (view, line))
    check(len(w) == 1 and missing in w[0] and "built-in config" in w[0],
          "missing: one warning naming the config: %s" % w)

# Blender's AgX and Filmic looks are the built-in config's too: applied,
# no warning but the config's.
for view, look in (("AgX", "AgX - Punchy"), ("AgX", "AgX - Greyscale"), ("Filmic", "Medium High Contrast")):
    rc, line, w = info(scene("look", view=view, look=look, ocioConfig=missing))
    check(rc == 0 and ("sRGB / %s, look %s," % (view, look)) in line and "built-in" in line,
          "look: the built-in config's %s with %s: %s" % (view, look, line))
    check(len(w) == 1 and missing in w[0], "look: only the config's warning: %s" % w)

rc, line, w = info(scene("look", view="AgX", look="No Such Look", ocioConfig=missing))
check(rc == 0 and "sRGB / AgX, look None" in line and "built-in" in line, "look: AgX without it: " + line)
check(len(w) == 2 and "'No Such Look'" in w[1] and "view 'AgX' is used without it" in w[1],
      "look: a warning naming the look and the view kept: %s" % w[1:])

rc, line, w = info(scene("unknown", view="No Such View", ocioConfig=missing))
check(rc == 0 and "sRGB / Filmic" in line, "unknown: the built-in default, Filmic: " + line)
check(len(w) == 2 and "'No Such View'" in w[1] and "sRGB / Filmic is used instead" in w[1],
      "unknown: a warning naming the view and the view used: %s" % w[1:])

# `info` has no colour options: a tiny reference render's PNG, against
# `display` of its EXR through the built-in AgX.
path = scene("cli", view="AgX", ocioConfig=ON_DISK)
d = os.path.dirname(path)
exr, png, want = (os.path.join(d, n) for n in ("c.exr", "c.png", "want.png"))
p = T.run(["reference", path, "-o", exr, "--png", png, "--spp", "1", "--width", "16", "--height", "12",
           "--ocio-config", "built-in"], expect_rc=0)
w = [ln for ln in p.stderr.splitlines() if "warning" in ln]
q = T.run(["display", exr, "-o", want, "--ocio-config", "built-in", "--view", "AgX"], expect_rc=0)
check(p.returncode == 0 and q.returncode == 0 and not w and filecmp.cmp(png, want, shallow=False),
      "cli: --ocio-config wins, with the scene's view (%s)" % w)

sys.exit(T.finish())
