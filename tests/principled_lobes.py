#!/usr/bin/env python3
"""Each Principled lobe alone, Blender's Diffuse BSDF, the rough glass, the
white furnace and the studio (tests/data/principled, made by
exporters/blender/make_principled_tests.py) rendered by photonbridge and
compared with the committed Cycles 3.4 render of the same .blend scene:

  mean   |mean(photonbridge) / mean(Cycles) - 1| <= 1 %  (all pixels, RGB)
  PSNR   >= 35 dB on the display image (photonbridge compare, built-in sRGB
         view); on the studio (full global illumination) the goals:
         the reference >= 38 dB, the GPU >= 30 dB

usage: principled_lobes.py PHOTONBRIDGE EXR_PROBE WORKDIR --renderer ref|gpu
           [--only NAME] [--spp N] [--table FILE.md]
           [--data DIR --psnr DB --mean-tol FRACTION] [--validate LABEL]...
--data tests/data/principled2 runs the Principled v2 scenes (Blender 4.x,
exporters/blender/make_principled2_tests.py) against their Cycles 4.x
renders, with the given thresholds.
--validate LABEL (repeatable, --renderer gpu): that case (a scene's name, or
NAME@R1 for its followed-glossy render) runs with --validation, every other
case with PB_VK_VALIDATION=0. Without --validate each render inherits the
environment. The GPU's cases run as one `photonbridge batch`. On lavapipe the layers cost about 2 s of CPU a process on
these materials (checking the large shader modules; more under load) and a
little more each sample (each submission checked), whatever the picture, so
a few scenes with every pass and specialization the lobes use carry the API
coverage, and the rest of the run measures only the pictures.
Exit 77 for --renderer gpu when no Vulkan device is present. Cycles' own
noise per scene is in tests/data/principled/cycles.json (every scene is far
below these thresholds: 46-139 dB, the studio 62-63 dB)."""
import json
import os
import shlex
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "data", "principled")
MEAN_TOL = 0.01
PSNR_MIN = 35.0
STUDIO = ("studio", "studio_multi")
PSNR_MIN_STUDIO = {"ref": 38.0, "gpu": 30.0}
# Scenes whose fault shows in fewer dB than the default threshold gives:
# 3.4's clearcoat over a normal map on Normal only, with the mapped normal
# for the coat (not Cycles' sd->N), gives 40.1 dB on the reference, and with
# the map on Clearcoat Normal ignored 39.8 dB (51.3 dB both when right).
PSNR_MIN_SCENE = {"ref": {"clearcoat_over_normal_map": 45.0, "clearcoat_normal_map": 45.0}, "gpu": {}}

# Samples per pixel for each renderer. Few photons: a convex sphere in a
# black world gets no indirect light (the furnace's and the glass's
# emitters are reached by the GPU's light samples and eye paths).
SPP = {"ref": 64, "gpu": 64}
# More samples where the noise needs them: the rough glass refracts an
# emitter; the GPU lights diffuse lobes from emitters by light sampling
# alone (the furnace: a uniform world); the sheen is a thin rim whose mean
# is its few silhouette pixels' anti-aliasing; the emission under a coat of
# roughness 0.05 reflects a point light in a highlight of a few pixels
# (the GPU's mean: -0.4 % at 256 spp, +1.1 % at 64, +0.09 % at 1024).
# The GPU renders the glasses and the coated emission at half the
# reference's counts: over seeds 0, 1, 2 (lavapipe, 2026-12-06) every seed stays far
# inside both thresholds, the mean error 4 sd (over the three) or more
# inside its tolerance:
#   glass 256         PSNR 38.8 / 39.8 / 39.0 dB (>= 35), mean +0.14 / -0.10 / -0.06 % (sd 0.12)
#   glass_ggx 256     PSNR 40.6 / 41.1 / 40.9 dB (>= 36), mean +0.01 / -0.08 / -0.12 % (sd 0.06)
#   glass_multi 256   PSNR 39.0 / 39.2 / 39.2 dB (>= 36), mean -0.42 / -0.46 / -0.39 % (sd 0.04)
#   emission_coat 512 PSNR 54.7 / 54.8 / 50.0 dB (>= 36), mean -0.34 / -0.37 / -0.13 % (sd 0.13)
# The thin film on glass (lavapipe, 2026-12-07, seed 0): the reference 42.9
# dB at 1024 spp (40.9 at 512, too close to 40), the GPU 39.3 dB at 256
# (36.9 at 128); Cycles' own render of it is 4096 spp (51.0 dB).
# At half their counts the others lose the margin (seed 0): the furnace at
# 128 spp 35.4 dB (>= 35), the v2 sheen's mean -1.2 % and sheen_bsdf's
# -1.6 % (the rim's few pixels), so those stay at 256.
# The Glass and Refraction BSDFs (lavapipe, 2026-12-07, seed 0): the
# reference 46.4 / 42.5 / 43.5 dB (glass_bsdf_ggx / _multi, glass_beckmann)
# at 512 spp (39.7 / 34.5 / 36.1 at 64), refraction_bsdf and
# refraction_beckmann 40.6 and 39.4 at 64, so 256; the GPU glass_bsdf_multi
# and glass_beckmann 34.6 and 36.3 dB at 64, so 256 as glass_multi,
# glass_bsdf_ggx, refraction_bsdf and refraction_beckmann 40.2, 40.6 and
# 39.7 at 64. Blender 3.4's Glass BSDF (Cycles 3.4.1): 34.0 (reference) and
# 33.7 dB (GPU) at 64 spp, so 512 and 256 as the Principled glass (41.6 and
# 39.1 dB).
SPP_SCENE = {"ref": {"glass": 512, "studio": 256, "studio_multi": 256, "glass_ggx": 512, "glass_multi": 512,
                     "thin_film_glass": 1024, "emission_coat": 1024, "glass_bsdf_ggx": 512,
                     "glass_bsdf_multi": 512, "glass_beckmann": 512, "refraction_bsdf": 256,
                     "refraction_beckmann": 256, "glass34_ggx": 512},
             "gpu": {"glass": 256, "glass_ggx": 256, "glass_multi": 256, "glass_bsdf_multi": 256, "glass_beckmann": 256,
                     "glass34_ggx": 256, "thin_film_glass": 256, "furnace": 256, "sheen": 256, "sheen_bsdf": 256, "studio": 16, "studio_multi": 16,
                     "emission_coat": 512}}
