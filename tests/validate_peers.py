#!/usr/bin/env python3
"""validate --renderers reference,luxcore,mitsuba on cornell_box (48 px, 256
samples a pixel each, 2 threads): LuxCoreRender and Mitsuba 3 render
export-peer's dump of the scene; both records ok with the peer's version,
every pair compared (PSNR, relMSE, heat map), each peer's mean within 1.5 %
of the reference's in every channel and >= 24 dB against it (at 256 spp the
three renders' own noise is about 27 dB apart), the peers' by-design note
in their pairs; every pair's HDR-FLIP (NVIDIA FLIP) in (0, 1) with its
error map written and shown in the page; a peer whose interpreter is missing is "unavailable" with a
reason naming the variable that sets it, and the run goes on.

usage: validate_peers.py PHOTONBRIDGE EXR_PROBE WORKDIR
"""
import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pbcheck import check, finish  # noqa: E402

EXE, PROBE, WORK = sys.argv[1:4]




def means(path):
    p = subprocess.run([PROBE, path], capture_output=True, text=True)
    ch = json.loads(p.stdout)["channels"]
    return [sum(ch[k]) / len(ch[k]) for k in "RGB"]


shutil.rmtree(WORK, ignore_errors=True)
out = os.path.join(WORK, "cb")
cmd = [EXE, "validate", "samples/cornell_box/cornell_box.gltf", "-o", out, "--renderers", "reference,luxcore,mitsuba",
       "--width", "48", "--ref-spp", "256", "--threads", "2", "-q"]
p = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
check(p.returncode == 0, "validate exit %d: %s" % (p.returncode, p.stderr.strip()[-400:]))
r = json.load(open(os.path.join(out, "report.json")))
rend = {x["name"]: x for x in r["renders"]}
ref = means(os.path.join(out, "reference.exr"))
for n in ("luxcore", "mitsuba"):
    x = rend.get(n, {})
    check(x.get("status") == "ok" and (x.get("settings") or {}).get("version"), "%s: %s" % (n, x))
    if x.get("status") != "ok":
        continue
    m = means(os.path.join(out, x["exr"]))
    dev = [abs(a / b - 1) for a, b in zip(m, ref)]
    pair = [q for q in r["pairs"] if q["test"] == n and q["reference"] == "reference"]
    psnr = pair[0].get("psnr_db") if pair else None
    print("validate_peers: %s %s: mean RGB %s against the reference's %s (%s), PSNR %s dB" % (
        n, x["settings"]["version"], ["%.4f" % v for v in m], ["%.4f" % v for v in ref],
        ", ".join("%+.2f %%" % (100 * (a / b - 1)) for a, b in zip(m, ref)), psnr))
    check(max(dev) <= 0.015, "%s's mean is %.2f %% off the reference's" % (n, 100 * max(dev)))
    check(psnr is not None and psnr >= 24.0, "%s against the reference: %s dB (>= 24)" % (n, psnr))
    check(pair and pair[0].get("heatmap") and pair[0].get("relmse") is not None, "%s's pair: %s" % (n, pair))
    check(pair and any(d["renderer"] == n and "export-peer" in d["note"] for d in pair[0]["by_design"]),
          "%s's pair lacks the export-peer note" % n)
check(len(r["pairs"]) == 3, "3 pairs expected: %s" % [(q["test"], q["reference"]) for q in r["pairs"]])
for q in r["pairs"]:
    f = q.get("hdr_flip")
    print("validate_peers: %s vs %s: HDR-FLIP %s, PSNR %s dB" % (q["test"], q["reference"], f, q.get("psnr_db")))
    check(isinstance(f, float) and 0 < f < 1 and q.get("flip_map") and os.path.isfile(os.path.join(out, q["flip_map"])),
          "the pair's FLIP: %s %s %s" % (f, q.get("flip_map"), q.get("flip_error")))
page = open(os.path.join(out, "index.html")).read()
check("HDR-FLIP" in page and all(q.get("flip_map", "?") in page for q in r["pairs"]), "the page lacks the FLIP maps")

# Cycles 4.5 (bpy 4.5 through tests/blender/bpy_blender.py) beside Debian's
# Blender: the sample through Blender 4.5's glTF importer (its Blender script
# is 3.4's), its mean within 1.5 % of the reference's.
out45 = os.path.join(WORK, "cy45")
p = subprocess.run([EXE, "validate", "samples/cornell_box/cornell_box.gltf", "-o", out45, "--renderers",
                    "reference,cycles45", "--width", "32", "--ref-spp", "256", "--cycles-spp", "256", "--threads", "2",
                    "-q"], capture_output=True, text=True, timeout=900)
check(p.returncode == 0, "validate with cycles45: exit %d: %s" % (p.returncode, p.stderr.strip()[-400:]))
r45 = json.load(open(os.path.join(out45, "report.json")))
c45 = {x["name"]: x for x in r45["renders"]}.get("cycles45", {})
st45 = c45.get("settings") or {}
check(c45.get("status") == "ok" and str(st45.get("blender", "")).startswith("4.5") and st45.get("source") == "gltf",
      "Cycles 4.5: %s" % c45)
if c45.get("status") == "ok":
    m = means(os.path.join(out45, c45["exr"]))
    ref45 = means(os.path.join(out45, "reference.exr"))
    dev = max(abs(x / y - 1) for x, y in zip(m, ref45))
    print("validate_peers: Cycles %s (%s): mean RGB %s against the reference's %s" % (
        st45.get("blender"), st45.get("source"), ["%.4f" % v for v in m], ["%.4f" % v for v in ref45]))
    check(dev <= 0.015, "Cycles 4.5's mean is %.2f %% off the reference's" % (100 * dev))

# A peer without its interpreter: unavailable, named; the others go on.
env = dict(os.environ, PB_MITSUBA_PYTHON=os.path.join(WORK, "no-such-python"),
           PB_FLIP_PYTHON=os.path.join(WORK, "no-such-python"))
out2 = os.path.join(WORK, "missing")
p = subprocess.run([EXE, "validate", "samples/cornell_box/cornell_box.gltf", "-o", out2, "--renderers",
                    "reference,mitsuba", "--width", "16", "--ref-spp", "4", "--threads", "1", "-q"],
                   capture_output=True, text=True, timeout=600, env=env)
r2 = json.load(open(os.path.join(out2, "report.json"))) if os.path.exists(os.path.join(out2, "report.json")) else {}
rend2 = {x["name"]: x for x in r2.get("renders", [])}
mi = rend2.get("mitsuba", {})
print("validate_peers: without its interpreter: exit %d, mitsuba %s: %s" % (p.returncode, mi.get("status"),
                                                                            mi.get("reason")))
check(mi.get("status") == "unavailable" and "PB_MITSUBA_PYTHON" in (mi.get("reason") or ""),
      "a missing Mitsuba: %s" % mi)
check(rend2.get("reference", {}).get("status") == "ok", "the reference did not go on: %s" % rend2.get("reference"))
fl = r2.get("flip") or {}
check(fl.get("available") is False and "PB_FLIP_PYTHON" in (fl.get("reason") or ""), "a missing FLIP: %s" % fl)

finish("validate_peers")
