#!/usr/bin/env python3
"""Cross-renderer validation report for one scene.

    python3 validation/validate.py SCENE --out DIR --exe build/photonbridge \
        [--width 128] [--spp 16] [--ref-spp 64] [--pov-quality medium] \
        [--cycles-spp 64] [--cycles-source auto|sample|gltf] [--cycles-materials model|principled] \
        [--no-cycles] [--no-gpu] [--no-povray] [--threads N] \
        [--direct-only] [--ocio-config F] [--display D] [--view V] [--look L] \
        [--renderers LIST] [--render-only | --report-from DIR[,DIR...]] [-q]

`photonbridge validate` runs this script. SCENE is a glTF/GLB file, a .blend,
or the name of a sample (samples/NAME/NAME.gltf). A .blend is handed over by
the Blender render engine's writer (exporters/blender/export_photonbridge.py,
the same as F12: its glTF and the PHOTONBRIDGE_blender extension, into
DIR/handoff/), which the photonbridge renderers and POV-Ray render, while
Cycles renders the .blend itself as the artist set it up. Renders, all at the
same width (the height follows the camera's aspect in every renderer):

  reference     photonbridge reference (CPU, Embree): PT, SPPM when the scene
                has caustics; --estimate-noise gives its own noise
  photonbridge  photonbridge render (GPU pipeline)
  povray        photonbridge export-pov + validation/run_povray.sh
  cycles        validation/run_cycles.sh, when Blender is installed, with
                photonbridge's camera, image size and path-length limit (the
                reference's max_bounces - 1 Cycles bounces), as two
                independent halves for its own noise. The Cycles scene comes
                from one of three sources (cycles_source): a .blend is opened
                as it is (its own materials, lights and world); a sample is built by
                exporters/blender/make_samples.py with Diffuse / Glossy /
                Glass BSDFs; any other .gltf / .glb goes through Blender's glTF
                importer with every material rebuilt as glTF's metallic-
                roughness model (cycles_gltf.py). A file the importer cannot
                read leaves Cycles failed with the importer's one-line reason.

Every EXR goes through `photonbridge display` with the same OCIO options, and
every pair through `photonbridge compare --json --heatmap` (the shared
src/metrics code; the earlier renderer of the list above is the pair's
reference). Writes DIR/index.html (images side by side, heat maps, metric
table, times, settings, tool versions) and DIR/report.json (the same numbers).
Every pair's row also lists what its two renderers model differently on this
scene (renderer_notes: a feature one side lacks, a material model, bounce
limits; from photonbridge info, the glTF's JSON and each renderer's own
report), so that a modelling difference is not read as an error.
Split by renderer (a farm's one task per scene and renderer):
`--renderers R --render-only` runs only R and writes its record as
DIR/render_R.json beside its image and logs; `--report-from DIR1,DIR2,...`
renders nothing, copies those folders into --out and compares and reports
as one process would (a renderer no folder has is listed as not rendered).

Before the first render, one stderr line estimates the run's time and what
dominates it (estimate_run: the reference and photonbridge render measured on
small probes in DIR/estimate/ and extrapolated by pixels x samples, POV-Ray and
Cycles modelled from the reference probe's speed); report.json's estimate holds
it. -q prints errors only (no progress, no estimate, no status lines).

A renderer that is missing or fails is listed with the reason and left out of
the comparisons; the exit status is 0 when the reference and at least one
other renderer produced an image, 1 otherwise, 2 on usage errors.

Only the Python standard library is used.
"""
import argparse
import html
import json
import math
import os
import shlex
import shutil
import signal
import struct
import subprocess
import sys
import time

import gltf_json

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
ORDER = ["reference", "cycles", "cycles45", "luxcore", "mitsuba", "povray", "photonbridge"]
RUN_ORDER = ["reference", "photonbridge", "povray", "luxcore", "mitsuba", "cycles", "cycles45"]  # as they run
DEFAULT_RENDERERS = ["reference", "photonbridge", "povray", "cycles"]  # the others when asked (--renderers)
LABEL = {"reference": "photonbridge reference (CPU)", "photonbridge": "photonbridge render (GPU)",
         "povray": "POV-Ray 3.7", "cycles": "Blender Cycles", "cycles45": "Blender Cycles 4.5 (bpy)",
         "luxcore": "LuxCoreRender (PATHCPU)",
         "mitsuba": "Mitsuba 3 (path)"}
# The peers' interpreters (scripts/install-deps.sh: pyluxcore and mitsuba in
# their own venvs), and the environment variables that name others.
PEER_PYTHON = {"luxcore": ("PB_LUXCORE_PYTHON", os.path.join(ROOT, "tools", "luxcore", "bin", "python")),
               "mitsuba": ("PB_MITSUBA_PYTHON", os.path.join(ROOT, "tools", "mitsuba3", "bin", "python"))}
# NVIDIA FLIP (flip-evaluator in tools/flip; PB_FLIP_PYTHON names another
# interpreter): each pair's HDR-FLIP and its error map (flip_mean.py).
FLIP_PYTHON = ("PB_FLIP_PYTHON", os.path.join(ROOT, "tools", "flip", "bin", "python"))
PEER_PER_SAMPLE = {"luxcore": 1.0, "mitsuba": 2.0}  # reference pixel-samples per peer sample (modelled)
PEER_START_S = 3.0


def peer_python(name):
    env, default = PEER_PYTHON[name]
    return os.environ.get(env) or default


def photonbridge_label(st):
    """The page's name for photonbridge render, from its --json statistics:
    the device it ran on, and said plainly when that is a CPU Vulkan device
    (lavapipe) rather than a GPU."""
    name = st.get("device") if isinstance(st.get("device"), str) else None
    if not name:
        return LABEL["photonbridge"]
    if st.get("device_type") == "cpu":
        return "photonbridge render: GPU pipeline on %s (CPU Vulkan device)" % name
    return "photonbridge render: GPU pipeline on %s" % name


def run(cmd, log=None, cwd=None, timeout=1800, env=None):
    t0 = time.time()
    try:
        p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           timeout=timeout, universal_newlines=True, env=env)
        rc, out = p.returncode, p.stdout
    except FileNotFoundError as e:
        rc, out = 127, str(e)
    except subprocess.TimeoutExpired:
        rc, out = 124, "timed out after %d s" % timeout
    dt = time.time() - t0
    if log:
        with open(log, "w") as f:
            f.write("$ " + " ".join(cmd) + "\n" + out + "\nexit=%d wall_s=%.3f\n" % (rc, dt))
    return rc, out, dt


def tool_version(cmd, match=None):
    rc, out, _ = run(cmd, timeout=120)
    lines = [l.strip() for l in out.splitlines() if l.strip() and (not match or match in l)]
    if rc != 0 or not lines:
        return None
    return lines[0]


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def resolve_scene(scene):
    if os.path.isfile(scene):
        path = os.path.abspath(scene)
    else:
        path = os.path.join(ROOT, "samples", scene, scene + ".gltf")
        if not os.path.isfile(path):
            return None, None
    name = os.path.splitext(os.path.basename(path))[0]
    sample = name if os.path.abspath(os.path.join(ROOT, "samples", name, name + ".gltf")) == path else None
    return path, sample


def blend_handoff(blend, out):
    """The render engine's hand-off of a .blend (exporters/blender/
    export_photonbridge.py: the same writer as F12) into OUT/handoff/.
    Returns (gltf path, report dict) or (None, one-line reason)."""
    bl = os.environ.get("BLENDER", "blender")
    if not shutil.which(bl):
        return None, "blender not installed (a .blend needs Blender's render engine hand-off)"
    hdir = os.path.join(out, "handoff")
    os.makedirs(hdir, exist_ok=True)
    gltf = os.path.join(hdir, os.path.splitext(os.path.basename(blend))[0] + ".gltf")
    js = os.path.join(hdir, "handoff.json")
    env = dict(os.environ)
    env["PATH"] = ":".join(p for p in env.get("PATH", "").split(":") if "pyenv" not in p)
    cmd = [bl, "-b", blend, "--factory-startup", "--python-exit-code", "1", "-P",
           os.path.join(ROOT, "exporters", "blender", "export_photonbridge.py"), "--", gltf, "--json", js]
    t0 = time.time()
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                           timeout=1800, env=env)
        rc, o = p.returncode, p.stdout
    except subprocess.TimeoutExpired:
        rc, o = 124, "timed out"
    with open(os.path.join(out, "handoff.log"), "w") as f:
        f.write("$ " + " ".join(cmd) + "\n" + o + "\nexit=%d wall_s=%.3f\n" % (rc, time.time() - t0))
    rep = read_json(js)
    if rc != 0 or not os.path.isfile(gltf) or rep is None:
        lines = [l for l in o.splitlines() if "rror" in l] or o.strip().splitlines()[-1:] or ["no output"]
        return None, "the render engine's hand-off of %s failed (exit %d): %s" % (blend, rc, lines[-1][-300:])
    rep["command"] = cmd
    return gltf, rep


def loader_args(args):
    """The options of a --ref-args string that change what the loader reads
    (for photonbridge info)."""
    words, out = shlex.split(args), []
    for i, w in enumerate(words):
        if w == "--allow-external-files":
            out.append(w)
        elif w == "--light-units" and i + 1 < len(words):
            out += [w, words[i + 1]]
        elif w.startswith("--light-units="):
            out.append(w)
    return out


def image_size(info, width):
    """pb_camera_image_size (src/scene/scene.c) for the first camera, in
    float32 as there; used when the reference did not say its size."""
    f32 = lambda x: struct.unpack("f", struct.pack("f", x))[0]
    cams = (info or {}).get("cameras") or [{}]
    aspect = f32(cams[0].get("aspect") or 0.0)
    if not aspect > 0:
        aspect = f32(f32(4.0) / f32(3.0))
    return width, max(1, int(math.floor(f32(f32(width) / aspect) + 0.5)))