# The GPU's photon options: 2^14 paths, one map, except on the studio, whose
# indirect light is the photon map's: 2^18 paths x 16 progressive maps at
# 16 spp (the Blender render engine's defaults until they followed the
# CLI's; measured 41.0 / 40.5 dB, mean -0.30 / -0.63 %, 17 s of CPU on
# lavapipe; fewer photons leave the mean up to 0.9 % low on studio_multi:
# bench/README.md).
ENGINE = ["--photons", "262144", "--iterations", "16", "--progressive"]
GPU_OPTS = {"studio": ENGINE, "studio_multi": ENGINE}
# The GPU renders these again with every glossy layer followed by the eye
# path (--glossy-path-roughness 1; by default layers rougher than 0.15 are
# shaded where the eye path stops, from direct light and the photon map):
# both ways must match Cycles.
FOLLOWED = ["specular_ggx_r02", "specular_multi_r05", "thin_film_diffuse", "metal_aniso", "metallic_f82_multi_aniso",
            "glossy_multi_aniso", "clearcoat", "studio"]


def probe(exe, path):
    p = subprocess.run([exe, path], capture_output=True, text=True)
    if p.returncode:
        raise RuntimeError("exr_probe %s: %s" % (path, p.stderr.strip()))
    ch = json.loads(p.stdout)["channels"]
    return [ch["R"], ch["G"], ch["B"]]


def mean(img):
    return sum(sum(c) for c in img) / sum(len(c) for c in img)


