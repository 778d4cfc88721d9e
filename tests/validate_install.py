#!/usr/bin/env python3
"""`photonbridge validate` from an installed binary: `cmake --install BUILD
--prefix P` into a fresh folder under the system's temporary folder (outside
the source tree), then P/bin/photonbridge run from another folder there:
  - the install holds the binary and, in P/share/photonbridge, validate.py
    with every validation module it imports and every script it,
    run_cycles.sh or run_cycles.py runs (found by reading them, so that a new
    one cannot be left out), the samples, the Blender hand-off and sample scripts and the
    OCIO config;
  - the installed binary's `validate --help` works and names the installed
    layout;
  - a real run (cornell_box at 32 px: the reference, and photonbridge render
    where a Vulkan device is there; POV-Ray and Cycles off) writes its report,
    and report.json names the installed validate.py as the script that ran
    (not the source tree's, which the binary also knows) and the installed
    sample as the scene.

usage: validate_install.py CMAKE BUILD_DIR PHOTONBRIDGE"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "pylib"))
from pbcheck import Checker, run_cmd  # noqa: E402

CMAKE, BUILD, EXE = sys.argv[1:4]
SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
T = Checker(EXE)
tmp = tempfile.mkdtemp(prefix="pb_install_")
try:
    prefix = os.path.join(tmp, "prefix")
    p = run_cmd([CMAKE, "--install", BUILD, "--prefix", prefix])
    T.check(p.returncode == 0, "cmake --install: exit 0 (%d)" % p.returncode)
    share = os.path.join(prefix, "share", "photonbridge")
    val = os.path.join(share, "validation")

    # What the scripts import and run, read from the source tree's copies.
    need = ["validate.py"]
    for script in ("validate.py", "run_cycles.py"):
        text = open(os.path.join(SRC, "validation", script)).read()
        need += [m + ".py" for m in re.findall(r"^import (\w+)", text, re.M)
                 if os.path.isfile(os.path.join(SRC, "validation", m + ".py"))]
        need += re.findall(r"os\.path\.join\(HERE, \"([\w.]+)\"\)", text)
    for script in [f for f in need if f.endswith(".sh")]:
        need += re.findall(r"\$here/([\w.]+)", open(os.path.join(SRC, "validation", script)).read())
    need = sorted(set(need))
    missing = [f for f in need if not os.path.isfile(os.path.join(val, f))]
    T.check(len(need) >= 5 and not missing, "validation/ holds %s (missing: %s)" % (", ".join(need), missing or "none"))
    T.check(all(os.access(os.path.join(val, f), os.X_OK) for f in need if f.endswith(".sh")),
            "the shell scripts are executable")
    others = ["samples/cornell_box/cornell_box.gltf", "samples/cornell_box/cornell_box.bin",
              "samples/spot_room/floor_checker.png", "exporters/blender/export_photonbridge.py",
              "exporters/blender/make_samples.py", "exporters/blender/photonbridge/writer.py",
              "config/ocio/photonbridge.ocio"]
    missing = [f for f in others if not os.path.isfile(os.path.join(share, f))]
    T.check(not missing, "share/photonbridge holds the samples, the Blender scripts and the OCIO config "
            "(missing: %s)" % (missing or "none"))
    exe = os.path.join(prefix, "bin", "photonbridge")
    T.check(os.access(exe, os.X_OK), "bin/photonbridge installed")

    # Run from a folder outside the source tree, with no PB_VALIDATION_DIR.
    cwd = os.path.join(tmp, "run")
    os.makedirs(cwd)
    env = {k: v for k, v in os.environ.items() if k != "PB_VALIDATION_DIR"}
    p = run_cmd([exe, "validate", "--help"], cwd=cwd, env=env)
    T.check(p.returncode == 0 and "share/photonbridge/validation" in p.stdout.replace("\n", " ").replace("  ", " "),
            "installed validate --help: exit 0, names the installed layout (%d)" % p.returncode)

    device = T.has_device()
    args = [exe, "validate", "cornell_box", "-o", "out", "--width", "32", "--spp", "1", "--ref-spp", "2",
            "--threads", "1", "--no-povray", "--no-cycles"] + ([] if device else ["--no-gpu"])
    p = run_cmd(args, expect_rc=0 if device else 1, cwd=cwd, env=env)
    # Without a device only the reference renders: exit 1 (fewer than two
    # pictures), the report still written.
    T.check(p.returncode == (0 if device else 1), "installed validate: exit %d (%d)" % (0 if device else 1,
                                                                                       p.returncode))
    try:
        r = json.load(open(os.path.join(cwd, "out", "report.json")))
        st = {x["name"]: x["status"] for x in r["renders"]}
        T.check(st.get("reference") == "ok" and (not device or st.get("photonbridge") == "ok"),
                "the report's renders (%s)" % st)
        want = os.path.realpath(os.path.join(val, "validate.py"))
        T.check(os.path.realpath(r.get("validation_script") or "") == want,
                "the installed validate.py ran (%s)" % r.get("validation_script"))
        T.check(os.path.realpath(r["scene"]).startswith(os.path.realpath(share) + os.sep),
                "the installed sample was rendered (%s)" % r["scene"])
    except (OSError, ValueError, KeyError, TypeError) as e:
        T.check(False, "report.json readable (%s)" % e)
finally:
    shutil.rmtree(tmp, ignore_errors=True)
sys.exit(T.finish())
