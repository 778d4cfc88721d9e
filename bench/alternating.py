#!/usr/bin/env python3
"""Repeated, alternating runs of a few `make bench` rows on a shared machine.

    python3 bench/alternating.py ratio [--scenes a,b] [--repeat R] [--exe EXE] [--out FILE]
    python3 bench/alternating.py leaf  [--scenes a,b] [--repeat R] [--exe EXE] [--out FILE]

`make bench` times every point once. On a machine other work shares (six
sessions on two cores), one run's times carry the load of the moment: a
neighbour's build during one point and not the next moves a ratio by 2x and
a leaf-size sweep by 50 %. This driver runs the same points as run_bench.py
(its CONFIGS["full"], converged references from its cache) R times, in an
order that alternates between the two sides being compared and is reversed
on every other round, and reports the median of each point's times with
their spread (min, max) and the load average at each run:

  ratio: photonbridge's "2^16 photons/map" and "2^18 photons/map" curves (up
         to 8 maps) and the reference path tracer's spp curve (up to 256 spp,
         1024 on cornell_box: past 30 dB); each point's PSNR (the
         renders are deterministic: the same image every round) and median
         wall time (spawn to exit, as run_bench.py), time to 25/30/35 dB per
         renderer (run_bench.time_to_psnr over the medians) and the ratio.
  leaf:  the Table 1 leaf-size sweep (run_bench's leaf_setup: gather + LBVH
         build GPU ms per threshold and T_auto), every threshold once per
         round in a rotated order; T_auto's share of the best fixed
         threshold's speed from the medians, and a least-squares fit of the
         medians to the traversal cost model of lbvh_bounds.comp (time =
         a + c_node V(T) + c_photon P(T) per scene, one ratio c_node /
         c_photon over all scenes).

Writes one JSON file (default bench/results/DEVICE/alternating/MODE.json)
and prints Markdown tables.
"""
import argparse
import json
import math
import os
import statistics
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import run_bench as rb  # noqa: E402


def args_ns(a):
    """A namespace run_bench.Bench accepts."""
    return argparse.Namespace(exe=a.exe, out=os.path.dirname(os.path.abspath(a.out)), cache=a.cache, width=0,
                              device=a.device, minutes=0, ref_spp=0, refresh_references=False)


def med(xs):
    return statistics.median(xs) if xs else None


# The reference's spp sweep is cut where it is past 30 dB on these scenes
# (run_bench's full run: 256 spp gives 29.3 dB on cornell_box, 31.2 and 37.5
# on cornell_caustics and spot_room), and photonbridge's at 8 maps.
REF_MAX_SPP = {"cornell_box": 1024}


