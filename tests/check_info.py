#!/usr/bin/env python3
"""`photonbridge info --json -` on a sample: it loads, with a camera from the
file, at least one light, triangles, a consistent bounding box and no
warnings, and the text summary names the same counts."""
import json, subprocess, sys

exe, scene = sys.argv[1], sys.argv[2]
problems = []
p = subprocess.run([exe, "info", scene, "--json", "-"], capture_output=True, text=True, timeout=120)
if p.returncode != 0:
    print(f"info failed ({p.returncode}): {p.stderr.strip()}")
    sys.exit(1)
j = json.loads(p.stdout)
if j["triangles"] <= 0: problems.append("no triangles")
if not j["cameras"] or j["cameras"][0]["synthesized"]: problems.append("no camera in the file")
if not j["lights"]: problems.append("no lights")
if any(lo > hi for lo, hi in zip(j["bounds_min"], j["bounds_max"])): problems.append("inverted bounds")
if j["warnings"]: problems.append("warnings: " + "; ".join(j["warnings"]))
for l in j["lights"]:
    if not (l.get("intensity_w_sr", l.get("irradiance_w_m2", 0)) > 0): problems.append(f"light {l['name']} has no power")
t = subprocess.run([exe, "info", scene], capture_output=True, text=True, timeout=120)
if f"triangles  {j['triangles']}" not in t.stdout: problems.append("text summary disagrees with --json")
# The photon tracers render --tracer takes (bvh the default), in both forms.
if j.get("tracers") != ["bvh", "images"] or "tracers    bvh (default" not in t.stdout or ", images (" not in t.stdout:
    problems.append("tracers not listed: %r" % j.get("tracers"))
checks = 8
for m in problems: print("FAIL:", m)
print(f"{checks - len(problems)} passed, {len(problems)} failed")
sys.exit(1 if problems else 0)
