#!/usr/bin/env python3
"""`photonbridge validate` split by renderer (what a farm runs as
one task per scene and renderer): `--renderers R --render-only` into one
folder per renderer, then `--report-from` those folders, against the same
renderers in one process. cornell_box at 24 px, the reference and the GPU
renderer (POV-Ray and Cycles off: their own tests cover them):
  - each --render-only run writes only its renderer's image and record
    (render_NAME.json) and no report;
  - the --report-from report lists both renders as ok and the one pair,
    whose PSNR equals the single process's to 0.05 dB (the reference is
    deterministic; the GPU's photon store order is not, which moves the
    last digits);
  - usage errors exit 2: an unknown renderer, both modes at once, a
    --report-from folder that does not exist.

usage: validate_split.py PHOTONBRIDGE WORKDIR"""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "pylib"))
from pbcheck import Checker  # noqa: E402

EXE, WORK = sys.argv[1:3]
T = Checker(EXE, WORK)
if not T.has_device():
    print("skip: no Vulkan device")
    sys.exit(77)
V = ["--width", "24", "--spp", "1", "--ref-spp", "4", "--threads", "1", "--no-povray", "--no-cycles"]
d = T.fresh("split")
one, r1, r2, rep = (os.path.join(d, x) for x in ("one", "r_reference", "r_photonbridge", "report"))

p = T.run(["validate", "cornell_box", "--out", one] + V)
T.check(p.returncode == 0, "one process: exit 0 (%d)" % p.returncode)
p = T.run(["validate", "cornell_box", "--out", r1, "--renderers", "reference", "--render-only"] + V)
T.check(p.returncode == 0 and os.path.isfile(os.path.join(r1, "reference.exr")) and
        os.path.isfile(os.path.join(r1, "render_reference.json")) and
        not os.path.exists(os.path.join(r1, "photonbridge.exr")) and
        not os.path.exists(os.path.join(r1, "report.json")),
        "--renderers reference --render-only: its image and record, no other render, no report")
p = T.run(["validate", "cornell_box", "--out", r2, "--renderers", "photonbridge", "--render-only"] + V)
T.check(p.returncode == 0 and os.path.isfile(os.path.join(r2, "photonbridge.exr")) and
        json.load(open(os.path.join(r2, "render_photonbridge.json")))["status"] == "ok",
        "--renderers photonbridge --render-only: its image and an ok record")
p = T.run(["validate", "cornell_box", "--out", rep, "--report-from", r1 + "," + r2] + V)
T.check(p.returncode == 0 and os.path.isfile(os.path.join(rep, "index.html")), "--report-from: exit 0 and a page")
try:
    a = json.load(open(os.path.join(one, "report.json")))
    b = json.load(open(os.path.join(rep, "report.json")))
    st = {r["name"]: r["status"] for r in b["renders"]}
    T.check(st.get("reference") == "ok" and st.get("photonbridge") == "ok", "--report-from: both renders ok (%s)" % st)
    pa = [(q["test"], q["reference"], q["psnr_db"]) for q in a["pairs"]]
    pb = [(q["test"], q["reference"], q["psnr_db"]) for q in b["pairs"]]
    T.check(len(pa) == 1 and len(pb) == 1 and pa[0][:2] == pb[0][:2] and abs(pa[0][2] - pb[0][2]) < 0.05,
            "the split's pair equals the single process's (%s, %s)" % (pa, pb))
except (OSError, ValueError, KeyError, TypeError) as e:
    T.check(False, "reports readable (%s)" % e)

for args, what in ((["--renderers", "foo"], "an unknown renderer"),
                   (["--render-only", "--report-from", r1], "--render-only with --report-from"),
                   (["--report-from", os.path.join(d, "nowhere")], "a --report-from folder that does not exist")):
    p = T.run(["validate", "cornell_box", "--out", os.path.join(d, "bad")] + V + args, expect_rc=2)
    T.check(p.returncode == 2 and p.stderr.strip().count("\n") == 0, "%s: exit 2, one line (%d: %s)" %
            (what, p.returncode, p.stderr.strip()[-200:]))
sys.exit(T.finish())
