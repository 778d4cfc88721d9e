#!/usr/bin/env python3
"""The density-estimator interface (src/render/estimate/estimator.h).

interface: `render --estimator lbvh` and `--estimator auto` (auto resolves to
  lbvh) give the default's pixels (to float rounding: the photon store's
  order follows the GPU's scheduling, as in tests/frame_same_pixels.py) and
  --json "estimator": {"name": "lbvh", ...} with the LBVH's named statistics,
  the former photons.t_auto / leaf_size / lbvh_leaves keys equal to them; a
  sequence's frames carry the same object; `info` names what auto picks and
  which estimators are built; an estimator this binary lacks is refused with
  a one-line error and exit 2 before any device work.

knn: see part_knn.
knn_spot: see part_knn_spot.
samples: see part_samples (every estimator renders every sample).
furnace: see part_furnace (a closed box: each estimator against the reference).

usage: estimator_check.py PHOTONBRIDGE EXR_PROBE ROOT WORKDIR [PART...]
Exit 77 when no Vulkan device is present."""
import base64
import glob
import json
import math
import os
import struct
import shutil
import subprocess
import sys

EXE, PROBE, ROOT, WORK = sys.argv[1:5]
PARTS = sys.argv[5:] or ["interface"]
ROUNDING = 1e-5
CORNELL = os.path.join(ROOT, "samples", "cornell_box", "cornell_box.gltf")
COMMON = ["--width", "40", "--height", "32", "--spp", "2", "--iterations", "2", "--photons", "4096", "--seed", "5",
          "-q"]
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def run(args, env_extra=None):
    env = dict(os.environ)
    env.setdefault("PB_VK_VALIDATION", "1")
    env.update(env_extra or {})
    p = subprocess.run([EXE] + args, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        print(" ".join([EXE] + args))
        print(p.stdout[-3000:])
        print(p.stderr[-3000:])
    return p


def exr(path):
    p = subprocess.run([PROBE, path], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(p.stderr)
    return json.loads(p.stdout)["channels"]


def worst_rel(a, b):
    peak = max(max((abs(v) for v in a), default=0.0), 1e-6)
    return max((abs(x - y) for x, y in zip(a, b)), default=0.0) / peak


def same_pixels(label, got, want):
    a, b = exr(got), exr(want)
    worst, name = 0.0, ""
    for ch in sorted(set(a) & set(b)):
        w = worst_rel(a[ch], b[ch]) if len(a[ch]) == len(b[ch]) else float("inf")
        if w > worst:
            worst, name = w, ch
    check(sorted(a) == sorted(b) and worst <= ROUNDING,
          "%s: the same channels, equal to float rounding (worst %.3g of the peak, %s)" % (label, worst, name or "-"))


def fresh(sub):
    d = os.path.join(WORK, sub)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    return d


def info_estimators():
    p = run(["info", CORNELL, "--json", "-"])
    check(p.returncode == 0, "info --json exits 0")
    e = json.loads(p.stdout).get("estimator", {}) if p.returncode == 0 else {}
    t = run(["info", CORNELL])
    check(e.get("auto") == "lbvh" and "lbvh" in e.get("built", []) and e.get("auto_rule"),
          "info --json estimator: auto %s, built %s" % (e.get("auto"), e.get("built")))
    check("estimator  auto -> %s" % e.get("auto") in t.stdout, "info's text names what auto picks")
    return e.get("built", [])


def part_interface():
    d = fresh("interface")
    built = info_estimators()
    outs = {}
    for name in ["default", "lbvh", "auto"]:
        out, js = os.path.join(d, name + ".exr"), os.path.join(d, name + ".json")
        extra = [] if name == "default" else ["--estimator", name]
        p = run(["render", CORNELL, "-o", out, "--json", js] + COMMON + extra)
        check(p.returncode == 0, "render --estimator %s exits 0" % name)
        if p.returncode != 0:
            continue
        outs[name] = out
        j = json.load(open(js))
        e, ph = j.get("estimator", {}), j.get("photons", {})
        check(e.get("name") == "lbvh", "%s: --json estimator.name %s" % (name, e.get("name")))
        check(all(k in e for k in ("photons", "t_auto", "leaf_size", "leaves")) and e["photons"] > 0 and
              e["t_auto"] >= 1 and e["leaves"] >= 1,
              "%s: the LBVH's named statistics (photons %s, t_auto %s, leaves %s)" %
              (name, e.get("photons"), e.get("t_auto"), e.get("leaves")))
        check(ph.get("t_auto") == e.get("t_auto") and ph.get("leaf_size") == e.get("leaf_size") and
              ph.get("lbvh_leaves") == e.get("leaves"),
              "%s: photons.t_auto / leaf_size / lbvh_leaves kept, equal to estimator's" % name)
        pm = j.get("passes_ms", {})
        check(pm.get("lbvh_build") == pm.get("estimator_build") and pm.get("lbvh_build", -1) >= 0,
              "%s: passes_ms.estimator_build %s (lbvh_build kept)" % (name, pm.get("estimator_build")))
        check(j["guarded"]["nonfinite_values"] == 0, "%s: no non-finite values" % name)
    for name in ("lbvh", "auto"):
        if name in outs and "default" in outs:
            same_pixels("--estimator %s vs the default" % name, outs[name], outs["default"])
    # The fixed leaf size reaches the LBVH estimator's description.
    js = os.path.join(d, "leaf.json")
    p = run(["render", CORNELL, "-o", os.path.join(d, "leaf.exr"), "--json", js, "--leaf-size", "8"] + COMMON)
    check(p.returncode == 0 and json.load(open(js))["estimator"]["leaf_size"] == 8, "--leaf-size 8: leaf_size 8")
    # The sequence path: every frame names its estimator.
    seq = os.path.join(ROOT, "samples", "cornell_box_moving_light", "cornell_box_moving_light.gltf")
    js = os.path.join(d, "seq.json")
    p = run(["render", seq, "-o", os.path.join(d, "seq_#.exr"), "--frames", "0:1", "--estimator", "lbvh",
             "--json", js] + COMMON)
    check(p.returncode == 0, "sequence --estimator lbvh exits 0")
    if p.returncode == 0:
        frames = json.load(open(js))["frames"]
        check(len(frames) == 2 and all(f.get("estimator", {}).get("name") == "lbvh" and
                                       f["estimator"].get("t_auto", 0) >= 1 for f in frames),
              "sequence: estimator.name lbvh with its statistics in each of %d frames" % len(frames))
    # Refused before any device work: a name that is none, and every kind
    # this binary was built without.
    for name in ["bogus"] + [k for k in ("knn", "splat", "vsch") if k not in built]:
        p = subprocess.run([EXE, "render", CORNELL, "-o", os.path.join(d, "no.exr"), "--estimator", name],
                           capture_output=True, text=True)
        lines = [l for l in p.stderr.splitlines() if l.strip()]
        want = "not built" if name != "bogus" else "estimator"
        check(p.returncode == 2 and len(lines) >= 1 and want in lines[0] and name in lines[0] and
              not os.path.exists(os.path.join(d, "no.exr")),
              "--estimator %s: exit %d, '%s'" % (name, p.returncode, lines[0] if lines else ""))


def part_knn():
    """kNN from the command line: --knn-k reaches the estimator (its k in
    --json, k_PD = k where r_max allows), the pixels near the LBVH gather's
    (mean within 3 % at this small budget), a sequence with the temporal
    filter on top (finite, every frame names knn), --knn-k refused without
    --estimator knn."""
    d = fresh("knn")
    outs = {}
    for name, extra in [("lbvh", []), ("knn", ["--estimator", "knn", "--knn-k", "32"])]:
        out, js = os.path.join(d, name + ".exr"), os.path.join(d, name + ".json")
        p = run(["render", CORNELL, "-o", out, "--json", js, "--width", "32", "--spp", "4", "--iterations", "4",
                 "--photons", "32768", "--seed", "3", "-q"] + extra)
        check(p.returncode == 0, "render %s exits 0" % name)
        if p.returncode == 0:
            outs[name] = (exr(out), json.load(open(js)))
    if len(outs) == 2:
        j = outs["knn"][1]
        e = j.get("estimator", {})
        check(e.get("name") == "knn" and e.get("k") == 32 and e.get("t_auto", 0) >= 1,
              "knn: --json estimator %s, k %s, the LBVH build's t_auto %s" % (e.get("name"), e.get("k"),
                                                                             e.get("t_auto")))
        check(30 <= j["photons"]["k_pd"] <= 32, "knn: k_PD %.2f (k 32 where r_max allows)" % j["photons"]["k_pd"])
        check(j["guarded"]["nonfinite_values"] == 0, "knn: no non-finite values")
        m = [sum(sum(outs[n][0]["indirect." + c]) for c in "RGB") for n in ("knn", "lbvh")]
        check(abs(m[0] / m[1] - 1) < 0.03, "knn: mean indirect %+.2f %% of the LBVH gather's" % (100 * (m[0] / m[1] - 1)))
    seq = os.path.join(ROOT, "samples", "cornell_box_moving_light", "cornell_box_moving_light.gltf")
    js = os.path.join(d, "seq.json")
    p = run(["render", seq, "-o", os.path.join(d, "seq_#.exr"), "--frames", "0:2", "--estimator", "knn",
             "--json", js] + COMMON)
    check(p.returncode == 0, "sequence --estimator knn (temporal filter, A-Trous) exits 0")
    if p.returncode == 0:
        frames = json.load(open(js))["frames"]
        check(len(frames) == 3 and all(f.get("estimator", {}).get("name") == "knn" for f in frames),
              "sequence: estimator.name knn in each of %d frames" % len(frames))
        for f in range(3):
            img = exr(os.path.join(d, "seq_%d.exr" % f))
            bad = sum(1 for ch in img.values() for v in ch if not isinstance(v, (int, float)) or v != v)
            ind = sum(sum(img["indirect." + c]) for c in "RGB")
            check(bad == 0 and ind > 0, "sequence frame %d: finite (%d bad), indirect %.4g" % (f, bad, ind))
    p = subprocess.run([EXE, "render", CORNELL, "-o", os.path.join(d, "no.exr"), "--knn-k", "8"],
                       capture_output=True, text=True)
    check(p.returncode == 2 and "--knn-k needs --estimator knn" in p.stderr,
          "--knn-k without --estimator knn: exit %d" % p.returncode)


def part_knn_spot():
    """kNN at the default k = 64 on spot_room (crate and ball lit by a spot):
    on llvmpipe the search used to run past the gallivm
    loop limiter (65535 back edges per SIMD vector, all loops together;
    shaders/estimate/knn.comp SC_BUDGET) and left pixels black where the LBVH gather
    is lit. No such pixel may be 0 in kNN, and the mean indirect + caustic
    light must be within 5 % of the gather's (measured: within ~1 %)."""
    d = fresh("knn_spot")
    scene = os.path.join(ROOT, "samples", "spot_room", "spot_room.gltf")
    imgs = {}
    for name, extra in [("lbvh", []), ("knn", ["--estimator", "knn", "--knn-k", "64"])]:
        out = os.path.join(d, name + ".exr")
        p = run(["render", scene, "-o", out, "--width", "96", "--height", "72", "--spp", "1", "--iterations", "2",
                 "--photons", "65536", "--seed", "7", "-q"] + extra)
        check(p.returncode == 0, "spot_room %s exits 0" % name)
        if p.returncode != 0:
            return
        img = exr(out)
        imgs[name] = [sum(img[l + "." + c][i] for l in ("indirect", "caustic") for c in "RGB")
                      for i in range(len(img["indirect.R"]))]
    g, k = imgs["lbvh"], imgs["knn"]
    peak = max(g)
    floor = 1e-4 * peak  # the gather's noise floor: 1e-4 of its brightest pixel
    lit = [i for i, v in enumerate(g) if v > 10 * floor]
    black = [i for i in lit if not k[i] > 0.0]
    check(len(lit) > len(g) // 4, "spot_room: %d of %d pixels lit by the gather" % (len(lit), len(g)))
    check(len(black) == 0, "spot_room: %d of the %d gather-lit pixels black in kNN at k = 64" % (len(black), len(lit)))
    mk, mg = sum(k) / len(k), sum(g) / len(g)
    check(abs(mk / mg - 1) < 0.05, "spot_room: kNN mean indirect %+.2f %% of the LBVH gather's" % (100 * (mk / mg - 1)))


ESTIMATORS = [("knn", ["--estimator", "knn"]), ("splat", ["--estimator", "splat"]), ("vsch", ["--estimator", "vsch"]),
              ("vsch directional", ["--estimator", "vsch", "--vsch-directional"])]


def light_sum(img, layers=("beauty",)):
    """Per pixel R + G + B summed over `layers` ("beauty" is the RGBA layer:
    channels R, G, B)."""
    n = len(img["R"]) if "R" in img else len(img["beauty.R"])
    out = [0.0] * n
    for l in layers:
        for c in "RGB":
            ch = img[c] if l == "beauty" and c in img else img[l + "." + c]
            for i in range(n):
                out[i] += ch[i]
    return out


def finite(vals):
    return all(math.isfinite(v) for v in vals)


def part_samples():
    """Every estimator renders every sample ("all four estimators
    render every sample"): samples/*/NAME.gltf at 32 px, 2 maps of 8192
    paths, 2 spp: exit 0, every pixel finite, and the mean indirect + caustic
    light within 35 % of the LBVH gather's on the same maps (a bound for
    gross failures -- black, doubled or leaking estimates -- at this tiny
    budget, not the estimators' agreement, which test_gpu_knn / _splat /
    _vsch and the benchmark measure; measured: within 4 % on the Cornell
    boxes and spot_room, except splat -18 % on cornell_caustics; -11 to
    -22 % on sun_atrium). Where the map holds fewer than 500 photons (ring
    here: 42) the estimators' bandwidths differ by design (kNN's r_max bound
    on k = 64 photons, the gather's footprints), so only "lit" is asked:
    mean > 0."""
    d = fresh("samples")
    scenes = sorted(glob.glob(os.path.join(ROOT, "samples", "*", "*.gltf")))
    scenes = [x for x in scenes if os.path.basename(os.path.dirname(x)) + ".gltf" == os.path.basename(x)]
    check(len(scenes) >= 6, "%d sample scenes found" % len(scenes))
    for scene in scenes:
        name = os.path.basename(scene)[:-5]
        means = {}
        for est, extra in [("lbvh", ["--estimator", "lbvh"])] + ESTIMATORS:
            out = os.path.join(d, "%s_%s.exr" % (name, est.replace(" ", "_")))
            js = out[:-4] + ".json"
            p = run(["render", scene, "-o", out, "--width", "32", "--spp", "2", "--iterations", "2",
                     "--photons", "8192", "--seed", "3", "-q", "--json", js] + extra)
            check(p.returncode == 0, "%s %s exits 0" % (name, est))
            if p.returncode != 0:
                continue
            stored = json.load(open(js))["photons"]["stored"]
            img = exr(out)
            beauty, ind = light_sum(img), light_sum(img, ("indirect", "caustic"))
            check(finite(beauty) and finite(ind), "%s %s: every pixel finite" % (name, est))
            means[est] = sum(ind) / len(ind)
        base = means.get("lbvh")
        for est, m in sorted(means.items()):
            if est == "lbvh" or base is None:
                continue
            rel = m / base - 1 if base > 0 else (0.0 if m == 0 else float("inf"))
            if stored < 500:
                check(m > 0 and base > 0, "%s %s: lit (mean indirect %.4g, the gather's %.4g; %d photons stored)" %
                      (name, est, m, base, stored))
                continue
            check(abs(rel) <= 0.35, "%s %s: mean indirect %+.1f %% of the gather's (%.4g)" % (name, est, 100 * rel, base))


def box_gltf(path, albedo, light_pos, intensity_cd):
    """A closed cube [-1, 1]^3, its 12 triangles facing inwards, one diffuse
    material of `albedo`, a point light inside and a camera at the centre
    looking at a corner (wide field of view): every pixel sees a wall."""
    pos, nrm, idx = [], [], []
    for axis in range(3):
        for sgn in (-1.0, 1.0):
            n = [0.0, 0.0, 0.0]
            n[axis] = -sgn  # inwards
            u, v = (axis + 1) % 3, (axis + 2) % 3
            base = len(pos)
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                q = [0.0, 0.0, 0.0]
                q[axis], q[u], q[v] = sgn, a, b
                pos.append(q)
                nrm.append(n)
            quad = [base, base + 1, base + 2, base, base + 2, base + 3]
            # Winding: counter-clockwise seen from inside (the normal's side).
            if sgn > 0:
                quad = [base, base + 2, base + 1, base, base + 3, base + 2]
            idx += quad
    blob = b"".join(struct.pack("<3f", *q) for q in pos) + b"".join(struct.pack("<3f", *q) for q in nrm)
    blob += b"".join(struct.pack("<H", i) for i in idx)
    nv = len(pos)
    doc = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "color": [1, 1, 1],
                                                           "intensity": intensity_cd}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"mesh": 0, "name": "Box"},
                  {"translation": light_pos, "extensions": {"KHR_lights_punctual": {"light": 0}}, "name": "Light"},
                  # Looking along (-1, -1, -1) / sqrt 3 from the centre.
                  {"camera": 0, "name": "Camera", "translation": [0.0, 0.0, 0.0],
                   "rotation": [-0.2798481, 0.3647052, 0.1159169, 0.8804762]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 1.6, "aspectRatio": 1.0, "znear": 0.01}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"name": "wall", "pbrMetallicRoughness": {"baseColorFactor": [albedo, albedo, albedo, 1.0],
                                                                 "metallicFactor": 0.0, "roughnessFactor": 1.0},
                       "doubleSided": True}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 12 * nv},
                        {"buffer": 0, "byteOffset": 12 * nv, "byteLength": 12 * nv},
                        {"buffer": 0, "byteOffset": 24 * nv, "byteLength": 2 * len(idx)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3",
                       "min": [-1, -1, -1], "max": [1, 1, 1]},
                      {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC3"},
                      {"bufferView": 2, "componentType": 5123, "count": len(idx), "type": "SCALAR"}],
    }
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def part_furnace():
    """A closed furnace ("a closed furnace scene conserving
    stored flux"): a cube of diffuse walls of albedo 0.6 around a point light,
    the camera inside. Nothing escapes, so the light on the walls is the
    light's flux reflected again and again (the indirect share is
    rho / (1 - rho) of the direct in the mean over the walls); each
    estimator's mean indirect light over the image, the same photon maps,
    must match the reference path tracer's: lbvh, knn and vsch within 1.5 %
    (measured -0.7 to -0.9 %, -0.3 % for the gather at 4x the photons: the
    kernels' bias; before the photon tracer's adjoint fix +2.2 to +2.3 %), splat within 5 % (-3.0 %), the directional variant of
    the view-sample hierarchy within 20 % (-13.2 %: its octant buckets
    spread a photon over a cluster's box by the product of three axes'
    coverage, which for walls oblique to the view axes counts less than the
    wall's covered area; seed 004 4.7's heuristic, not fixed here); the
    direct light the reference's within 2 %. This caught the photon
    tracer's non-adjoint glTF BSDF (+2.2 % for every estimator, +2.9 % at
    4x the photons, before the fix in photon_trace.comp)."""
    d = fresh("furnace")
    scene = box_gltf(os.path.join(d, "box.gltf"), 0.6, [0.3, -0.2, 0.25], 5.0)
    ref = os.path.join(d, "ref.exr")
    p = run(["reference", scene, "-o", ref, "--width", "48", "--spp", "256", "--seed", "2", "-q"])
    check(p.returncode == 0, "furnace reference exits 0")
    if p.returncode != 0:
        return
    r = exr(ref)
    r_ind, r_dir = light_sum(r, ("indirect",)), light_sum(r, ("direct",))
    m_ind, m_dir = sum(r_ind) / len(r_ind), sum(r_dir) / len(r_dir)
    check(m_ind > 0.5 * m_dir, "furnace reference: indirect %.4g against direct %.4g (a furnace: indirect "
                               "comparable)" % (m_ind, m_dir))
    for est, extra in [("lbvh", ["--estimator", "lbvh"])] + ESTIMATORS:
        out = os.path.join(d, est.replace(" ", "_") + ".exr")
        p = run(["render", scene, "-o", out, "--width", "48", "--spp", "8", "--iterations", "4",
                 "--photons", "65536", "--seed", "2", "-q"] + extra)
        check(p.returncode == 0, "furnace %s exits 0" % est)
        if p.returncode != 0:
            continue
        g = exr(out)
        g_ind = light_sum(g, ("indirect", "caustic"))
        g_dir = light_sum(g, ("direct",))
        gi, gd = sum(g_ind) / len(g_ind), sum(g_dir) / len(g_dir)
        check(finite(g_ind), "furnace %s: every pixel finite" % est)
        bound = {"splat": 0.05, "vsch directional": 0.20}.get(est, 0.015)
        check(abs(gi / m_ind - 1) <= bound, "furnace %s: mean indirect %.5g, reference %.5g (%+.2f %%, bound %g %%)" %
              (est, gi, m_ind, 100 * (gi / m_ind - 1), 100 * bound))
        check(abs(gd / m_dir - 1) <= 0.02, "furnace %s: mean direct %.5g, reference %.5g (%+.2f %%)" %
              (est, gd, m_dir, 100 * (gd / m_dir - 1)))


if subprocess.run([EXE, "info", "--devices"], capture_output=True, text=True).returncode != 0:
    print("skip: no Vulkan device")
    sys.exit(77)
for part in PARTS:
    globals()["part_" + part]()
if failures:
    print("%d failed" % len(failures))
    sys.exit(1)
print("all passed")