def cycles_source(a, scene, sample, blend=None):
    """Where the Cycles scene comes from, as run_cycles.sh takes it: the
    sample script for a sample, the .blend itself for a .blend (Cycles renders
    it as the artist set it up; photonbridge renders the render engine's
    hand-off of it), Blender's glTF importer for any other file. None when
    --cycles-source sample is asked of a file that is not a sample."""
    if blend:
        return {"kind": "blend", "scene": blend, "materials": "blend", "args": []}
    kind = a.cycles_source if a.cycles_source != "auto" else ("sample" if sample else "gltf")
    model = a.cycles_materials == "model"
    if kind == "sample":
        return {"kind": "sample", "scene": sample, "materials": "bsdf" if model else "principled",
                "args": []} if sample else None
    return {"kind": "gltf", "scene": scene, "materials": "gltf" if model else "principled", "args": []}


def not_runnable(a, n, scene, sample, blend):
    """Why renderer n will not run here, decided once for the time estimate
    and for the run itself: ("skipped", why) where an option turned it off,
    ("unavailable", why) where something it needs is missing, None where it
    runs."""
    if n == "photonbridge" and a.no_gpu:
        return "skipped", "--no-gpu"
    if n == "povray":
        if a.no_povray:
            return "skipped", "--no-povray"
        if not shutil.which("povray"):
            return "unavailable", "povray not installed"
    if n in PEER_PYTHON:
        if a.direct_only:
            return "skipped", "--direct-only: the peers' dumps render every bounce"
        if not os.access(peer_python(n), os.X_OK):
            return "unavailable", "%s not found (scripts/install-deps.sh installs it; or set %s)" % (
                peer_python(n), PEER_PYTHON[n][0])
    if n in ("cycles", "cycles45"):
        if a.no_cycles:
            return "skipped", "--no-cycles"
        if n == "cycles" and not shutil.which(os.environ.get("BLENDER", "blender")):
            return "unavailable", "blender not installed"
        if n == "cycles45" and bpy45_missing():
            return "unavailable", bpy45_missing()
        src = cycles_source(a, scene, sample, blend)
        if src is None:
            return "unavailable", ("--cycles-source sample: %s is not a sample built by "
                                   "exporters/blender/make_samples.py" % os.path.basename(scene))
        if n == "cycles45" and src["kind"] == "sample" and a.cycles_source != "auto":
            return "unavailable", ("--cycles-source sample: the samples' Blender script is Blender 3.4's (Cycles "
                                   "4.5 takes the glTF: --cycles-source gltf)")
    return None


def _paths(xs, n=4):
    return ", ".join(xs[:n]) + (" and %d more" % (len(xs) - n) if len(xs) > n else "")


def renderer_notes(name, r, info, facts):
    """What renderer `name` models differently from the others on this
    scene, one line each: the differences a reader must not take for errors
    (a feature one side lacks, a material model, bounce limits). info:
    photonbridge info --json; facts: gltf_json.facts of the file (None if it
    is not readable JSON)."""
    st = r.get("settings") or {}
    notes = list(r.get("notes") or [])
    mats = (info or {}).get("materials") or []
    delta = [m.get("name", "?") for m in mats if m.get("kind") in ("mirror", "glass")]
    f = facts or {}
    if name in ("reference", "photonbridge"):
        models = sorted({m.get("model") or "glTF metallic-roughness" for m in mats})
        notes.append("material model: %s%s" % (", ".join(models) or "none",
                                               " (the Blender render engine's hand-off of the .blend)"
                                               if r.get("handoff") else ""))
        notes += ["loader: " + w for w in (info or {}).get("warnings") or []]
        if f.get("alpha"):
            notes.append("alphaMode MASK / BLEND rendered opaque: " + _paths(f["alpha"]))
        if f.get("extension_textures"):
            notes.append("KHR_materials_specular / transmission textures not read (their factors are): " +
                         _paths(f["extension_textures"]))
        if f.get("rough_transmission"):
            notes.append("transmission refracted as smooth glass whatever its roughness: " +
                         _paths(f["rough_transmission"]))
    if name == "reference":
        notes.append("paths of up to %s scattering events (--max-bounces; direct light is 1)" % st.get("max_bounces"))
        if st.get("mode") == "sppm":
            notes.append("caustics (point, spot or sun light through perfect mirrors or glass) from SPPM photons")
    elif name == "photonbridge":
        notes.append("photon density estimation for indirect light and caustics: consistent but biased at a "
                     "finite photon count (%s emitted): light blurred over the gather footprint" %
                     st.get("photons_emitted"))
    elif name in ("luxcore", "mitsuba"):
        notes += ["export-peer: " + n for n in st.get("notes") or []]
        notes.append("renders photonbridge's loaded scene (export-peer): the same triangles, camera and lights, "
                     "each material as close as the peer's own models come")
    elif name == "povray":
        notes += ["export-pov " + n for n in st.get("notes") or []]
        notes.append("diffuse inter-reflection from radiosity (--quality %s), truncated at its recursion limit"
                     % st.get("quality"))
    elif name in ("cycles", "cycles45"):
        notes.insert(0, "material model: %s" % st.get("materials"))
        if "Principled" in (st.get("materials") or "") and not any(m.get("model") == "principled" for m in mats):
            notes.insert(1, "Blender's Principled BSDF is not glTF's model: Disney diffuse with retro-reflection, "
                            "and a GGX layer whose Fresnel rises to 1 at grazing angles even at Specular 0 "
                            "(cornell_box renders 16.7 % brighter than with Diffuse BSDFs)")
        notes.append("paths of up to %s bounces (Cycles counts direct light as 0: the reference's limit)"
                     % st.get("bounces"))
        if delta and (info or {}).get("lights"):
            notes.append("caustics of point, spot and sun lights through perfect mirrors or glass (%s) are "
                         "unreachable for Cycles' path tracing (a delta light seen through a delta surface); "
                         "the reference renders them from photons" % _paths(delta))
        if st.get("source") == "gltf":
            for k, what in (("texture_transform", "KHR_texture_transform"), ("texcoord1", "texCoord > 0"),
                            ("color0", "COLOR_0"), ("alpha", "alphaMode MASK / BLEND")):
                if f.get(k):
                    notes.append("%s applied as glTF says: %s" % (what, _paths(f[k])))
            if f.get("unmodelled_extensions"):
                notes.append("extensions not modelled: %s" % ", ".join(f["unmodelled_extensions"]))
    return notes


def scene_notes(facts):
    """What every renderer here leaves out of the file (no pair differs by it)."""
    f, notes = facts or {}, []
    if f.get("occlusion"):
        notes.append("occlusionTexture ignored by every renderer (path tracing computes what it approximates): " +
                     _paths(f["occlusion"]))
    if f.get("light_range"):
        notes.append("light range ignored by every renderer (inverse-square fall-off everywhere): " +
                     _paths(f["light_range"]))
    return notes


def halves_noise(exe, out, halves, color):
    """The noise of the average of two independent halves A and B, as
    photonbridge reference --estimate-noise reports its own (src/metrics:
    Var(M) = E[(A - B)^2] / 4): RMSE / 2, relMSE / 4 (over B^2 + 0.01 rather
    than M^2 + 0.01), display MSE / 4, i.e. PSNR + 6.02 dB."""
    js = os.path.join(out, "cycles_halves.json")
    rc, _, _ = run([exe, "compare", halves[0], halves[1], "--json", js, "-q"] + color,
                   os.path.join(out, "cycles_halves.log"))
    m = read_json(js) if rc == 0 else None
    if not m or not isinstance(m.get("rmse"), (int, float)):
        return None
    psnr = m.get("psnr_db")
    return {"rmse": m["rmse"] / 2, "relmse": m["relmse"] / 4,
            "psnr_db": psnr + 10 * math.log10(4) if isinstance(psnr, (int, float)) else None,
            "method": "two independent halves (hashed seeds): Var(mean) = E[(A-B)^2]/4"}


CREATED = None  # the output folder, when this run created it (removed if interrupted)
QUIET = False  # -q: errors only (no progress, no estimate, no status lines)


class Terminated(Exception):
    pass


def progress(what):
    """One stderr line as each renderer starts (progress goes to stderr)."""
    if not QUIET:
        print("validate: %s ..." % what, file=sys.stderr, flush=True)


def write_atomic(path, text):
    tmp = "%s.tmp.%d" % (path, os.getpid())
    try:
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def reference_cmd(a, exe, scene, exr, js, width, spp):
    """photonbridge reference as validate runs it (the render and the
    estimate's probe of it)."""
    cmd = [exe, "reference", scene, "-o", exr, "--width", str(width), "--spp", str(spp), "--estimate-noise",
           "--json", js, "-q"]
    if a.threads:
        cmd += ["--threads", str(a.threads)]
    if a.direct_only:
        cmd += ["--max-bounces", "1"]
    return cmd + shlex.split(a.ref_args)


def render_cmd(a, exe, scene, exr, js, width, spp):
    """photonbridge render as validate runs it (the render and the estimate's
    probe of it)."""
    cmd = [exe, "render", scene, "-o", exr, "--width", str(width), "--spp", str(spp), "--json", js, "-q"]
    if a.direct_only:
        cmd += ["--direct-only"]
    return cmd + shlex.split(a.render_args)


# The renderers that are not probed, in units of the reference's measured
# time per pixel and sample (the probe's), so that the model follows the
# machine's speed and --threads: POV-Ray's time per pixel by --pov-quality,
# and Cycles' per pixel and sample plus Blender's start and scene build.
# Measured on cornell_box (64 to 192 px, one thread, POV-Ray 3.7, Blender
# 3.4; high at 32 px only); radiosity's and Cycles' cost depend on the scene
# far more than the reference's, so these two are stated as modelled.
POV_PER_PIXEL = {"direct": 5.0, "draft": 20.0, "medium": 660.0, "high": 14000.0}
POV_START_S = 0.5
CYCLES_PER_SAMPLE = 0.75
CYCLES_START_S = 4.0
PROBE_MIN_S = 0.3
SHORT = {"reference": "reference", "photonbridge": "photonbridge", "povray": "POV-Ray", "cycles": "Cycles",
         "cycles45": "Cycles 4.5",
         "luxcore": "LuxCore", "mitsuba": "Mitsuba",
         "sequence": "sequence", "other": "pictures and comparisons"}