def run_ratio(b, scenes, repeat, max_iterations=8):
    cfg = b.cfg
    curves = [c for c in cfg["photonbridge"] if c["label"] in ("2^16 photons/map", "2^18 photons/map")]
    rows = {}
    for s in scenes:
        ref = b.reference(s)
        pb = [("photonbridge", c["label"], p) for c in curves for p in c["points"] if p["iterations"] <= max_iterations]
        rf = [("reference", "path tracing", {"spp": spp}) for spp in cfg["reference"]
              if spp <= REF_MAX_SPP.get(s, 256)]
        # Alternate: pb, ref, pb, ref, ... (the longer list's tail at the end).
        order = []
        for i in range(max(len(pb), len(rf))):
            if i < len(pb):
                order.append(pb[i])
            if i < len(rf):
                order.append(rf[i])
        for rep in range(repeat):
            seq = order if rep % 2 == 0 else list(reversed(order))
            for rn, label, p in seq:
                key = (s, rn, label, json.dumps(p, sort_keys=True))
                tag = "%s_%s_%d" % (s, rb.slug(rn + "_" + label + "_" + json.dumps(p, sort_keys=True)), rep)
                exr, js = os.path.join(b.work, tag + ".exr"), os.path.join(b.work, tag + ".json")
                if rn == "photonbridge":
                    cmd = [b.exe, "render", b.scene_path(s), "-o", exr, "--width", str(b.width), "--spp",
                           str(p["spp"]), "--photons", str(p["photons"]), "--iterations", str(p["iterations"]),
                           "--json", js, "-q"] + p["extra"] + b.dev
                else:
                    cmd = [b.exe, "reference", b.scene_path(s), "-o", exr, "--width", str(b.width), "--spp",
                           str(p["spp"]), "--seed", "1", "--json", js, "-q"]
                load = rb.loadavg()
                r = rb.run_point(cmd, os.path.join(b.work, tag + ".log"), b.timeout)
                row = rows.setdefault(key, {"scene": s, "renderer": rn, "config": label, "params": p, "wall_s": [],
                                            "load_1m": [], "psnr_db": None})
                if r["rc"] != 0 or not os.path.isfile(exr):
                    row["error"] = rb.tail(r["out"])
                    continue
                if row["psnr_db"] is None or rep == 0:
                    m = b.compare(exr, ref["exr"], tag)
                    row["psnr_db"] = m.get("psnr_db")
                    st = rb.read_json(js) or {}
                    ph = st.get("photons") or {}
                    row["photons_stored"], row["k_pd"] = ph.get("stored"), ph.get("k_pd")
                os.unlink(exr)
                row["wall_s"].append(r["wall_s"])
                row["load_1m"].append(load)
                b.log("%-16s %-12s %-18s %-50s %7.2f s load %4.1f PSNR %s" % (
                    s, rn, label, json.dumps(p, separators=(",", ":"))[:50], r["wall_s"], load or -1,
                    "%.2f" % row["psnr_db"] if row["psnr_db"] is not None else "-"))
    out = list(rows.values())
    for row in out:
        row["median_s"] = med(row["wall_s"])
    summary = []
    for s in scenes:
        for thr in rb.THRESHOLDS_DB:
            best = {}
            for rn in ("photonbridge", "reference"):
                for label in set(r["config"] for r in out if r["scene"] == s and r["renderer"] == rn):
                    pts = [{"wall_s": r["median_s"], "psnr_db": r["psnr_db"]} for r in out
                           if r["scene"] == s and r["renderer"] == rn and r["config"] == label and r["median_s"]]
                    t, bound = rb.time_to_psnr(pts, thr)
                    if t is not None and (rn not in best or t < best[rn][0]):
                        best[rn] = (t, bound, label)
            e = {"scene": s, "psnr_db": thr, "best": {k: list(v) for k, v in best.items()}}
            if "photonbridge" in best and "reference" in best:
                e["ratio"] = best["photonbridge"][0] / best["reference"][0]
                pb_b, rf_b = best["photonbridge"][1] == "<=", best["reference"][1] == "<="
                e["ratio_bound"] = "?" if pb_b and rf_b else ("<=" if pb_b else (">=" if rf_b else "="))
            summary.append(e)
    return {"points": out, "summary": summary}


def ratio_markdown(res):
    L = ["| scene | dB | photonbridge s (curve) | reference s | ratio |", "|---|---|---|---|---|"]
    for e in res["summary"]:
        pb, rf = e["best"].get("photonbridge"), e["best"].get("reference")
        f = lambda v: ("&le; " if v[1] == "<=" else "") + "%.2f" % v[0] if v else "not reached"  # noqa: E731
        L.append("| %s | %g | %s%s | %s | %s |" % (
            e["scene"], e["psnr_db"], f(pb), " (%s)" % pb[2] if pb else "", f(rf),
            ("%s%.2f" % ({"=": "", "<=": "&le; ", ">=": "&ge; ", "?": "~"}[e["ratio_bound"]], e["ratio"]))
            if "ratio" in e else "-"))
    L.append("")
    L.append("| scene | renderer | point | PSNR dB | median s | min-max s | loads |")
    L.append("|---|---|---|---|---|---|---|")
    for r in res["points"]:
        w = r["wall_s"]
        L.append("| %s | %s | %s | %s | %s | %s | %s |" % (
            r["scene"], r["renderer"], r["config"] + " " + json.dumps(r["params"], separators=(",", ":")),
            "%.2f" % r["psnr_db"] if r.get("psnr_db") is not None else "-",
            "%.2f" % r["median_s"] if r.get("median_s") else "-",
            "%.2f-%.2f" % (min(w), max(w)) if w else "-",
            " ".join("%.1f" % x for x in r["load_1m"] if x is not None)))
    return "\n".join(L)


