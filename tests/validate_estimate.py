#!/usr/bin/env python3
"""`photonbridge validate`'s estimate of the run's time, printed before the
first render. cornell_box at 24 px, the reference and (where POV-Ray is
installed) POV-Ray's draft preset; photonbridge render and Cycles off, so
that no GPU is needed:
  - one stderr line "validate: estimate: about N UNIT (...)" before the
    first renderer's progress line, naming the reference, and POV-Ray as
    modelled where it runs;
  - report.json's estimate: a positive total_s, the reference measured on a
    probe, the same line;
  - with -q: no estimate line (nothing on stderr, nothing on stdout), and
    report.json still holds the estimate.
No wall-clock value is asserted.

usage: validate_estimate.py PHOTONBRIDGE WORKDIR"""
import json
import os
import re
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "pylib"))
from pbcheck import Checker  # noqa: E402

EXE, WORK = sys.argv[1:3]
T = Checker(EXE, WORK)
d = T.fresh("estimate")
pov = shutil.which("povray") is not None
V = ["--width", "24", "--ref-spp", "4", "--threads", "1", "--pov-quality", "draft",
     "--renderers", "reference,povray" if pov else "reference"]
rc = 0 if pov else 1  # the reference alone is too few renders for exit 0
LINE = re.compile(r"^validate: estimate: about [0-9]+(\.[0-9]+)? (s|min|h) \(.*reference [0-9.]+ (s|min|h)", re.M)

p = T.run(["validate", "cornell_box", "-o", os.path.join(d, "v")] + V, expect_rc=rc)
T.check(p.returncode == rc, "validate: exit %d (%d)" % (rc, p.returncode))
m = LINE.search(p.stderr)
T.check(bool(m), "the estimate line, with a number and a unit (%s)" % p.stderr.strip().splitlines()[:1])
first = p.stderr.find("validate: reference ...")
T.check(m is not None and 0 <= m.start() < first, "the estimate comes before the first render")
if pov:
    T.check(bool(re.search(r"POV-Ray [0-9.]+ (s|min|h) \(modelled\)", p.stderr)), "POV-Ray's part said as modelled")
try:
    e = json.load(open(os.path.join(d, "v", "report.json")))["estimate"]
    printed = re.findall(r"^validate: (estimate: .*)$", p.stderr, re.M)
    T.check(isinstance(e["total_s"], (int, float)) and e["total_s"] > 0 and
            e["parts"]["reference"]["method"] == "probe" and printed == [e["line"]],
            "report.json's estimate: a total, the reference's probe, the line printed")
except (OSError, ValueError, KeyError, TypeError) as ex:
    T.check(False, "report.json's estimate readable (%s)" % ex)

p = T.run(["validate", "cornell_box", "-o", os.path.join(d, "q"), "-q"] + V, expect_rc=rc)  # -q
T.check(p.returncode == rc and "estimate" not in p.stderr and not p.stderr.strip() and not p.stdout.strip(),
        "-q: no estimate line, nothing printed (%r %r)" % (p.stderr[-200:], p.stdout[-200:]))
try:
    e = json.load(open(os.path.join(d, "q", "report.json")))["estimate"]
    T.check(e["total_s"] > 0, "-q: report.json still holds the estimate")
except (OSError, ValueError, KeyError, TypeError) as ex:
    T.check(False, "-q: report.json's estimate readable (%s)" % ex)
sys.exit(T.finish())