def duration(sec):
    """Seconds as a person reads them: 40 s, 2.5 min, 25 min, 1.5 h."""
    if sec < 59.5:
        return "%d s" % max(1, int(round(sec)))
    if sec < 600:
        return "%.1f min" % (sec / 60.0)
    if sec < 5400:
        return "%d min" % int(round(sec / 60.0))
    return "%.1f h" % (sec / 3600.0)


def probe_width(width, part):
    """A probe's width: 1/part of the run's, at least 16 px."""
    return min(width, max(16, int(round(width / float(part)))))


def tool_versions(exe):
    """The tools' versions for the report (photonbridge, POV-Ray, Blender,
    OpenColorIO, Python)."""
    bl = os.environ.get("BLENDER", "blender")
    versions = {
        "photonbridge": tool_version([exe, "--version"]),
        "povray": tool_version(["povray", "--version"], "POV-Ray") if shutil.which("povray") else None,
        "blender": tool_version([bl, "--version"], "Blender") if shutil.which(bl) else None,
        "opencolorio": None,
        "python": sys.version.split()[0],
    }
    rc, o, _ = run(["pkg-config", "--modversion", "OpenColorIO"], timeout=30)
    if rc == 0 and o.strip():
        versions["opencolorio"] = o.strip()
    return versions


def estimate_run(a, exe, scene, out, runs, color):
    """How long the renders of `runs` will take, before any of them starts.
    Measured where it is cheap: the reference and photonbridge render each
    render a probe with the run's own options in OUT/estimate/ (the
    reference at a quarter of the width and 2 samples per pixel; the GPU at
    half the width and 1 sample, since lavapipe's time per pass falls with
    the image size far into the thousands of pixels, so that a smaller
    probe overstates it), and each run is extrapolated by pixels x
    samples from the probe's render time, plus the probe's time outside it
    (start, scene load, BVH; for photonbridge also the photon map, which
    does not depend on the image size). POV-Ray and Cycles are modelled from
    the reference probe's time per pixel and sample (POV_PER_PIXEL,
    CYCLES_PER_SAMPLE). The pictures and comparisons count as the time of
    one display of a probe's picture (through the run's colour options)
    each (the faster of two), a compare as one; the tools' versions are
    taken here for the report (before the line, so not in its estimate). Returns (the report.json entry, its "line" the one printed;
    the versions)."""
    pdir = os.path.join(out, "estimate")
    os.makedirs(pdir, exist_ok=True)
    pw = probe_width(a.width, 4)
    parts, ref_rate, size = {}, None, None
    t0 = time.time()
    def pixel_passes_s(st):  # the GPU's passes per pixel and sample
        return sum((st.get("passes_ms") or {}).get(k) or 0.0 for k in ("gbuffer", "direct", "gather", "filter")) / 1e3

    def probe(name, build, full_spp, timed, width, spp):
        """One probe at `width` and `spp` samples, then, where its
        render took under PROBE_MIN_S (too short to time on a busy machine)
        and the run it extrapolates to matters (over 2 s), once more with
        the samples for about 1.5 PROBE_MIN_S (at most the run's). timed(st):
        the probe's render seconds from its --json. Returns (its --json,
        its wall seconds), or (None, None) when it failed."""
        spp = min(spp, full_spp)
        for _ in range(2):
            js = os.path.join(pdir, name + ".json")
            rc, _, dt = run(build(a, exe, scene, os.path.join(pdir, name + ".exr"), js, width, spp),
                            os.path.join(pdir, name + ".log"))
            st = read_json(js) or {}
            if rc != 0 or not all(isinstance(st.get(k), int) and st[k] > 0 for k in ("width", "height", "spp")):
                return None, None
            t = timed(st)
            run_s = t * (a.width / float(st["width"])) ** 2 * full_spp / st["spp"]
            if t >= PROBE_MIN_S or st["spp"] >= full_spp or run_s < 2:
                break
            spp = min(full_spp, int(math.ceil(st["spp"] * PROBE_MIN_S * 1.5 / max(t, 1e-3))))
        return st, dt

    if any(n in runs for n in ("reference", "povray", "cycles", "cycles45", "luxcore", "mitsuba")) or a.frames:
        spp = a.ref_spp + a.ref_spp % 2  # --estimate-noise rounds up to even
        st, dt = probe("reference", reference_cmd, spp, lambda st: st.get("time_s") or 0.0, pw, 2)
        if st and isinstance(st.get("time_s"), (int, float)) and st["time_s"] > 0:
            size = (a.width, max(1, int(round(a.width * st["height"] / float(st["width"])))))
            ref_rate = st["time_s"] / (st["width"] * st["height"] * st["spp"])
            if "reference" in runs:
                parts["reference"] = {
                    "s": max(0.0, dt - st["time_s"]) + ref_rate * size[0] * size[1] * spp, "method": "probe",
                    "probe": {"width": st["width"], "height": st["height"], "spp": st["spp"], "wall_s": round(dt, 3),
                              "render_s": st["time_s"]}}
    gpu = None
    if "photonbridge" in runs or (a.frames and not a.no_gpu):
        st, dt = probe("photonbridge", render_cmd, a.spp, pixel_passes_s, probe_width(a.width, 2), 1)
        if st:
            size = size or (a.width, max(1, int(round(a.width * st["height"] / float(st["width"])))))
            # The rest (device start, photon map, estimator) is the same at
            # any image size.
            pix_s = pixel_passes_s(st)
            photon_s = sum((st.get("passes_ms") or {}).get(k) or 0.0 for k in ("photon_trace", "estimator_build")) / 1e3
            gpu = {"fixed_s": max(0.0, dt - pix_s), "photon_s": photon_s,
                   "rate": pix_s / (st["width"] * st["height"] * st["spp"])}
            if "photonbridge" in runs:
                parts["photonbridge"] = {
                    "s": gpu["fixed_s"] + gpu["rate"] * size[0] * size[1] * a.spp, "method": "probe",
                    "probe": {"width": st["width"], "height": st["height"], "spp": st["spp"],
                              "wall_s": round(dt, 3), "pixel_passes_s": round(pix_s, 3)}}
    t_disp = None
    for f in ("reference.exr", "photonbridge.exr"):
        exr = os.path.join(pdir, f)
        if os.path.exists(exr) and t_disp is None:
            # Twice, the faster counting: the first also reads the binary
            # and the view's files from disk.
            for _ in range(2):
                rc, _, dt = run([exe, "display", exr, "-o", exr[:-4] + ".png"] + color,
                                os.path.join(pdir, "display.log"))
                t_disp = (dt if t_disp is None else min(t_disp, dt)) if rc == 0 else None
        for x in (exr, exr[:-4] + ".png"):
            if os.path.exists(x):
                os.remove(x)
    versions = tool_versions(exe)  # here, so that the line's time includes them
    probe_s = time.time() - t0
    if ref_rate and size:
        px = size[0] * size[1]
        if "povray" in runs:
            parts["povray"] = {"s": POV_START_S + ref_rate * px * POV_PER_PIXEL.get(a.pov_quality, 660.0),
                               "method": "model: %g reference pixel-samples per pixel at --pov-quality %s"
                                         % (POV_PER_PIXEL.get(a.pov_quality, 660.0), a.pov_quality)}
        for n in ("luxcore", "mitsuba"):
            if n in runs:
                parts[n] = {"s": PEER_START_S + ref_rate * px * a.ref_spp * PEER_PER_SAMPLE[n],
                            "method": "model: %g s start and %g reference pixel-samples per sample"
                                      % (PEER_START_S, PEER_PER_SAMPLE[n])}
        if "cycles45" in runs:
            parts["cycles45"] = {"s": CYCLES_START_S + ref_rate * px * a.cycles_spp * CYCLES_PER_SAMPLE,
                                 "method": "model: as Cycles 3.4"}
        if "cycles" in runs:
            parts["cycles"] = {"s": CYCLES_START_S + ref_rate * px * a.cycles_spp * CYCLES_PER_SAMPLE,
                               "method": "model: %g s Blender start and %g reference pixel-samples per sample"
                                         % (CYCLES_START_S, CYCLES_PER_SAMPLE)}
    frames = None
    if a.frames and size:
        try:
            f0, f1 = (int(x) for x in a.frames.split(":"))
            frames = f1 - f0 + 1
        except ValueError:
            frames = None
    if frames and frames > 0 and gpu and ref_rate:
        px = size[0] * size[1]
        parts["sequence"] = {"s": gpu["fixed_s"] + frames * (gpu["photon_s"] + gpu["rate"] * px * a.spp +
                                                             ref_rate * px * a.seq_ref_spp),
                             "method": "the probes, per frame"}
    n = len(runs)
    if t_disp is not None:
        # A display of each picture; each pair compared twice (the second
        # time on the shared heat-map scale), a compare measured at about
        # one display's time (the view's set-up dominates both).
        steps = n + n * (n - 1)
        parts["other"] = {"s": steps * t_disp,
                          "method": "%d displays' worth at the probe's display (%.2f s)" % (steps, t_disp)}
    total = sum(p["s"] for p in parts.values())
    shown = sorted((k for k in parts if k != "other"), key=lambda k: -parts[k]["s"])
    what = ", ".join("%s %s%s" % (SHORT[k], duration(parts[k]["s"]),
                                  " (modelled)" if parts[k]["method"].startswith("model") else "")
                     for k in shown + (["other"] if "other" in parts else []))
    spp = ", ".join("%s %d spp" % (SHORT[k], v) for k, v in (("reference", a.ref_spp), ("photonbridge", a.spp),
                                                              ("cycles", a.cycles_spp), ("cycles45", a.cycles_spp),
                                                              ("luxcore", a.ref_spp),
                                                              ("mitsuba", a.ref_spp)) if k in runs)
    if "povray" in runs:
        spp += (", " if spp else "") + "POV-Ray %s" % a.pov_quality
    line = "estimate: about %s (%s) at %s, %s; measured on small probe renders in %s" % (
        duration(total), what or "no render measured", "%dx%d" % size if size else "%d px wide" % a.width, spp,
        duration(probe_s))
    for p in parts.values():
        p["s"] = round(p["s"], 2)
    return {"total_s": round(total, 2), "parts": parts, "width": size[0] if size else a.width,
            "height": size[1] if size else None, "probe_s": round(probe_s, 2),
            "line": line}, versions