# The traversal cost model of lbvh_bounds.comp (pb_t_auto): photons tested P
# and inner nodes opened V per query for threshold t, k footprints over a
# point, n photons.
def model_vp(t, k, n):
    kp, nf = max(k, 0.0) / math.pi, max(float(n), 1.0)
    sl = max(t * 0.72134752, 1.0)
    sq = math.sqrt(sl) + 2.0 * math.sqrt(kp)
    p, v, sz = sq * sq, 0.0, 2.0 * sl
    while sz < nf:
        c = 1.0 + 2.0 * math.sqrt(kp / sz)
        v += min(nf / sz, c * c)
        sz *= 2.0
    return v, p


def run_leaf(b, scenes, repeat, partial=None):
    s_cfg = b.cfg["leaf_setup"]
    sizes = [0] + list(b.cfg["leaf_sizes"])
    out = []
    for s in scenes:
        rows = {leaf: {"leaf_size": leaf or "auto", "query_ms": [], "gather_ms": [], "lbvh_ms": [], "load_1m": [],
                       "cpu_s": []} for leaf in sizes}
        for rep in range(repeat):
            k = rep % len(sizes)
            seq = sizes[k:] + sizes[:k]
            if rep % 2:
                seq = list(reversed(seq))
            for leaf in seq:
                tag = "%s_leaf_%d_%d" % (s, leaf, rep)
                exr, js = os.path.join(b.work, tag + ".exr"), os.path.join(b.work, tag + ".json")
                cmd = [b.exe, "render", b.scene_path(s), "-o", exr, "--width", str(s_cfg["width"]), "--spp",
                       str(s_cfg["spp"]), "--photons", str(s_cfg["photons"]), "--iterations",
                       str(s_cfg["iterations"]), "--json", js, "-q"] + b.dev
                if leaf:
                    cmd += ["--leaf-size", str(leaf)]
                load = rb.loadavg()
                r = rb.run_point(cmd, os.path.join(b.work, tag + ".log"), b.timeout)
                st = rb.read_json(js)
                if os.path.exists(exr):
                    os.unlink(exr)
                row = rows[leaf]
                if r["rc"] != 0 or not st:
                    row["error"] = rb.tail(r["out"])
                    continue
                pm = st["passes_ms"]
                row.update(t_auto=st["photons"]["t_auto"], leaves=st["photons"]["lbvh_leaves"],
                           k_pd=st["photons"]["k_pd"], stored=st["photons"]["stored"])
                g, lb = pm.get("gather") or 0, pm.get("lbvh_build") or 0
                row["gather_ms"].append(g)
                row["lbvh_ms"].append(lb)
                row["query_ms"].append(g + lb)
                row["load_1m"].append(load)
                row["cpu_s"].append(r.get("cpu_s"))
                b.log("leaf %-5s %-16s round %d: %.1f ms, process %.2f s CPU (load %.1f)" % (
                    leaf or "auto", s, rep, g + lb, r.get("cpu_s") or -1, load or -1))
        rl = [rows[x] for x in sizes]
        for r in rl:
            r["median_ms"] = med(r["query_ms"])
            r["median_cpu_s"] = med([x for x in r["cpu_s"] if x is not None])
        ok = [r for r in rl if r["median_ms"]]
        auto = [r for r in ok if r["leaf_size"] == "auto"]
        man = [r for r in ok if r["leaf_size"] != "auto"]
        e = {"scene": s, "setup": s_cfg, "rows": rl}
        if auto and man:
            bm = min(man, key=lambda r: r["median_ms"])
            t_auto = auto[0]["t_auto"]
            # T_auto's own threshold among the fixed ones, when it was swept.
            e.update(t_auto=t_auto, best_leaf=bm["leaf_size"], best_ms=bm["median_ms"], auto_ms=auto[0]["median_ms"],
                     auto_fraction=bm["median_ms"] / auto[0]["median_ms"])
            # The same from the process CPU time (everything but the gather
            # and the build is the same at every threshold, so the
            # differences are theirs; the fraction is of the whole process).
            mc = [r for r in man if r.get("median_cpu_s")]
            if mc and auto[0].get("median_cpu_s"):
                bc = min(mc, key=lambda r: r["median_cpu_s"])
                e.update(best_leaf_cpu=bc["leaf_size"], best_cpu_s=bc["median_cpu_s"],
                         auto_cpu_s=auto[0]["median_cpu_s"])
        out.append(e)
        if partial:  # what is done so far, should the run be stopped
            with open(partial, "w") as f:
                json.dump({"sweeps": out}, f, indent=1)
    fit = fit_costs(out)
    return {"sweeps": out, "fit": fit}


