#!/usr/bin/env python3
"""End-to-end check of bench/run_bench.py in its smoke mode
(cornell_box at 32 px, a few points of photonbridge, the reference and
POV-Ray, a two-point leaf sweep, the radius histogram, one LBVH rate), plus
its time-to-PSNR interpolation on made-up curves.

    python3 tests/bench_smoke.py PHOTONBRIDGE_EXE WORK_DIR

Asserts outcomes that can fail: every point measured (time, peak memory,
PSNR); more samples give a higher PSNR for the reference and more maps for
photonbridge; the leaf-size sweep's leaf count falls from 1 to 512 and T_auto
is reported; the footprint histogram counts every stored photon; the LBVH
rate is positive; results.json, results.csv and BENCHMARKS.md exist with the
ratio table. Prints "N passed, M failed"; exit 1 on a failure, 77 when no
Vulkan device is present.
"""
import csv
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
import run_bench  # noqa: E402

passed = failed = 0


def check(cond, what):
    global passed, failed
    if cond:
        passed += 1
    else:
        failed += 1
        print("FAIL: " + what)


def interpolation():
    pts = [{"wall_s": 1.0, "psnr_db": 20.0}, {"wall_s": 10.0, "psnr_db": 30.0}, {"wall_s": 100.0, "psnr_db": 32.0}]
    t, b = run_bench.time_to_psnr(pts, 25.0)
    check(b == "=" and abs(t - 10 ** 0.5) < 1e-9, "25 dB halfway in log time: %s %s" % (t, b))
    t, b = run_bench.time_to_psnr(pts, 30.0)
    check(b == "=" and abs(t - 10.0) < 1e-9, "30 dB at the second point: %s" % t)
    t, b = run_bench.time_to_psnr(pts, 19.0)
    check(b == "<=" and t == 1.0, "reached at the first point: bound <=")
    t, b = run_bench.time_to_psnr(pts, 35.0)
    check(t is None and b is None, "never reached: None")
    # Points in any order; a later dip does not undo the first crossing.
    t, b = run_bench.time_to_psnr(list(reversed(pts)) + [{"wall_s": 50.0, "psnr_db": 29.0}], 30.0)
    check(abs(t - 10.0) < 1e-9, "first crossing in time order")
    rows = run_bench.summarise(
        [dict(p, scene="s", renderer="photonbridge", config="a", status="ok") for p in pts] +
        [{"scene": "s", "renderer": "reference", "config": "pt", "status": "ok", "wall_s": 40.0, "psnr_db": 30.0}],
        ["s"])
    r30 = [r for r in rows if r["psnr_db"] == 30.0][0]
    check(abs(r30["ratio"] - 0.25) < 1e-9 and r30["best_peer"] == "reference", "ratio = 10 s / 40 s")


def main(argv):
    exe, work = os.path.abspath(argv[0]), os.path.abspath(argv[1])
    interpolation()
    devs = run_bench.devices(exe)
    if not devs:
        print("SKIP: no Vulkan device")
        return 77
    shutil.rmtree(work, ignore_errors=True)
    out = os.path.join(work, "out")
    p = subprocess.run([sys.executable, os.path.join(ROOT, "bench", "run_bench.py"), "--mode", "smoke", "--exe", exe,
                        "--out", out, "--cache", os.path.join(work, "cache")],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=900)
    print(p.stdout[-3000:])
    check(p.returncode == 0, "run_bench exit %d" % p.returncode)
    res = run_bench.read_json(os.path.join(out, "results.json"))
    check(res is not None, "results.json written")
    if not res:
        print("%d passed, %d failed" % (passed, failed))
        return 1
    pts = res["points"]
    for r in ("photonbridge", "reference"):
        check(any(x["renderer"] == r for x in pts), "points of " + r)
    for x in pts:
        tag = "%s %s" % (x["renderer"], json.dumps(x["params"]))
        check(x["status"] == "ok", tag + ": " + x.get("error", "ok"))
        check(x.get("psnr_db") is not None and 5 < x["psnr_db"] < 80, tag + ": PSNR %s" % x.get("psnr_db"))
        check(x["wall_s"] > 0, tag + ": wall time")
        # Peak RSS from the helper: a real process is over 1 MiB and under 8 GiB.
        check(x["maxrss_mb"] is not None and 1 < x["maxrss_mb"] < 8192, tag + ": peak RSS %s" % x["maxrss_mb"])

    def psnr(renderer, key, value):
        return [x["psnr_db"] for x in pts if x["renderer"] == renderer and x["params"].get(key) == value][0]

    check(psnr("reference", "spp", 16) > psnr("reference", "spp", 1) + 3, "reference: 16 spp beats 1 spp by 3 dB")
    check(psnr("photonbridge", "iterations", 4) > psnr("photonbridge", "iterations", 1) + 1,
          "photonbridge: 4 maps beat 1")
    ref = res["references"]["cornell_box"]
    check(ref["noise"] and ref["noise"]["psnr_db"] > 20, "converged reference with its noise estimate")
    check(os.path.isfile(ref["exr"]), "converged reference cached")
    it = res["internals"]
    ls = it["leaf_sweep"][0]
    rows = {r["leaf_size"]: r for r in ls["rows"]}
    check(rows[1]["leaves"] > rows[512]["leaves"], "leaf sweep: fewer leaves at 512 than at 1")
    check(rows["auto"]["leaf_used"] == rows["auto"]["t_auto"] and rows[512]["leaf_used"] == 512, "leaf size used")
    check(0 < ls.get("auto_fraction_of_best", 0) <= 5, "T_auto fraction of the best manual speed")
    h = it["histograms"][0]
    check(h.get("histogram") and sum(h["histogram"]["counts"]) == h["stored"],
          "radius histogram counts every stored photon")
    check(h.get("k_pd", 0) > 0, "k_PD reported")
    lb = it["lbvh_rates"]
    check(len(lb) == 1 and lb[0].get("build_mphotons_s", 0) > 0 and lb[0].get("sort_mkeys_s", 0) > 0,
          "LBVH build and sort rates")
    check(it["passes"] and "gather" in it["passes"][0]["passes_ms"], "per-pass breakdown")
    with open(os.path.join(out, "results.csv")) as f:
        check(len(list(csv.DictReader(f))) == len(pts), "results.csv: one row per point")
    md = open(os.path.join(out, "BENCHMARKS.md")).read()
    check("Time to reach 25, 30 and 35 dB" in md and "| cornell_box |" in md, "BENCHMARKS.md table")
    check("T_auto reaches" in md, "BENCHMARKS.md leaf sweep")
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