def main(argv):
    ap = argparse.ArgumentParser(prog="validate.py")
    ap.add_argument("scene")
    ap.add_argument("--out", required=True)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "photonbridge"))
    ap.add_argument("--width", type=int, default=384)
    ap.add_argument("--spp", type=int, default=16, help="photonbridge render samples per pixel")
    ap.add_argument("--ref-spp", type=int, default=64, help="reference samples per pixel")
    ap.add_argument("--pov-quality", default="medium", choices=["draft", "medium", "high", "direct"])
    ap.add_argument("--cycles-spp", type=int, default=64,
                    help="Cycles samples per pixel (two independent halves, for its own noise)")
    ap.add_argument("--cycles-source", choices=["auto", "sample", "gltf"], default="auto",
                    help="where the Cycles scene comes from: sample (exporters/blender/make_samples.py builds it), "
                         "gltf (Blender's importer reads SCENE, materials rebuilt as glTF's model); auto: sample "
                         "for the samples, gltf for every other file")
    ap.add_argument("--cycles-materials", choices=["model", "principled"], default="model",
                    help="model: glTF's material model (sample: Diffuse/Glossy/Glass BSDFs; gltf: rebuilt from "
                         "Cycles nodes); principled: Blender's Principled BSDFs as Blender sets them up")
    ap.add_argument("--threads", type=int, default=0, help="CPU threads for reference/POV-Ray/Cycles (0: all)")
    ap.add_argument("--direct-only", action="store_true",
                    help="direct light only everywhere: reference --max-bounces 1, render --direct-only, "
                         "POV-Ray quality direct, Cycles --bounces 0")
    ap.add_argument("--no-gpu", action="store_true")
    ap.add_argument("--no-povray", action="store_true")
    ap.add_argument("--no-cycles", action="store_true")
    ap.add_argument("--ocio-config")
    ap.add_argument("--display")
    ap.add_argument("--view")
    ap.add_argument("--look")
    ap.add_argument("--exposure")
    ap.add_argument("--render-args", default="", help="more options for photonbridge render (one string)")
    ap.add_argument("--ref-args", default="", help="more options for photonbridge reference (one string)")
    ap.add_argument("--frames", help="A:B: a sequence (photonbridge render --frames with per-frame references) "
                                     "instead of one picture")
    ap.add_argument("--seq-ref-spp", type=int, default=64, help="per-frame reference spp of --frames")
    ap.add_argument("--renderers", default=",".join(DEFAULT_RENDERERS),
                    help="comma list of the renderers to run (default: %s; also cycles45, luxcore, mitsuba); the others "
                         "are listed as skipped" % ",".join(DEFAULT_RENDERERS))
    ap.add_argument("--render-only", action="store_true",
                    help="run the renderers and write each one's record as DIR/render_NAME.json, no comparison "
                         "or report (one task per scene and renderer on a farm; then --report-from)")
    ap.add_argument("-q", "--quiet", action="store_true",
                    help="errors only: no progress, no time estimate, no status lines")
    ap.add_argument("--report-from", metavar="DIR[,DIR...]",
                    help="render nothing: gather what --render-only runs wrote into these folders (their records, "
                         "images and logs, copied into --out), then compare and write the report")
    a = ap.parse_args(argv)
    global QUIET
    QUIET = a.quiet
    want = [n.strip() for n in a.renderers.split(",") if n.strip()]
    bad = [n for n in want if n not in RUN_ORDER]
    if bad or not want:
        print("validate: --renderers %s: each one of %s" % (a.renderers, ",".join(RUN_ORDER)), file=sys.stderr)
        return 2
    if a.render_only and a.report_from:
        print("validate: --render-only and --report-from exclude each other", file=sys.stderr)
        return 2
    gather = [os.path.abspath(d) for d in a.report_from.split(",") if d] if a.report_from else []
    for d in gather:
        if not os.path.isdir(d):
            print("validate: --report-from %s: no such folder" % d, file=sys.stderr)
            return 2

    scene, sample = resolve_scene(a.scene)
    if not scene:
        print("validate: %s: no such scene file or sample" % a.scene, file=sys.stderr)
        return 2
    blend = scene if scene.lower().endswith(".blend") else None
    if not os.access(a.exe, os.X_OK):
        print("validate: %s: photonbridge executable not found (--exe)" % a.exe, file=sys.stderr)
        return 2
    exe = os.path.abspath(a.exe)
    out = os.path.abspath(a.out)
    global CREATED
    try:
        if not os.path.exists(out):
            CREATED = out
        os.makedirs(out, exist_ok=True)
    except OSError as e:  # one line and the result table's PB_ERR_IO (3), not a traceback
        print("photonbridge validate: error: %s: cannot create the output folder: %s" % (out, e.strerror),
              file=sys.stderr)
        return 3
    color = []
    for k in ("ocio_config", "display", "view", "look", "exposure"):
        v = getattr(a, k)
        if v:
            color += ["--" + k.replace("_", "-"), v]
    if a.direct_only:
        a.pov_quality = "direct"

    # --report-from: the folders of --render-only runs (one per renderer on a
    # farm) copied into OUT; each renderer's file names are its own, and the
    # hand-off of a .blend is the same in each (one writer, one file).
    for d in gather:
        shutil.copytree(d, out, dirs_exist_ok=True)

    # A .blend: photonbridge (reference, GPU, POV-Ray) renders what the
    # Blender render engine hands over (its glTF and the PHOTONBRIDGE_blender
    # extension); Cycles renders the .blend itself.
    handoff = None
    if blend and gather and read_json(os.path.join(out, "handoff", "handoff.json")):
        handoff = read_json(os.path.join(out, "handoff", "handoff.json"))
        scene = os.path.join(out, "handoff", os.path.splitext(os.path.basename(blend))[0] + ".gltf")
    elif blend:
        progress("the render engine's hand-off of the .blend")
        gltf, handoff = blend_handoff(blend, out)
        if gltf is None:
            print("photonbridge validate: error: %s" % handoff, file=sys.stderr)
            return 1
        scene = gltf

    renders = {}

    def record(name, status, reason=None, **kw):
        r = {"name": name, "label": LABEL[name], "status": status}
        if handoff and name not in ("cycles", "cycles45"):
            r["handoff"] = True  # renders the render engine's hand-off of the .blend
        if reason:
            r["reason"] = reason
        r.update(kw)
        renders[name] = r
        if not QUIET or status == "failed":
            print("validate: %-12s %s%s" % (name, status, (": " + reason) if reason else ""))

    # --report-from: the renderers' records as their runs wrote them.
    if gather:
        for n in RUN_ORDER:
            rec = read_json(os.path.join(out, "render_%s.json" % n))
            if rec and rec.get("name") == n:
                renders[n] = rec
                if not QUIET:
                    print("validate: %-12s %s (from --report-from)" % (n, rec.get("status")))
            else:
                record(n, "skipped", "not rendered: no render_%s.json in the --report-from folders" % n)
    skip = (lambda n: True) if gather else (lambda n: n not in want)
    for n in RUN_ORDER:
        if skip(n) and not gather:
            record(n, "skipped", "--renderers %s" % a.renderers)

    # How long the renders will take, measured on small probes (estimate_run),
    # before the first of them: one stderr line, and report.json's estimate.
    estimate = versions = None
    if not gather:
        runs = [n for n in RUN_ORDER if not skip(n) and not not_runnable(a, n, scene, sample, blend)]
        if runs:
            estimate, versions = estimate_run(a, exe, scene, out, runs, color)
            if not QUIET:
                print("validate: %s" % estimate["line"], file=sys.stderr, flush=True)

    # Reference (CPU).
    if not skip("reference"):
        progress("reference")
        exr = os.path.join(out, "reference.exr")
        cmd = reference_cmd(a, exe, scene, exr, os.path.join(out, "reference.json"), a.width, a.ref_spp)
        rc, o, dt = run(cmd, os.path.join(out, "reference.log"))
        st = read_json(os.path.join(out, "reference.json")) or {}
        if rc == 0 and os.path.isfile(exr):
            record("reference", "ok", exr="reference.exr", wall_s=round(dt, 3), render_s=st.get("time_s"),
                   width=st.get("width"), height=st.get("height"), camera=st.get("camera"),
                   settings={"spp": st.get("spp"), "mode": st.get("mode"), "max_bounces": st.get("max_bounces"),
                             "seed": st.get("seed"), "threads": st.get("threads"),
                             "photon_paths": st.get("photon_paths")},
                   noise=st.get("noise"), command=cmd)
        else:
            record("reference", "failed", "exit %d: %s" % (rc, o.strip()[-300:]), command=cmd)

    # What the loader made of the scene (cameras, lights, units, warnings):
    # the Cycles scene takes photonbridge's camera, and the report's notes.
    info_path = os.path.join(out, "info.json")
    rc, o, _ = run([exe, "info", scene, "--json", info_path, "-q"] + loader_args(a.ref_args),
                   os.path.join(out, "info.log"))
    info = read_json(info_path) if rc == 0 else None
    info_error = o.strip().splitlines()[-1] if o.strip() else "exit %d" % rc
    # Cycles follows the reference's image size, camera and path length; a run
    # without the reference (--renderers) takes them as the reference would:
    # from the loader and from --ref-args.
    ref_r = renders.get("reference") if renders.get("reference", {}).get("status") == "ok" else {}
    size = (ref_r.get("width"), ref_r.get("height")) if ref_r.get("width") else image_size(info, a.width)
    ref_opts = shlex.split(a.ref_args)
    for k, v in zip(ref_opts, ref_opts[1:]):
        if k == "--max-bounces" and not ref_r.get("settings"):
            ref_r = dict(ref_r, settings={"max_bounces": int(v) if v.isdigit() else None})
        if k == "--camera" and not ref_r.get("camera"):
            ref_r = dict(ref_r, camera=v)

    # photonbridge render (GPU).
    why = None if skip("photonbridge") else not_runnable(a, "photonbridge", scene, sample, blend)
    if skip("photonbridge"):
        pass
    elif why:
        record("photonbridge", *why)
    else:
        progress("photonbridge render")
        exr = os.path.join(out, "photonbridge.exr")
        cmd = render_cmd(a, exe, scene, exr, os.path.join(out, "photonbridge.json"), a.width, a.spp)
        rc, o, dt = run(cmd, os.path.join(out, "photonbridge.log"))
        st = read_json(os.path.join(out, "photonbridge.json")) or {}
        if rc == 0 and os.path.isfile(exr):
            record("photonbridge", "ok", exr="photonbridge.exr", wall_s=round(dt, 3), label=photonbridge_label(st),
                   render_s=(st["wall_ms"] / 1000.0) if isinstance(st.get("wall_ms"), (int, float)) else None,
                   settings={"spp": a.spp, "direct_only": a.direct_only, "device": st.get("device"),
                             "device_type": st.get("device_type"),
                             "photons_emitted": (st.get("photons") or {}).get("emitted"),
                             "photons_stored": (st.get("photons") or {}).get("stored"),
                             "extra": a.render_args or None},
                   command=cmd)
        else:
            record("photonbridge", "failed", "exit %d: %s" % (rc, o.strip()[-300:]), command=cmd)

    # POV-Ray.
    why = None if skip("povray") else not_runnable(a, "povray", scene, sample, blend)
    if skip("povray"):
        pass
    elif why:
        record("povray", *why)
    else:
        progress("POV-Ray")
        pdir = os.path.join(out, "povray")
        os.makedirs(pdir, exist_ok=True)
        pov = os.path.join(pdir, "scene.pov")
        exr = os.path.join(out, "povray.exr")
        cmd1 = [exe, "export-pov", scene, "-o", pov, "--width", str(a.width), "--quality", a.pov_quality]
        rc, o, _ = run(cmd1, os.path.join(out, "povray-export.log"))
        notes = [l for l in o.splitlines() if l.startswith("note:")]
        if rc != 0:
            record("povray", "failed", "export-pov exit %d: %s" % (rc, o.strip()[-300:]), command=cmd1)
        else:
            extra = ["--", "+WT%d" % a.threads] if a.threads else []
            cmd2 = ["sh", os.path.join(HERE, "run_povray.sh"), pov, exr] + extra
            rc, o, dt = run(cmd2, os.path.join(out, "povray-run.log"))
            if rc == 0 and os.path.isfile(exr):
                wall = None
                try:
                    for l in open(exr + ".log"):
                        if l.startswith("wall_s="):
                            wall = float(l.split("=", 1)[1])
                except OSError:
                    pass
                record("povray", "ok", exr="povray.exr", wall_s=round(dt, 3), render_s=wall,
                       settings={"quality": a.pov_quality, "antialias": "run_povray.sh default",
                                 "notes": notes}, command=cmd1 + [";"] + cmd2)
            else:
                record("povray", "failed", "run_povray exit %d: %s" % (rc, o.strip()[-300:]),
                       command=cmd1 + [";"] + cmd2)

    # The peers: LuxCoreRender (PATHCPU) and Mitsuba 3 (path) render what
    # photonbridge's loader made of the scene (export-peer: world-space
    # meshes, the camera, lights in each peer's units), at the reference's
    # size, camera and samples.
    for n in ("luxcore", "mitsuba"):
        if skip(n):
            continue
        py = peer_python(n)
        why = not_runnable(a, n, scene, sample, blend)
        if why:
            record(n, *why)
            continue
        progress(LABEL[n])
        pdir = os.path.join(out, n)
        exr = os.path.join(out, n + ".exr")
        cmd1 = [exe, "export-peer", scene, "--format", n, "-o", pdir, "--width", str(size[0]), "--height",
                str(size[1]), "--spp", str(a.ref_spp), "--threads", str(a.threads or 2)]
        cmd1 += (["--camera", ref_r["camera"]] if ref_r.get("camera") else []) + loader_args(a.ref_args)
        rc, o, _ = run(cmd1, os.path.join(out, n + "-export.log"))
        notes = [l[len("note: "):] if l.startswith("note: ") else l for l in o.splitlines() if l.startswith("note")]
        if rc != 0:
            record(n, "failed", "export-peer exit %d: %s" % (rc, o.strip()[-300:]), command=cmd1)
            continue
        cmd2 = [py, os.path.join(HERE, "peer_render.py"), n, pdir, exr, "--spp", str(a.ref_spp),
                "--threads", str(a.threads or 2)]
        rc, o, dt = run(cmd2, os.path.join(out, n + "-run.log"))
        st = read_json(exr + ".json") or {}
        if rc == 0 and os.path.isfile(exr):
            record(n, "ok", exr=n + ".exr", wall_s=round(dt, 3), render_s=st.get("render_s"),
                   settings={"version": st.get("version"), "spp": st.get("spp_reached", a.ref_spp),
                             "threads": a.threads or 2, "engine": st.get("engine"), "variant": st.get("variant"),
                             "notes": notes}, command=cmd1 + [";"] + cmd2)
        else:
            record(n, "failed", "peer_render exit %d: %s" % (rc, o.strip()[-300:]), command=cmd1 + [";"] + cmd2)

    # Cycles: Debian's Blender (cycles), and Blender 4.5 LTS as a Python
    # module (cycles45: tools/bpy45 through tests/blender/bpy_blender.py,
    # the `blender` command line over bpy), the same sources and settings.
    for n in ("cycles", "cycles45"):
        if not skip(n):
            run_cycles_renderer(a, n, exe, scene, sample, blend, out, info, info_path, info_error, ref_r, size,
                                color, record)

    # --render-only: each renderer's record for a later --report-from run.
    if a.render_only:
        for n in want:
            write_atomic(os.path.join(out, "render_%s.json" % n), json.dumps(renders[n], indent=1))
        failed = [n for n in want if renders[n]["status"] == "failed"]
        if not QUIET or failed:
            print("validate: rendered %s%s" % (",".join(want), "; failed: " + ",".join(failed) if failed else ""))
        return 1 if failed else 0

    ok = [n for n in ORDER if renders.get(n, {}).get("status") == "ok"]

    # Display images, all through the same OCIO view (Blender's Filmic by
    # default, as Blender shows renders).
    picture_view = None
    for n in ok:
        png = n + ".png"
        cmd = [exe, "display", os.path.join(out, renders[n]["exr"]), "-o", os.path.join(out, png)] + color
        rc, o, _ = run(cmd, os.path.join(out, n + "-display.log"))
        if rc == 0:
            renders[n]["png"] = png
            for line in o.splitlines():
                if line.startswith("display: wrote ") and " through " in line:
                    picture_view = picture_view or line.split(" through ", 1)[1]
        else:
            renders[n]["display_error"] = o.strip()[-300:]

    # What each renderer shows differently by design, for every pair's row.
    try:
        facts = gltf_json.facts(gltf_json.read(scene))
    except gltf_json.GltfError:
        facts = None
    for n, r in renders.items():
        if r["status"] == "ok":
            r["notes"] = renderer_notes(n, r, info, facts)

    # Every pair through the shared metrics, then the heat maps again on one
    # scale (the largest of the pairs' 99th percentiles), so that their
    # colours compare across maps.
    pairs = []
    display_name = None
    for i, r in enumerate(ok):
        for t in ok[i + 1:]:
            tag = "%s_vs_%s" % (t, r)
            js = os.path.join(out, "cmp_" + tag + ".json")
            heat = "heat_" + tag + ".png"
            cmd = [exe, "compare", os.path.join(out, renders[t]["exr"]), os.path.join(out, renders[r]["exr"]),
                   "--json", js, "--heatmap", os.path.join(out, heat), "-q"] + color
            rc, o, _ = run(cmd, os.path.join(out, "cmp_" + tag + ".log"))
            m = read_json(js) if rc == 0 else None
            # A note both renderers carry (the loader both read the file with)
            # leaves them alike: only the others can separate the pair.
            both = set(renders[t]["notes"]) & set(renders[r]["notes"])
            p = {"test": t, "reference": r, "_cmd": cmd,
                 "by_design": [{"renderer": x, "note": note} for x in (t, r) for note in renders[x]["notes"]
                               if note not in both]}
            if m:
                display_name = display_name or m.get("display")
                p.update({k: m.get(k) for k in ("width", "height", "rmse", "relmse", "psnr_db", "ssim",
                                                "max_abs_error", "nonfinite_values")})
                p["heatmap"] = heat if os.path.isfile(os.path.join(out, heat)) else None
                p["_scale"] = (m.get("heatmap") or {}).get("scale_max")
            else:
                p["error"] = o.strip()[-300:]
            pairs.append(p)
    scales = [p["_scale"] for p in pairs if isinstance(p.get("_scale"), (int, float)) and p["_scale"] > 0]
    heat_scale = max(scales) if scales else None
    for p in pairs:
        cmd = p.pop("_cmd")
        p.pop("_scale", None)
        if heat_scale and p.get("heatmap"):
            rc, o, _ = run(cmd + ["--heatmap-max", repr(heat_scale)],
                           os.path.join(out, "cmp_%s_vs_%s.log" % (p["test"], p["reference"])))
            if rc != 0:
                p["heatmap"] = None

    # HDR-FLIP of every pair on the scene-linear images (the exposures from
    # the pair's reference), with FLIP's own error map.
    flip_py = os.environ.get(FLIP_PYTHON[0]) or FLIP_PYTHON[1]
    flip = {"available": os.access(flip_py, os.X_OK)}
    if not flip["available"]:
        flip["reason"] = "%s not found (scripts/install-deps.sh installs it; or set %s)" % (flip_py, FLIP_PYTHON[0])
    for p in pairs:
        if not flip["available"] or "error" in p:
            continue
        tag = "%s_vs_%s" % (p["test"], p["reference"])
        fmap = "flip_" + tag + ".png"
        rc, o, _ = run([flip_py, os.path.join(HERE, "flip_mean.py"), os.path.join(out, renders[p["reference"]]["exr"]),
                        os.path.join(out, renders[p["test"]]["exr"]), "--map", os.path.join(out, fmap)],
                       os.path.join(out, "flip_" + tag + ".log"))
        try:
            res = json.loads(o.strip().splitlines()[-1])
            flip["version"] = res.get("version")
            res = res["results"][0]
        except (ValueError, IndexError, KeyError):
            res = {"error": "exit %d: %s" % (rc, o.strip()[-300:])}
        if rc == 0 and "hdr_flip_mean" in res:
            p["hdr_flip"] = res["hdr_flip_mean"]
            p["flip_map"] = fmap if os.path.isfile(os.path.join(out, fmap)) else None
        else:
            p["flip_error"] = res.get("error") or "exit %d" % rc

    sequence = run_sequence(a, exe, scene, out, color) if a.frames else None

    versions = versions or tool_versions(exe)
    report = {
        "scene": scene, "sample": sample, "blend": blend, "handoff": handoff, "width": a.width,
        "direct_only": a.direct_only,
        "display": display_name or "sRGB / Standard (built-in)", "color_options": color,
        "picture_view": picture_view, "heat_scale": heat_scale, "sequence": sequence, "estimate": estimate,
        "validation_script": os.path.abspath(__file__),
        "scene_notes": scene_notes(facts),
        "metrics_note": "RMSE and relMSE (mean of (t-r)^2/(r^2+0.01)) on scene-linear RGB; PSNR and SSIM "
                        "on the display image through the OCIO view above (src/metrics, photonbridge compare); "
                        "HDR-FLIP (NVIDIA FLIP: 0 indistinguishable, 1 maximal) on scene-linear RGB, the exposures "
                        "from each pair's reference",
        "flip": flip,
        "renders": [renders[n] for n in ORDER if n in renders], "pairs": pairs, "versions": versions,
        "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    # Written to a temporary and renamed: an interrupted run leaves no
    # half-written report.
    write_atomic(os.path.join(out, "report.json"), json.dumps(report, indent=1))
    write_atomic(os.path.join(out, "index.html"), render_html(report))
    if not QUIET:
        print("validate: wrote %s and %s" % (os.path.join(out, "index.html"), os.path.join(out, "report.json")))
    return 0 if "reference" in ok and len(ok) >= 2 else 1


def bpy45_paths():
    """tools/bpy45's Python (PB_BPY45_PYTHON names another) and the shim
    that runs it as a `blender` command line."""
    return (os.environ.get("PB_BPY45_PYTHON") or os.path.join(ROOT, "tools", "bpy45", "bin", "python"),
            os.path.join(ROOT, "tests", "blender", "bpy_blender.py"))


def bpy45_missing():
    """Why Cycles 4.5 cannot run here, or None."""
    py, shim = bpy45_paths()
    if not os.access(py, os.X_OK):
        return "%s not found (scripts/install-deps.sh installs bpy 4.5; or set PB_BPY45_PYTHON)" % py
    if not os.path.isfile(shim):
        return "%s not found (Cycles 4.5 needs the source tree)" % shim
    return None


def blender_command(name, out):
    """The Blender run_cycles.sh starts: $BLENDER (default blender) for
    cycles; for cycles45 a wrapper in OUT running tests/blender/bpy_blender.py
    under bpy 4.5's Python (bpy45_missing() None)."""
    if name == "cycles":
        return os.environ.get("BLENDER", "blender")
    py, shim = bpy45_paths()
    wrapper = os.path.join(out, "cycles45", "blender")
    os.makedirs(os.path.dirname(wrapper), exist_ok=True)
    with open(wrapper, "w") as f:
        f.write("#!/bin/sh\nexec %s %s \"$@\"\n" % (shlex.quote(py), shlex.quote(shim)))
    os.chmod(wrapper, 0o755)
    return wrapper


def run_cycles_renderer(a, n, exe, scene, sample, blend, out, info, info_path, info_error, ref_r, size, color,
                        record):
    """Cycles (n: cycles or cycles45) on the scene's Cycles source
    (cycles_source) at the reference's size, camera and path length, as two
    independent halves; its record through record()."""
    src = cycles_source(a, scene, sample, blend)
    if n == "cycles45" and src is not None and src["kind"] == "sample" and a.cycles_source == "auto":
        # The samples' Blender script (make_samples.py) sets up Blender 3.4's
        # Principled sockets: Blender 4.5 reads the glTF through its importer.
        src = {"kind": "gltf", "scene": scene, "materials": "gltf" if src["materials"] == "bsdf" else "principled",
               "args": []}
    why = not_runnable(a, n, scene, sample, blend)
    if why:
        record(n, *why)
    elif not info:
        record(n, "failed", "photonbridge info could not read the scene: %s" % info_error)
    else:
        progress(LABEL[n])
        exr = os.path.join(out, n + ".exr")
        ref_st = ref_r.get("settings") or {}
        # The reference's path-length limit: max_bounces scattering events
        # between light and eye (direct light: 1); Cycles counts the first
        # hit's light as bounce 0, so max_bounces - 1 is the same set of paths.
        bounces = max(0, (ref_st.get("max_bounces") or (1 if a.direct_only else 8)) - 1)
        if src["kind"] == "gltf":
            src["args"] += ["--info", info_path] + (["--camera", ref_r["camera"]] if ref_r.get("camera") else [])
        cmd = ["sh", os.path.join(HERE, "run_cycles.sh"), src["scene"], exr, "--width", str(size[0]),
               "--height", str(size[1]), "--samples", str(a.cycles_spp), "--bounces", str(bounces),
               "--materials", src["materials"], "--halves"] + src["args"]
        if a.threads:
            cmd += ["--threads", str(a.threads)]
        rc, o, dt = run(cmd, os.path.join(out, n + "-run.log"),
                        env=dict(os.environ, BLENDER=blender_command(n, out)))
        st = read_json(exr + ".json") or {}
        if rc == 0 and os.path.isfile(exr):
            noise = halves_noise(exe, out, [exr + "." + h for h in ("a.exr", "b.exr")], color)
            record(n, "ok", exr=n + ".exr", wall_s=round(dt, 3), render_s=st.get("render_s"),
                   settings={"source": src["kind"], "materials": st.get("material_model"), "blender": st.get("blender"),
                             "samples": st.get("samples"), "bounces": st.get("bounces"), "seed": st.get("seed"),
                             "pixel_filter": st.get("pixel_filter"), "denoising": False, "clamping": False},
                   noise=noise, notes=st.get("notes") or [], command=cmd)
        else:
            reason = st.get("error") or "exit %d: %s" % (rc, o.strip()[-300:])
            record(n, "failed", reason, command=cmd)


def run_sequence(a, exe, scene, out, color):
    """photonbridge render --frames A:B with per-frame references (cached in
    DIR/seq/ref): each frame's picture and its reference's, the per-frame error
    and the flicker, for the sequence part of the page."""
    sdir = os.path.join(out, "seq")
    os.makedirs(os.path.join(sdir, "ref"), exist_ok=True)
    progress("photonbridge render --frames %s (with per-frame references)" % a.frames)
    js = os.path.join(sdir, "sequence.json")
    cmd = [exe, "render", scene, "--frames", a.frames, "-o", os.path.join(sdir, "frame_####.exr"),
           "--png", os.path.join(sdir, "frame_####.png"), "--width", str(a.width), "--spp", str(a.spp),
           "--reference-spp", str(a.seq_ref_spp), "--reference-cache", os.path.join(sdir, "ref"),
           "--json", js, "-q"] + color + shlex.split(a.render_args)
    rc, o, dt = run(cmd, os.path.join(out, "sequence.log"))
    st = read_json(js)
    if rc != 0 or not st:
        return {"first": 0, "last": -1, "frames": [], "note": "sequence failed: exit %d: %s" % (rc, o.strip()[-300:]),
                "summary": {}}
    frames = []
    for f in st.get("frames", []):
        n = f.get("frame")
        ref = f.get("reference") or {}
        item = {"frame": n, "psnr_db": ref.get("psnr_db"), "relmse": ref.get("relmse"),
                "change_result": ref.get("change_result"), "change_reference": ref.get("change_reference"),
                "wall_ms": f.get("wall_ms"), "_ref": ref.get("file")}
        png = "seq/frame_%04d.png" % n
        if os.path.isfile(os.path.join(out, png)):
            item["png"] = png
        frames.append(item)
    # The cached references, through the same view, beside each frame.
    for item in frames:
        ref = item.pop("_ref", None)
        if ref and os.path.isfile(ref):
            png = "seq/ref_%04d.png" % item["frame"]
            rc2, _, _ = run([exe, "display", ref, "-o", os.path.join(out, png)] + color)
            if rc2 == 0:
                item["reference_png"] = png
    nums = [f["frame"] for f in frames] or [0]
    return {"first": min(nums), "last": max(nums), "frames": frames, "summary": st.get("summary", {}),
            "wall_s": round(dt, 3),
            "note": "photonbridge render --frames %s (temporal + A-Trous filtering), top row; each frame's reference "
                    "(%d spp, Embree path tracer) below it. Settings: %s" % (a.frames, a.seq_ref_spp,
                                                                          " ".join(cmd[2:]))}


def fmt(v, spec):
    if v is None:
        return "—"
    try:
        return format(v, spec)
    except (TypeError, ValueError):
        return html.escape(str(v))


# matplotlib's viridis at 0, 1/8, ..., 1: the heat maps' colour map
# (src/metrics/metrics.c), for the colour bar.
VIRIDIS = ["#440154", "#482878", "#3e4989", "#31688e", "#26828e", "#1f9e89", "#35b779", "#6ece58",
           "#fde725"]

STYLE = """
body{font-family:system-ui,sans-serif;margin:16px 24px;background:#1e1e1e;color:#ddd;max-width:1600px}
a{color:#8cf} h1{font-size:22px;margin:4px 0} h2{font-size:17px;margin:22px 0 6px;color:#fff}
p.note{font-size:13px;color:#aaa;max-width:1100px}
table{border-collapse:collapse;margin:6px 0}td,th{border:1px solid #555;padding:3px 8px;font-size:13px}
th{background:#333} td.num{text-align:right;font-variant-numeric:tabular-nums} .bad{color:#f77}
.pics{display:flex;flex-wrap:wrap;gap:10px}
.fig{text-align:center;font-size:13px}
.fig img{display:block;max-width:100%;height:auto;image-rendering:pixelated;border:1px solid #666;background:#000}
#cmp{position:relative;display:inline-block;border:1px solid #888;background:#000;line-height:0}
#cmp img{display:block;image-rendering:pixelated;height:auto}
#cmp #cmpB{position:absolute;left:0;top:0;width:100%;height:100%}
#cmp .lab{position:absolute;top:6px;padding:2px 6px;background:rgba(0,0,0,.6);font-size:13px;line-height:16px;color:#fff}
#cmp #labA{left:6px} #cmp #labB{right:6px}
#divider{position:absolute;top:0;bottom:0;width:2px;background:#fff;pointer-events:none}
.controls{margin:6px 0;font-size:14px} .controls select,.controls button{font-size:14px;margin-right:6px}
.bar{display:flex;align-items:center;gap:8px;font-size:13px;margin:6px 0}
.bar .grad{width:320px;height:14px;border:1px solid #888}
td.design{font-size:12px;color:#bbb;max-width:560px} td.design ul{margin:0;padding-left:16px}
.strip{display:flex;gap:4px;overflow-x:auto} .strip .fig img{width:160px}
"""

SCRIPT = r"""
(function(){
  var R = JSON.parse(document.getElementById('renders-data').textContent);
  var loaded = 0, failed = 0, imgs = document.images;
  function tally(){ document.body.setAttribute('data-images-loaded', loaded);
                    document.body.setAttribute('data-images-failed', failed); }
  for (var i = 0; i < imgs.length; ++i) {
    var im = imgs[i];
    if (im.complete && im.naturalWidth) { loaded++; continue; }
    im.addEventListener('load', function(){ loaded++; tally(); });
    im.addEventListener('error', function(){ failed++; tally(); });
  }
  tally();
  var a = document.getElementById('selA'), b = document.getElementById('selB');
  var ia = document.getElementById('cmpA'), ib = document.getElementById('cmpB');
  var mode = 'slider', pos = 50, show = 'B', timer = null;
  function url(n){ for (var k = 0; k < R.length; ++k) if (R[k].name == n) return R[k].png; return ''; }
  function label(n){ for (var k = 0; k < R.length; ++k) if (R[k].name == n) return R[k].label; return n; }
  function draw(){
    ia.src = url(a.value); ib.src = url(b.value);
    document.getElementById('labA').textContent = label(a.value);
    document.getElementById('labB').textContent = label(b.value);
    var d = document.getElementById('divider');
    if (mode == 'slider') {
      ib.style.visibility = 'visible';
      ib.style.clipPath = 'inset(0 0 0 ' + pos + '%)';
      d.style.display = 'block'; d.style.left = pos + '%';
      document.getElementById('labA').style.visibility = 'visible';
      document.getElementById('labB').style.visibility = 'visible';
    } else {
      ib.style.clipPath = 'none'; d.style.display = 'none';
      ib.style.visibility = show == 'B' ? 'visible' : 'hidden';
      document.getElementById('labA').style.visibility = show == 'A' ? 'visible' : 'hidden';
      document.getElementById('labB').style.visibility = show == 'B' ? 'visible' : 'hidden';
    }
    document.getElementById('cmp').setAttribute('data-state', mode + ':' + (mode == 'slider' ? pos : show));
  }
  function setMode(m){ mode = m; if (timer) { clearInterval(timer); timer = null; } draw(); }
  document.getElementById('modeSlider').onclick = function(){ setMode('slider'); };
  document.getElementById('modeFlip').onclick = function(){ setMode('flip'); };
  document.getElementById('autoFlip').onclick = function(){
    setMode('flip'); timer = setInterval(function(){ show = show == 'A' ? 'B' : 'A'; draw(); }, 700); };
  document.getElementById('swap').onclick = function(){ var t = a.value; a.value = b.value; b.value = t; draw(); };
  a.onchange = b.onchange = draw;
  var box = document.getElementById('cmp');
  function slide(e){ if (mode != 'slider') return; var r = box.getBoundingClientRect();
    pos = Math.max(0, Math.min(100, 100 * (e.clientX - r.left) / r.width)); draw(); }
  box.addEventListener('mousemove', function(e){ if (e.buttons & 1) slide(e); });
  box.addEventListener('mousedown', slide);
  box.addEventListener('click', function(){ if (mode == 'flip') { show = show == 'A' ? 'B' : 'A'; draw(); } });
  document.addEventListener('keydown', function(e){
    if (e.key == 'f' || e.key == ' ') { if (mode != 'flip') setMode('flip'); show = show == 'A' ? 'B' : 'A'; draw(); e.preventDefault(); }
    if (e.key == 's') setMode('slider');
  });
  // State from the address: #a=reference&b=photonbridge&mode=flip&show=A (or &pos=30),
  // so a link (or a headless browser) opens a given comparison.
  var h = {}; location.hash.replace(/^#/, '').split('&').forEach(function(kv){
    var p = kv.split('='); if (p[0]) h[decodeURIComponent(p[0])] = decodeURIComponent(p[1] || ''); });
  if (h.a && url(h.a)) a.value = h.a;
  if (h.b && url(h.b)) b.value = h.b;
  if (h.mode == 'flip' || h.mode == 'slider') mode = h.mode;
  if (h.show == 'A' || h.show == 'B') show = h.show;
  if (h.pos && !isNaN(+h.pos)) pos = Math.max(0, Math.min(100, +h.pos));
  draw();
})();
"""


def render_html(rep):
    e = html.escape
    shown = [r for r in rep["renders"] if r.get("png")]
    # Pictures at least 384 px wide on the page (small renders scaled up with
    # square pixels), the comparison at least 640; full size on click.
    fig_w = max(384, rep["width"])
    cmp_w = max(640, rep["width"])
    h = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>photonbridge validation: %s</title>"
         % e(os.path.basename(rep["scene"])), "<style>%s</style></head><body>" % STYLE,
         "<h1>Validation: %s</h1>" % e(os.path.basename(rep["scene"])),
         "<p class='note'>Scene <code>%s</code>, %d px wide%s. Pictures through <b>%s</b> (scene-linear EXRs "
         "beside this page). Metrics through <b>%s</b>.</p>"
         % (e(rep["scene"]), rep["width"], ", direct light only" if rep["direct_only"] else "",
            e(rep.get("picture_view") or "?"), e(rep["display"]))]

    # The comparison: any two renderers, slider or flip.
    if len(shown) >= 2:
        ref = "reference" if any(r["name"] == "reference" for r in shown) else shown[0]["name"]
        test = next((r["name"] for r in shown if r["name"] == "photonbridge"),
                    next(r["name"] for r in shown if r["name"] != ref))
        opts = lambda sel: "".join("<option value='%s'%s>%s</option>" % (e(r["name"]), " selected" if r["name"] == sel
                                                                          else "", e(r["label"])) for r in shown)
        h += ["<h2>Compare</h2>",
              "<div class='controls'>A <select id='selA'>%s</select> B <select id='selB'>%s</select>"
              "<button id='swap'>swap</button> <button id='modeSlider'>slider</button>"
              "<button id='modeFlip'>flip (click, f or space)</button><button id='autoFlip'>auto flip</button></div>"
              % (opts(ref), opts(test)),
              "<div id='cmp'><img id='cmpA' alt='A' style='width:%dpx'><img id='cmpB' alt='B'><div id='divider'></div>"
              % cmp_w +
              "<span class='lab' id='labA'></span><span class='lab' id='labB'></span></div>",
              "<p class='note'>Drag across the picture to move the divider (A left, B right); in flip mode a "
              "click, f or space switches A and B in place, which shows differences the eye misses side by "
              "side.</p>"]

    h.append("<h2>Pictures</h2><div class='pics'>")
    for r in rep["renders"]:
        if r.get("png"):
            t = r.get("render_s")
            h.append("<div class='fig'><a href='%s'><img src='%s' alt='%s' style='width:%dpx'></a>%s<br>"
                     "<small>%s</small></div>" % (e(r["png"]), e(r["png"]), e(r["name"]), fig_w, e(r["label"]),
                        ("%.2f s" % t) if isinstance(t, (int, float)) else ""))
    h.append("</div>")

    heat = [p for p in rep["pairs"] if p.get("heatmap")]
    if heat:
        scale = rep.get("heat_scale")
        grad = "linear-gradient(to right,%s)" % ",".join(VIRIDIS)
        h.append("<h2>Per-pixel error</h2><p class='note'>sqrt(mean over RGB of (t-r)^2/(r^2+0.01)) of test "
                 "against reference, scene-linear; every map on the same scale, so colours compare across "
                 "maps.</p>")
        h.append("<div class='bar'>0 <div class='grad' style='background:%s'></div> %s (and above)</div>"
                 % (grad, fmt(scale, ".3g")))
        h.append("<div class='pics'>")
        for p in heat:
            h.append("<div class='fig'><a href='%s'><img src='%s' alt='heat' style='width:%dpx'></a>%s vs %s<br>"
                     "<small>PSNR %s dB</small></div>" % (e(p["heatmap"]), e(p["heatmap"]), fig_w, e(p["test"]),
                                                          e(p["reference"]),
                                         fmt(p.get("psnr_db"), ".2f")))
        h.append("</div>")
    fl = [p for p in rep["pairs"] if p.get("flip_map")]
    if fl:
        h.append("<h2>HDR-FLIP</h2><p class='note'>NVIDIA FLIP %s's error map of test against reference on the "
                 "scene-linear images, at the exposures FLIP picks from the pair's reference (black: "
                 "indistinguishable; light yellow: maximal).</p><div class='pics'>"
                 % e((rep.get("flip") or {}).get("version") or ""))
        for p in fl:
            h.append("<div class='fig'><a href='%s'><img src='%s' alt='FLIP' style='width:%dpx'></a>%s vs %s<br>"
                     "<small>HDR-FLIP %s</small></div>" % (e(p["flip_map"]), e(p["flip_map"]), fig_w, e(p["test"]),
                                                           e(p["reference"]), fmt(p.get("hdr_flip"), ".4f")))
        h.append("</div>")
    elif not (rep.get("flip") or {}).get("available", True):
        h.append("<p class='note'>HDR-FLIP: %s</p>" % e(rep["flip"].get("reason", "")))

    times = {r["name"]: r.get("render_s") for r in rep["renders"]}
    h.append("<h2>Metrics</h2><p class='note'>%s. The last column lists what each renderer of the pair models "
             "differently on this scene (a feature one side lacks, a material model, a bounce limit): a difference "
             "it explains is not an error.</p>" % e(rep["metrics_note"]))
    if rep.get("scene_notes"):
        h.append("<p class='note'>%s</p>" % "<br>".join(e(n) for n in rep["scene_notes"]))
    h.append("<table><tr><th>test</th><th>reference</th><th>PSNR dB</th><th>SSIM</th><th>relMSE</th>"
             "<th>HDR-FLIP</th><th>RMSE</th><th>max abs</th><th>test s</th><th>reference s</th><th>size</th>"
             "<th>can differ by design</th></tr>")
    for p in rep["pairs"]:
        if "error" in p:
            h.append("<tr><td>%s</td><td>%s</td><td colspan=10 class='bad'>%s</td></tr>"
                     % (e(p["test"]), e(p["reference"]), e(p["error"])))
            continue
        design = "".join("<li><b>%s</b>: %s</li>" % (e(d["renderer"]), e(d["note"])) for d in p.get("by_design", []))
        h.append("<tr><td>%s</td><td>%s</td><td class=num>%s</td><td class=num>%s</td><td class=num>%s</td>"
                 "<td class=num>%s</td><td class=num>%s</td><td class=num>%s</td><td class=num>%s</td>"
                 "<td class=num>%s</td><td>%sx%s</td><td class='design'><ul>%s</ul></td></tr>"
                 % (e(p["test"]), e(p["reference"]), fmt(p.get("psnr_db"), ".2f"), fmt(p.get("ssim"), ".4f"),
                    fmt(p.get("relmse"), ".4g"), fmt(p.get("hdr_flip"), ".4f"), fmt(p.get("rmse"), ".4g"), fmt(p.get("max_abs_error"), ".4g"),
                    fmt(times.get(p["test"]), ".2f"), fmt(times.get(p["reference"]), ".2f"),
                    p.get("width"), p.get("height"), design))
    h.append("</table><h2>Renders: times and settings</h2><table><tr><th>renderer</th><th>status</th>"
             "<th>render s</th><th>wall s</th><th>settings</th></tr>")
    for r in rep["renders"]:
        st = r.get("settings", {})
        if r.get("noise"):
            st = dict(st, noise=r["noise"])
        h.append("<tr><td>%s</td><td%s>%s</td><td class=num>%s</td><td class=num>%s</td><td><code>%s</code></td>"
                 "</tr>" % (e(r["label"]), "" if r["status"] == "ok" else " class='bad'",
                            e(r["status"] + (": " + r["reason"] if r.get("reason") else "")),
                            fmt(r.get("render_s"), ".3f"), fmt(r.get("wall_s"), ".3f"), e(json.dumps(st))))
    h.append("</table>")
    if rep.get("sequence"):
        h += render_sequence_html(rep["sequence"])
    h.append("<h2>Tool versions</h2><table>")
    for k, v in rep["versions"].items():
        h.append("<tr><th>%s</th><td>%s</td></tr>" % (e(k), e(v or "not available")))
    h.append("</table><p class='note'>Numbers: <a href='report.json'>report.json</a>. Created %s.</p>"
             % e(rep["created"]))
    data = [{"name": r["name"], "label": r["label"], "png": r["png"]} for r in shown]
    # "</" cannot appear inside the script element.
    h.append("<script type='application/json' id='renders-data'>%s</script>"
             % json.dumps(data).replace("</", "<\\/"))
    h.append("<script>%s</script></body></html>\n" % SCRIPT)
    return "\n".join(h)