def fit_costs(sweeps):
    """Least squares of median_ms = a_scene + c_node V + c_photon P over the
    fixed thresholds of every scene (V, P: the model's counts per query times
    the scene's queries, which cancel into c per scene as they are the same
    queries at every threshold: time_s(T) = a_s + q_s (c_n V_s(T) + c_p
    P_s(T))). Solved as: for a trial ratio rho = c_n / c_p on a grid, each
    scene's (a_s, q_s c_p) by linear least squares; the rho of least total
    relative squared residual."""
    best = None
    for i in range(0, 401):
        rho = 10 ** (-2 + i * 0.01)  # 0.01 .. 100
        tot, per = 0.0, []
        for e in sweeps:
            pts = [(r["leaf_size"], r["median_ms"], r.get("k_pd"), r.get("stored")) for r in e["rows"]
                   if r.get("median_ms") and r["leaf_size"] != "auto" and r.get("stored")]
            if len(pts) < 3:
                continue
            xs, ys = [], []
            for t, y, k, n in pts:
                v, p = model_vp(t, k or 0, n)
                xs.append(rho * v + p)
                ys.append(y)
            # y = a + b x, weighted by 1 / y (relative residuals)
            w = [1.0 / (y * y) for y in ys]
            sw, sx, sy = sum(w), sum(wi * x for wi, x in zip(w, xs)), sum(wi * y for wi, y in zip(w, ys))
            sxx, sxy = sum(wi * x * x for wi, x in zip(w, xs)), sum(wi * x * y for wi, x, y in zip(w, xs, ys))
            den = sw * sxx - sx * sx
            if den <= 0:
                continue
            bb = (sw * sxy - sx * sy) / den
            aa = (sy - bb * sx) / sw
            res = sum(wi * (y - aa - bb * x) ** 2 for wi, x, y in zip(w, xs, ys))
            tot += res
            per.append({"scene": e["scene"], "a_ms": aa, "b_ms": bb, "rms_rel": math.sqrt(res / len(xs))})
        if per and (best is None or tot < best["residual"]):
            best = {"node_over_photon": rho, "residual": tot, "scenes": per}
    return best


