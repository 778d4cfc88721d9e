#!/usr/bin/env python3
"""bench/run_peers.py in its tiny configuration (cornell_box, 32 px, a few
samples a renderer), then structural checks on what it wrote, so that the
peers' benchmark cannot rot unnoticed:

  - the run exits 0 and writes results.json and PEERS.md;
  - every renderer (the Embree reference, LuxCore PhotonGI, LuxCore
    BIDIRVMCPU, Mitsuba 3, Cycles 4.5) has points, all "ok", each with a
    finite PSNR, SSIM and HDR-FLIP in [0, 1] and no non-finite pixel;
  - the JSON has the run's fields (machine, versions with the peers' and
    FLIP's, references, summary rows with times to 25/30/35 dB);
  - more samples give a higher PSNR and a lower FLIP (the reference's 4 and
    32 spp, Mitsuba's 4 and 64 spp).

    bench_peers_check.py PHOTONBRIDGE WORKDIR
Prints one line per check and "N checks, M failed".
"""
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
failed = []
count = [0]


def check(ok, what):
    count[0] += 1
    print("%s: %s" % ("ok" if ok else "FAILED", what))
    if not ok:
        failed.append(what)


def finite(x):
    return isinstance(x, (int, float)) and math.isfinite(x)


def main(argv):
    exe, work = os.path.abspath(argv[0]), os.path.abspath(argv[1])
    out = os.path.join(work, "out")
    os.makedirs(work, exist_ok=True)
    cmd = [sys.executable, os.path.join(ROOT, "bench", "run_peers.py"), "--mode", "tiny", "--exe", exe,
           "--out", out, "--cache", os.path.join(work, "cache"), "--no-photonbridge"]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
    print(p.stdout[-4000:])
    check(p.returncode == 0, "run_peers.py --mode tiny exits 0 (exit %d)" % p.returncode)
    try:
        res = json.load(open(os.path.join(out, "results.json")))
    except (OSError, ValueError) as e:
        check(False, "results.json: %s" % e)
        return
    check(os.path.isfile(os.path.join(out, "PEERS.md")), "PEERS.md written")
    for key in ("machine", "versions", "references", "points", "summary", "width", "threads", "scenes", "flip"):
        check(key in res, "results.json has '%s'" % key)
    v = res.get("versions", {})
    for key in ("photonbridge", "luxcore", "mitsuba", "flip", "bpy"):
        check(bool(v.get(key)), "versions.%s = %s" % (key, v.get(key)))
    pts = res.get("points", [])
    for rn in ("reference", "luxcore-photongi", "luxcore-bidirvm", "mitsuba", "cycles"):
        mine = [q for q in pts if q["renderer"] == rn]
        check(len(mine) > 0, "%s: %d point(s)" % (rn, len(mine)))
        for q in mine:
            what = "%s %s" % (rn, json.dumps(q["params"], separators=(",", ":")))
            check(q.get("status") == "ok", "%s: status %s %s" % (what, q.get("status"), q.get("error", "")))
            check(finite(q.get("psnr_db")) and finite(q.get("ssim")),
                  "%s: PSNR %s dB, SSIM %s finite" % (what, q.get("psnr_db"), q.get("ssim")))
            f = q.get("flip_hdr")
            check(finite(f) and 0.0 <= f <= 1.0, "%s: HDR-FLIP %s in [0, 1]" % (what, f))
            check(q.get("flip_nonfinite") == 0, "%s: no non-finite pixel (%s)" % (what, q.get("flip_nonfinite")))
            check(finite(q.get("wall_s")) and q["wall_s"] > 0, "%s: wall %s s" % (what, q.get("wall_s")))
    for rn, key in (("reference", "spp"), ("mitsuba", "spp")):
        mine = sorted((q for q in pts if q["renderer"] == rn and finite(q.get("psnr_db"))),
                      key=lambda q: q["params"][key])
        if len(mine) >= 2:
            lo, hi = mine[0], mine[-1]
            check(hi["psnr_db"] > lo["psnr_db"], "%s: PSNR %s spp %.2f dB > %s spp %.2f dB" % (
                rn, hi["params"][key], hi["psnr_db"], lo["params"][key], lo["psnr_db"]))
            check(hi["flip_hdr"] < lo["flip_hdr"], "%s: FLIP %s spp %.4f < %s spp %.4f" % (
                rn, hi["params"][key], hi["flip_hdr"], lo["params"][key], lo["flip_hdr"]))
        else:
            check(False, "%s: two points to compare (%d)" % (rn, len(mine)))
    rows = res.get("summary", [])
    check(len(rows) >= 5, "summary: %d rows" % len(rows))
    for row in rows:
        check(all(k in row.get("psnr", {}) for k in ("25", "30", "35")) and "0.1" in row.get("flip", {}),
              "summary %s %s: times to 25/30/35 dB and to FLIP 0.1" % (row.get("scene"), row.get("renderer")))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    main(sys.argv[1:])
    print("%d checks, %d failed" % (count[0], len(failed)))
    sys.exit(1 if failed else 0)