def svg_plot(series, width=640, height=220, ylabel=""):
    """A line plot as inline SVG: series = [(label, colour, [(x, y), ...])]."""
    pts = [p for _, _, ps in series for p in ps if p[1] is not None]
    if not pts:
        return ""
    x0, x1 = min(p[0] for p in pts), max(p[0] for p in pts)
    y0, y1 = min(0.0, min(p[1] for p in pts)), max(p[1] for p in pts)
    if x1 == x0:
        x1 = x0 + 1
    if y1 == y0:
        y1 = y0 + 1
    L, R, T, B = 56, 12, 10, 30
    X = lambda x: L + (width - L - R) * (x - x0) / (x1 - x0)
    Y = lambda y: height - B - (height - T - B) * (y - y0) / (y1 - y0)
    o = ["<svg xmlns='http://www.w3.org/2000/svg' width='%d' height='%d' style='background:#111'>" % (width, height)]
    for k in range(5):
        yv = y0 + (y1 - y0) * k / 4
        o.append("<line x1='%d' x2='%d' y1='%.1f' y2='%.1f' stroke='#333'/><text x='4' y='%.1f' fill='#aaa' "
                 "font-size='11'>%.3g</text>" % (L, width - R, Y(yv), Y(yv), Y(yv) + 4, yv))
    o.append("<text x='%d' y='%d' fill='#aaa' font-size='11'>frame</text>" % (width // 2, height - 6))
    o.append("<text x='4' y='%d' fill='#aaa' font-size='11'>%s</text>" % (height - 6, html.escape(ylabel)))
    for i, (lab, col, ps) in enumerate(series):
        ps = [p for p in ps if p[1] is not None]
        if ps:
            o.append("<polyline fill='none' stroke='%s' stroke-width='2' points='%s'/>"
                     % (col, " ".join("%.1f,%.1f" % (X(x), Y(y)) for x, y in ps)))
        o.append("<text x='%d' y='%d' fill='%s' font-size='12'>%s</text>" % (L + 8, T + 14 + 14 * i, col,
                                                                            html.escape(lab)))
    o.append("</svg>")
    return "".join(o)


def render_sequence_html(seq):
    e = html.escape
    h = ["<h2>Sequence: frames %d-%d</h2>" % (seq["first"], seq["last"]),
         "<p class='note'>%s</p>" % e(seq["note"]), "<div class='strip'>"]
    for f in seq["frames"]:
        cell = "<div class='fig'>"
        if f.get("png"):
            cell += "<a href='%s'><img src='%s' alt='frame %d'></a>" % (e(f["png"]), e(f["png"]), f["frame"])
        if f.get("reference_png"):
            cell += "<a href='%s'><img src='%s' alt='reference %d'></a>" % (e(f["reference_png"]),
                                                                           e(f["reference_png"]), f["frame"])
        cell += "frame %d<br><small>%s dB</small></div>" % (f["frame"], fmt(f.get("psnr_db"), ".2f"))
        h.append(cell)
    h.append("</div>")
    fr = [f["frame"] for f in seq["frames"]]
    h.append("<h3>Error per frame</h3>")
    h.append(svg_plot([("PSNR against the frame's reference (dB)", "#6ece58",
                        list(zip(fr, [f.get("psnr_db") for f in seq["frames"]])))], ylabel="dB"))
    h.append("<h3>Flicker: change from the previous frame</h3>")
    h.append(svg_plot([("photonbridge (filtered)", "#fde725",
                        list(zip(fr, [f.get("change_result") for f in seq["frames"]]))),
                       ("reference (the motion itself)", "#35b7e9",
                        list(zip(fr, [f.get("change_reference") for f in seq["frames"]])))], ylabel="RMS change"))
    sm = seq.get("summary", {})
    h.append("<p class='note'>Mean PSNR %s dB, mean relMSE %s; flicker: result %s, reference %s, excess %s "
             "(RMS change between consecutive frames, scene-linear; excess = result - reference).</p>"
             % (fmt(sm.get("mean_psnr_db"), ".2f"), fmt(sm.get("mean_relmse"), ".4g"),
                fmt(sm.get("flicker_result"), ".4g"), fmt(sm.get("flicker_reference"), ".4g"),
                fmt(sm.get("flicker_excess"), ".4g")))
    return h


def on_term(sig, frame):
    raise Terminated()


if __name__ == "__main__":
    # photonbridge validate passes SIGINT/SIGTERM on to this script's process
    # group (the renderers remove their own temporaries) and prints the one
    # line itself; a folder this run created goes with it.
    signal.signal(signal.SIGTERM, on_term)
    try:
        sys.exit(main(sys.argv[1:]))
    except (KeyboardInterrupt, Terminated) as e:
        if CREATED:
            shutil.rmtree(CREATED, ignore_errors=True)
        sys.exit(143 if isinstance(e, Terminated) else 130)