def leaf_markdown(res):
    L = []
    for e in res["sweeps"]:
        L.append("%s (setup %s): median of %d rounds, gather + LBVH build GPU ms" % (
            e["scene"], json.dumps(e["setup"]), max(len(r["query_ms"]) for r in e["rows"])))
        L.append("")
        L.append("| leaf size | " + " | ".join(str(r["leaf_size"]) for r in e["rows"]) + " |")
        L.append("|---|" + "---|" * len(e["rows"]))
        L.append("| median ms | " + " | ".join("%.1f" % r["median_ms"] if r.get("median_ms") else "-"
                                              for r in e["rows"]) + " |")
        L.append("| min-max | " + " | ".join("%.0f-%.0f" % (min(r["query_ms"]), max(r["query_ms"]))
                                            if r["query_ms"] else "-" for r in e["rows"]) + " |")
        L.append("| process CPU s | " + " | ".join("%.2f" % r["median_cpu_s"] if r.get("median_cpu_s") else "-"
                                                  for r in e["rows"]) + " |")
        if "auto_fraction" in e:
            L.append("")
            L.append("T_auto = %d; best fixed threshold %s (%.1f ms); T_auto reaches %.0f %% of its speed." % (
                e["t_auto"], e["best_leaf"], e["best_ms"], 100 * e["auto_fraction"]))
            if "best_cpu_s" in e:
                L.append("Process CPU: best fixed %s (%.2f s), T_auto %.2f s." % (e["best_leaf_cpu"], e["best_cpu_s"],
                                                                                 e["auto_cpu_s"]))
        L.append("")
    f = res.get("fit")
    if f:
        L.append("Cost model fit (all scenes): c_node / c_photon = %.2f; per scene rms relative residual %s" % (
            f["node_over_photon"], ", ".join("%s %.1f %%" % (x["scene"], 100 * x["rms_rel"]) for x in f["scenes"])))
    return "\n".join(L)


def main(argv):
    ap = argparse.ArgumentParser(prog="alternating.py", description=__doc__.split("\n")[0])
    ap.add_argument("mode", choices=("ratio", "leaf"))
    ap.add_argument("--scenes")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--exe", default=os.path.join(rb.ROOT, "build", "photonbridge"))
    ap.add_argument("--device", type=int)
    ap.add_argument("--cache", default=os.path.join(HERE, "cache"))
    ap.add_argument("--out")
    ap.add_argument("--leaf-sizes", help="comma-separated fixed thresholds (default run_bench's full list)")
    a = ap.parse_args(argv)
    cfg = rb.CONFIGS["full"]
    if not os.access(a.exe, os.X_OK):
        print("alternating: %s: no photonbridge executable" % a.exe, file=sys.stderr)
        return 2
    devs = rb.devices(os.path.abspath(a.exe))
    dev = next((d for d in devs if (d["index"] == a.device if a.device is not None else d["default"])), None)
    if not dev:
        print("alternating: no Vulkan device", file=sys.stderr)
        return 2
    if not a.out:
        a.out = os.path.join(HERE, "results", rb.slug(dev["name"]), "alternating", a.mode + ".json")
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    if a.leaf_sizes:
        cfg = dict(cfg, leaf_sizes=[int(x) for x in a.leaf_sizes.split(",")])
    b = rb.Bench(args_ns(a), cfg)
    b.version = rb.subprocess.run([b.exe, "--version"], stdout=rb.subprocess.PIPE,
                                  universal_newlines=True).stdout.strip()
    rb.build_peak_helper(b.cache)
    default = cfg["scenes"] if a.mode == "ratio" else cfg["leaf_scenes"]
    scenes = a.scenes.split(",") if a.scenes else default
    t0, load0 = time.time(), rb.loadavg()
    res = (run_ratio(b, scenes, a.repeat) if a.mode == "ratio" else
           run_leaf(b, scenes, a.repeat, partial=a.out + ".partial"))
    res.update(mode=a.mode, repeat=a.repeat, scenes=scenes, width=b.width, device=dev,
               version=b.version, machine=rb.machine_info(), started=time.strftime("%Y-%m-%d %H:%M UTC",
                                                                                    time.gmtime(t0)),
               duration_s=round(time.time() - t0), load_start=load0, load_end=rb.loadavg())
    md = ratio_markdown(res) if a.mode == "ratio" else leaf_markdown(res)
    res["markdown"] = md
    with open(a.out, "w") as f:
        json.dump(res, f, indent=1)
    rb.shutil.rmtree(b.work, ignore_errors=True)
    print(md)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