def main(argv):
    exe, probe_exe, work = argv[0], argv[1], argv[2]
    rest = argv[3:]
    renderer, only, spp, table, validate = "ref", [], None, None, []
    global DATA, MEAN_TOL, PSNR_MIN
    while rest:
        a = rest.pop(0)
        if a == "--data":
            DATA = os.path.abspath(rest.pop(0))
            continue
        if a == "--psnr":
            PSNR_MIN = float(rest.pop(0))
            continue
        if a == "--mean-tol":
            MEAN_TOL = float(rest.pop(0))
            continue
        if a == "--renderer":
            renderer = rest.pop(0)
        elif a == "--only":
            only.append(rest.pop(0))
        elif a == "--spp":
            spp = int(rest.pop(0))
        elif a == "--table":
            table = rest.pop(0)
        elif a == "--validate":
            validate.append(rest.pop(0))
    spp_all = spp
    if renderer == "gpu":
        if subprocess.run([exe, "info", "--devices"], capture_output=True).returncode:
            print("skip: no Vulkan device")
            return 77
    with open(os.path.join(DATA, "cycles.json")) as f:
        cyc = json.load(f)
    os.makedirs(work, exist_ok=True)
    names = [n for n in sorted(cyc) if not only or n in only]
    unknown = [v for v in validate if v.split("@")[0] not in cyc]
    if unknown:
        print("FAIL --validate names no scene of %s: %s" % (DATA, unknown))
        return 1
    # (label, scene, extra render options)
    cases = [(n, n, []) for n in names]
    if renderer == "gpu":
        cases += [(n + "@R1", n, ["--glossy-path-roughness", "1"]) for n in names if n in FOLLOWED]
    failed = 0
    rows = []
    # The GPU renders every case as one `photonbridge batch` (the device and
    # its compiled pipelines shared: scenes of one closure set create their
    # pipelines once); a validated case's job adds --validation (a device of
    # its own).
    jobs = {}
    if renderer == "gpu":
        lines = []
        for label, name, extra in cases:
            scene = os.path.join(DATA, name, name + ".gltf")
            out = os.path.join(work, "%s_%s.exr" % (label, renderer))
            spp = spp_all or SPP_SCENE[renderer].get(name, SPP[renderer])
            cmd = ["render", scene, "-o", out, "--width", str(cyc[name]["width"]), "--spp", str(spp), "-q"]
            cmd += GPU_OPTS.get(name, ["--photons", "16384"]) + extra
            if label in validate:
                cmd.append("--validation")
            lines.append(" ".join(shlex.quote(c) for c in cmd))
        jobs_path = os.path.join(work, "jobs.txt")
        with open(jobs_path, "w") as f:
            f.write("\n".join(lines) + "\n")
        env = dict(os.environ, PB_VK_VALIDATION="0") if validate else None
        p = subprocess.run([exe, "batch", jobs_path], capture_output=True, text=True, env=env)
        done = [json.loads(l) for l in p.stdout.splitlines() if l.startswith("{")]
        for (label, _, _), d in zip(cases, done):
            jobs[label] = d
        made = sum(d["pipelines_created"] for d in done)
        taken = sum(d["pipelines_reused"] for d in done)
        print("batch: %d of %d jobs reported, %d pipelines created, %d from the cache, %.0f s" % (
            len(done), len(cases), made, taken, sum(d["wall_ms"] for d in done) / 1e3))
        if p.returncode:
            print("batch exited %d: %s" % (p.returncode, p.stderr.strip()[-4000:]))
    for label, name, extra in cases:
        scene = os.path.join(DATA, name, name + ".gltf")
        ref = os.path.join(DATA, name, "cycles.exr")
        out = os.path.join(work, "%s_%s.exr" % (label, renderer))
        w = str(cyc[name]["width"])
        spp = spp_all or SPP_SCENE[renderer].get(name, SPP[renderer])
        if renderer == "ref":
            cmd = [exe, "reference", scene, "-o", out, "--width", w, "--spp", str(spp), "-q"]
            if name in STUDIO:
                cmd += ["--max-bounces", "64"]  # as Cycles' render (the lobes' paths end sooner)
            p = subprocess.run(cmd, capture_output=True, text=True)
            if p.returncode:
                print("FAIL %s: %s exited %d: %s" % (label, renderer, p.returncode, p.stderr.strip()))
                failed += 1
                continue
        elif label not in jobs or jobs[label]["exit"]:
            print("FAIL %s: gpu job %s" % (label, "exited %d" % jobs[label]["exit"] if label in jobs else "not run"))
            failed += 1
            continue
        js = os.path.join(work, "%s_%s.json" % (label, renderer))
        p = subprocess.run([exe, "compare", out, ref, "--json", js, "-q"], capture_output=True, text=True)
        if p.returncode:
            print("FAIL %s: compare exited %d: %s" % (label, p.returncode, p.stderr.strip()))
            failed += 1
            continue
        psnr = json.load(open(js))["psnr_db"]
        psnr = 200.0 if psnr is None else psnr
        ma, mb = mean(probe(probe_exe, out)), mean(probe(probe_exe, ref))
        dm = ma / mb - 1.0 if mb > 0 else 0.0
        psnr_min = PSNR_MIN_STUDIO[renderer] if name in STUDIO else PSNR_MIN_SCENE[renderer].get(name, PSNR_MIN)
        ok = abs(dm) <= MEAN_TOL and psnr >= psnr_min
        failed += not ok
        rows.append((label, psnr, dm, cyc[name]["noise_psnr_db"]))
        print("%s %-22s %s %3d spp%s: PSNR %6.2f dB, mean %+.3f %% (photonbridge %.5f, Cycles %.5f; Cycles' noise %.1f dB)" % (
            "ok  " if ok else "FAIL", label, renderer, spp, ", validated" if label in validate else "", psnr, 100 * dm, ma, mb, cyc[name]["noise_psnr_db"]))
    if table:
        with open(table, "w") as f:
            f.write("| scene | PSNR | mean | Cycles' noise |\n|---|---:|---:|---:|\n")
            for name, psnr, dm, noise in rows:
                f.write("| %s | %.2f dB | %+.3f %% | %.1f dB |\n" % (name, psnr, 100 * dm, noise))
    print("%d passed, %d failed" % (len(cases) - failed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
