#!/usr/bin/env python3
"""ring to 35 dB: photonbridge's caustic-share configurations against the
reference renderer, interleaved on a shared machine (ring's 35 dB goal).

    python3 bench/ring_share.py [--exe build/photonbridge] [--repeat 3] [--out FILE]

Every round runs each point once, alternating photonbridge and reference
points, the order reversed on every other round (as bench/alternating.py);
each point is one process timed spawn to exit (run_bench.run_point), its
PSNR from `photonbridge compare` against run_bench's cached converged
reference (128 px, 2048 spp; `run_bench.py --references-only --scenes ring`
makes it). Reports the median wall time per point, the time to 35 dB per
renderer (run_bench.time_to_psnr over the medians) and the ratio.
"""
import argparse
import json
import os
import statistics
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import run_bench as rb  # noqa: E402

SCENE = os.path.join(ROOT, "samples", "ring", "ring.gltf")
PB = [
    # label, photons per map, maps, spp, extra
    ("old: rsm, share 0, S_c 0.5", 1 << 16, 16, 32, ["--first-bounce", "rsm", "--caustic-share", "0",
                                                      "--smoothing-caustic", "0.5"]),
    ("auto (share 0.5, S_c 1)", 1 << 17, 1, 8, ["--first-bounce", "auto"]),
    ("auto (share 0.5, S_c 1)", 1 << 17, 1, 16, ["--first-bounce", "auto"]),
    ("auto (share 0.5, S_c 1)", 1 << 18, 1, 16, ["--first-bounce", "auto"]),
    ("auto (share 0.5, S_c 1)", 1 << 18, 1, 32, ["--first-bounce", "auto"]),
    ("auto, share 0.9", 1 << 17, 1, 16, ["--first-bounce", "auto", "--caustic-share", "0.9"]),
    ("auto, share 0.9", 1 << 18, 1, 16, ["--first-bounce", "auto", "--caustic-share", "0.9"]),
]
REF_SPP = [64, 128, 256]


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "photonbridge"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--cache", default=os.path.join(HERE, "cache"))
    ap.add_argument("--out", default=os.path.join(HERE, "results", "lavapipe", "alternating", "ring_share.json"))
    a = ap.parse_args(argv)
    exe = os.path.abspath(a.exe)
    work = os.path.join(tempfile.gettempdir(), "pb_ring_share")
    os.makedirs(work, exist_ok=True)
    refs = [f for f in os.listdir(a.cache) if f.startswith("ring_w128_spp2048_") and f.endswith(".exr")]
    if not refs:
        print("ring_share: no cached reference (run_bench.py --references-only --scenes ring)", file=sys.stderr)
        return 2
    ref = os.path.join(a.cache, sorted(refs)[0])
    rb.PEAK["exe"] = None
    pts = [("photonbridge", lab, {"photons": n, "iterations": k, "spp": spp, "extra": ex})
           for lab, n, k, spp, ex in PB] + [("reference", "path tracing + SPPM", {"spp": s}) for s in REF_SPP]
    pb_idx = [i for i, p in enumerate(pts) if p[0] == "photonbridge"]
    rf_idx = [i for i, p in enumerate(pts) if p[0] == "reference"]
    order = []
    for i in range(max(len(pb_idx), len(rf_idx))):
        if i < len(pb_idx):
            order.append(pb_idx[i])
        if i < len(rf_idx):
            order.append(rf_idx[i])
    walls = {i: [] for i in range(len(pts))}
    loads = {i: [] for i in range(len(pts))}
    psnr, extra = {}, {}
    for rep in range(a.repeat):
        seq = order if rep % 2 == 0 else list(reversed(order))
        for i in seq:
            rn, lab, p = pts[i]
            exr, js, log = [os.path.join(work, "p%d%s" % (i, e)) for e in (".exr", ".json", ".log")]
            if rn == "photonbridge":
                cmd = [exe, "render", SCENE, "-o", exr, "--width", "128", "--spp", str(p["spp"]), "--photons",
                       str(p["photons"]), "--iterations", str(p["iterations"]), "--json", js, "-q"] + p["extra"]
            else:
                cmd = [exe, "reference", SCENE, "-o", exr, "--width", "128", "--spp", str(p["spp"]), "--seed", "1",
                       "--json", js, "-q"]
            loads[i].append(rb.loadavg())
            r = rb.run_point(cmd, log, 600)
            if r["rc"] != 0:
                print("failed: %s" % " ".join(cmd), file=sys.stderr)
                continue
            walls[i].append(r["wall_s"])
            cj = os.path.join(work, "c%d.json" % i)
            rb.subprocess.run([exe, "compare", exr, ref, "--json", cj, "-q"], check=True)
            psnr[i] = json.load(open(cj))["psnr_db"]
            if rn == "photonbridge":
                st = json.load(open(js))
                ph = st.get("photons") or {}
                extra[i] = {"emitted": ph.get("emitted"), "stored": ph.get("stored"), "caustic": ph.get("caustic"),
                            "k_pd": ph.get("k_pd"), "passes_ms": st.get("passes_ms")}
            print("round %d %-12s %-28s %-60s %.2f s %.2f dB load %.1f" % (
                rep + 1, rn, lab, json.dumps(p)[:60], r["wall_s"], psnr[i], loads[i][-1] or -1), flush=True)
    rows = []
    for i, (rn, lab, p) in enumerate(pts):
        if not walls[i]:
            continue
        rows.append({"renderer": rn, "config": lab, "params": p, "psnr_db": psnr[i],
                     "wall_s": statistics.median(walls[i]), "wall_min": min(walls[i]), "wall_max": max(walls[i]),
                     "loads": loads[i], "extra": extra.get(i)})
    res = {"rows": rows, "reference": ref, "repeat": a.repeat}
    for target in (30.0, 35.0):
        t = {}
        for rn in ("photonbridge", "reference"):
            best = None
            for lab in sorted({r["config"] for r in rows if r["renderer"] == rn}):
                tt = rb.time_to_psnr([r for r in rows if r["renderer"] == rn and r["config"] == lab], target)
                if tt and tt[0] is not None and (best is None or tt[0] < best[0]):
                    best = (tt[0], tt[1], lab)
            t[rn] = best
        res["to_%g_db" % target] = t
        pb, rf = t["photonbridge"], t["reference"]
        print("%g dB: photonbridge %s, reference %s, ratio %s" % (
            target, "%.2f s (%s%s)" % (pb[0], pb[1] or "", pb[2]) if pb else "not reached",
            "%.2f s%s" % (rf[0], " " + rf[1] if rf[1] else "") if rf else "not reached",
            "%.2f" % (pb[0] / rf[0]) if pb and rf else "-"))
    print("| renderer | configuration | photons x maps, spp | caustic records | k_PD | PSNR dB | median wall s (min-max) |")
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        p, e = r["params"], r["extra"] or {}
        pp = ("2^%d x %d, %d spp" % (p["photons"].bit_length() - 1, p["iterations"], p["spp"])
              if r["renderer"] == "photonbridge" else "%d spp" % p["spp"])
        print("| %s | %s | %s | %s | %s | %.2f | %.2f (%.2f-%.2f) |" % (
            r["renderer"], r["config"], pp, e.get("caustic", "-"),
            "%.2f" % e["k_pd"] if e.get("k_pd") is not None else "-", r["psnr_db"], r["wall_s"], r["wall_min"],
            r["wall_max"]))
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(res, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
