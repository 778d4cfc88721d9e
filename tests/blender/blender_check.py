#!/usr/bin/env python3
"""The Blender render engine (exporters/blender/photonbridge), headless with
the Debian Blender (`blender -b --factory-startup`, the add-on enabled from
the checkout through BLENDER_USER_SCRIPTS, the binary through
PHOTONBRIDGE_BIN):

  register     the add-on registers and unregisters cleanly, twice;
  writer       for every sample .blend, the add-on's glTF and Blender's own
               exporter's load in photonbridge with the same triangle count,
               bounds, materials, lights and camera view (`info --json`),
               and small renders of the static samples agree within noise;
  validator    the written files pass the Khronos glTF-Validator;
  f12          `blender -b S.blend -E PHOTONBRIDGE -f 1` writes exactly the
               pixels `photonbridge render` gives for the written file (same
               seed); the multilayer EXR has Blender's channel names for the
               registered passes; a border render equals that part of the
               full render;
  cancel       Ctrl-C (SIGINT) to Blender mid-render stops the CLI: no
               process left, no output, no temporary file;
  animation    `-a` of a 3-frame animation gives 3 different frames that
               follow the motion, frame by frame (the three still renders
               jobs of one kept `photonbridge batch -` session) and as one
               sequence;
  vcolor       colour attributes on the base colour (a Color Attribute node
               into a Principled BSDF, an Attribute node into a Diffuse BSDF)
               are written as COLOR_0 of those primitives only, and render as
               the same colours given as the sockets' constants do;
  mix          Mix Shader(Transparent, Principled) with a constant and an
               image Fac, Add Shader(Emission, Principled) render as the
               Principled BSDFs with that Alpha and Emission do, with no
               warning;
  mapping      an image read through a Mapping node (location, Z rotation,
               scale) renders pixel for pixel as the same mapping applied to
               the mesh's UVs (KHR_texture_transform in the written file);
  lightnodes   a light whose node tree's Emission has a colour and strength
               renders as the light with that colour and power (Cycles
               multiplies them in: measured 2 x (1, 0.5, 0.25) in Cycles 3.4);
  groups       Principled BSDFs inside node groups (exposed inputs set on the
               group node, a nested group, a reroute) render as the same
               BSDFs without groups, with no warning;
  unsupported  a material with an untranslated node renders, with a warning
               naming the material and the node;
  badinput     a missing binary, no camera, no lights, only an empty mesh, a
               0-pixel image, an unwritable output path and a CLI killed
               mid-render each give their message, never a hang, and leave no
               output or process; a negative light is left out with a
               warning (the CLI refused the whole file before);
  everyday     what artists' scenes hold and Cycles renders as bl_scenes.py's
               references: a material without nodes and an object without
               one (Diffuse BSDFs), the view layer's Material Override (was
               left out), a camera and a spot light under a mirrored parent
               (they looked and shone backwards: black), an image sequence's
               frame (was magenta), a material whose only output targets EEVEE
               and a light with nothing on its Light Output (black in Cycles;
               were rendered).

Under PB_VK_VALIDATION=1 (the test suite's) a part's first F12 render runs
with the Vulkan validation layers and its later ones without
(PB_VK_VALIDATION=0): on lavapipe the layers cost 1-2 s of CPU a process on
Blender materials (checking the large shader modules) whatever the scene,
and the engine drives the same passes each time, so the rest check only the
pictures. badinput and cancel keep the layers on every
run (their error paths and torn-down devices are what the layers check).

usage: blender_check.py PHOTONBRIDGE EXR_PROBE ROOT WORKDIR PART
Exit 77 (skipped) when Blender or a Vulkan device is missing."""
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time

EXE, PROBE, ROOT, WORK, PART = sys.argv[1:6]
EXE, PROBE = os.path.abspath(EXE), os.path.abspath(PROBE)
HERE = os.path.join(ROOT, "tests", "blender")
SAMPLES = ["cornell_box", "cornell_caustics", "ring", "spot_room", "sun_atrium", "cornell_box_moving_light",
           "cornell_caustics_moving_sphere", "sun_atrium_flythrough"]
STATIC = ["cornell_box", "cornell_caustics", "ring", "spot_room", "sun_atrium"]
# Small and quick (lavapipe on 2 cores): the engine's settings and the same
# options for the CLI (exporters/blender/photonbridge/settings.py cli_args);
# progressive maps and Blender's Max Bounces on (F12's defaults, stated).
QUICK = {"photons": 8192, "iterations": 2, "spp": 2, "seed": 5, "preview_interval": 0, "progressive": 1,
         "blender_bounces": 1}
QUICK_CLI = ["--photons", "8192", "--iterations", "2", "--spp", "2", "--first-bounce", "traced",
             "--tracer", "bvh", "--seed", "5", "--max-bounces", "13", "--progressive"]  # Blender's default Max Bounces 12
failures = []
# Which Blender: Debian's `blender` (3.4), or with PB_BLENDER_PYTHON set, the
# bpy module of that interpreter (Blender 4.5 LTS in tools/bpy45) driven
# through bpy_blender.py, the same command line over the module.
BPY = os.environ.get("PB_BLENDER_PYTHON")
BLENDER = [BPY, os.path.join(HERE, "bpy_blender.py")] if BPY else ["blender"]


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def blender_env(extra=None):
    env = dict(os.environ)
    env["PATH"] = ":".join(p for p in env.get("PATH", "").split(":") if "pyenv" not in p)
    scripts = os.path.join(WORK, "scripts")
    os.makedirs(os.path.join(scripts, "addons"), exist_ok=True)
    link = os.path.join(scripts, "addons", "photonbridge")
    if not os.path.islink(link):
        os.symlink(os.path.join(ROOT, "exporters", "blender", "photonbridge"), link)
    env["BLENDER_USER_SCRIPTS"] = scripts
    env["PHOTONBRIDGE_BIN"] = EXE
    env["TMPDIR"] = os.path.join(WORK, "tmp")  # Blender's temporary folder: checked empty after each run
    os.makedirs(env["TMPDIR"], exist_ok=True)
    if extra:
        env.update(extra)
    return env


def blender(args, setup=None, env=None, timeout=600, check_rc=True):
    """Runs Blender headless: [BLEND --python bl_setup.py] ARGS [-- SETTINGS]
    (setup = (BLEND, SETTINGS): the add-on enabled and set up before ARGS,
    which Blender runs in order: -o, -F, then -f/-a)."""
    argv = BLENDER + ["-b", "--factory-startup", "--python-exit-code", "1"]
    if setup is not None:
        argv += [setup[0], "--python", os.path.join(HERE, "bl_setup.py")]
    argv += args
    if setup is not None and setup[1]:
        argv += ["--"] + ["%s=%s" % kv for kv in setup[1].items()]
    p = subprocess.run(argv, capture_output=True, text=True, env=env or blender_env(), timeout=timeout)
    if check_rc and p.returncode != 0:
        print(" ".join(argv))
        print(p.stdout[-4000:])
        print(p.stderr[-2000:])
    return p


def tmp_left():
    d = os.path.join(WORK, "tmp")
    left = []
    for root, dirs, files in os.walk(d):
        left += [os.path.join(root, f) for f in files]
        left += [os.path.join(root, x) for x in dirs if x.startswith("photonbridge_")]
    return left


def fresh(sub):
    d = os.path.join(WORK, sub)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    return d


def exr(path):
    p = subprocess.run([PROBE, path], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(p.stderr)
    return json.loads(p.stdout)


def info(path):
    p = subprocess.run([EXE, "info", path, "--json", "-", "-q"], capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(p.stderr)
    return json.loads(p.stdout)


def sample_blend(name):
    return os.path.join(ROOT, "samples", name, name + ".blend")


def write_with_addon(blend, out, *extra):
    p = blender([blend, "-P", os.path.join(ROOT, "exporters", "blender", "export_photonbridge.py"), "--", out] +
                list(extra))
    return p.returncode == 0 and os.path.isfile(out), p.stdout


def close(a, b, tol):
    return abs(a - b) <= tol * max(1.0, abs(a), abs(b))


def same_values(x, y, tol):
    """Equal JSON values, numbers within tol (relative above 1)."""
    if isinstance(x, dict):
        if set(x) != set(y):
            print("  keys differ:", sorted(set(x) ^ set(y)))
            return False
        return all(same_values(x[k], y[k], tol) for k in x)
    if isinstance(x, list):
        return len(x) == len(y) and all(same_values(p, q, tol) for p, q in zip(x, y))
    if isinstance(x, (int, float)) and not isinstance(x, bool) and isinstance(y, (int, float)):
        if not close(x, y, tol):
            print("  %r != %r" % (x, y))
            return False
        return True
    if x != y:
        print("  %r != %r" % (x, y))
    return x == y


# ---- parts ---------------------------------------------------------------------


def part_register():
    p = blender(["-P", os.path.join(HERE, "bl_register.py")])
    print(p.stdout[p.stdout.find("ok   "):][:4000] if "ok   " in p.stdout else p.stdout[-2000:])
    check(p.returncode == 0 and "0 failed" in p.stdout, "register/unregister: every check passed")


def compare_info(name, a, b):
    """The add-on's glTF (a) against Blender's exporter's (b), as
    photonbridge loads them."""
    check(a["triangles"] == b["triangles"], "%s: triangles %d = %d" % (name, a["triangles"], b["triangles"]))
    ok = all(close(x, y, 1e-4) for k in ("bounds_min", "bounds_max") for x, y in zip(a[k], b[k]))
    check(ok, "%s: bounds %s..%s = %s..%s" % (name, a["bounds_min"], a["bounds_max"], b["bounds_min"],
                                               b["bounds_max"]))
    ma, mb = (sorted(x["materials"], key=lambda m: m["name"]) for x in (a, b))
    same = len(ma) == len(mb) and all(same_values(x, y, 1e-5) for x, y in zip(ma, mb))
    check(same, "%s: %d materials, the same names, kinds, colours, factors and textures" % (name, len(ma)))
    la, lb = (sorted(x["lights"], key=lambda m: m["name"]) for x in (a, b))
    same = len(la) == len(lb) and all(same_values(x, y, 1e-4) for x, y in zip(la, lb))
    check(same, "%s: %d lights, the same type, intensity, position, direction and cone" % (name, len(la)))
    ca, cb = a["cameras"], b["cameras"]
    same = len(ca) == len(cb) == 1 and all(
        close(p, q, 1e-4) for k in ("position", "forward", "up", "window") for p, q in zip(ca[0][k], cb[0][k])) and \
        close(ca[0]["aspect"], cb[0]["aspect"], 1e-5) and close(ca[0]["znear"], cb[0]["znear"], 1e-5) and \
        close(ca[0]["zfar"], cb[0]["zfar"], 1e-5)
    check(same, "%s: the camera's position, frame, view window and clip range" % name)


def strip_extension(src, dst):
    """src without PHOTONBRIDGE_blender (but on cameras), written to dst
    beside it (its .bin and images resolve the same)."""
    with open(src) as f:
        doc = json.load(f)
    doc.get("extensions", {}).pop("PHOTONBRIDGE_blender", None)
    for key in ("nodes", "materials"):
        for o in doc.get(key, []):
            o.get("extensions", {}).pop("PHOTONBRIDGE_blender", None)
    if not any("PHOTONBRIDGE_blender" in c.get("extensions", {}) for c in doc.get("cameras", [])):
        doc["extensionsUsed"] = [e for e in doc.get("extensionsUsed", []) if e != "PHOTONBRIDGE_blender"]
    with open(dst, "w") as f:
        json.dump(doc, f)
    return dst


def part_writer():
    d = fresh("writer")
    for name in SAMPLES:
        ours, theirs = os.path.join(d, name, "addon.gltf"), os.path.join(d, name, "blender.gltf")
        p = blender([sample_blend(name), "-P", os.path.join(HERE, "bl_export_blender.py"), "--", theirs, ours])
        ok = p.returncode == 0 and os.path.isfile(ours)
        check(ok, "%s: the add-on's writer wrote %s" % (name, ours))
        check(p.returncode == 0 and os.path.isfile(theirs), "%s: Blender's exporter wrote %s" % (name, theirs))
        if not (ok and os.path.isfile(theirs)):
            continue
        # The extension replaces the plain glTF form of what it describes
        # (Blender's materials as Cycles renders them, Blender's light units
        # and world), so photonbridge renders the add-on's file like Cycles,
        # not like Blender's exporter's: what must match that exporter is the
        # plain form other viewers see, i.e. the file without the extension
        # (the camera's kept: the same view either way). The full file must
        # load with every material and light from the extension.
        full = info(ours)
        check(all(m["model"] != "gltf" for m in full["materials"]) and full["materials"],
              "%s: every material read from the extension (%s)" % (
                  name, ", ".join(sorted({m["model"] for m in full["materials"]}))))
        # Its lights from PHOTONBRIDGE_blender.light: Blender's watts and
        # W/m^2 and Cycles' spot falloff (the plain form: candela and lux).
        check(full["lights"] and all(l.get("blender_units") and ("file_watts" in l or "file_w_m2" in l) and
                                     l.get("spot_falloff", "cycles") in ("cycles", "cycles4") for l in full["lights"]),
              "%s: every light read from the extension, in Blender's units" % name)
        ours = strip_extension(ours, os.path.join(d, name, "addon_plain.gltf"))
        compare_info(name, info(ours), info(theirs))
        if name not in STATIC:
            continue
        # A small render of both with the same seed: what differs is only the
        # files' vertex and triangle order (other BVHs, so other photon
        # paths), which moves the mean by 0.06 % on sun_atrium, while two
        # seeds of one file differ by up to 5 % at this size.
        for f in (ours, theirs):
            subprocess.run([EXE, "render", f, "-o", f[:-5] + ".exr", "--width", "48", "--photons", "16384",
                            "--iterations", "2", "--spp", "2", "--seed", "1", "-q"], check=False)
        a, b = exr(ours[:-5] + ".exr"), exr(theirs[:-5] + ".exr")
        ma = sum(sum(a["channels"][c]) for c in "RGB")
        mb = sum(sum(b["channels"][c]) for c in "RGB")
        rel = abs(ma - mb) / max(mb, 1e-9)
        check(mb > 0 and rel < 0.01, "%s: mean beauty of the two renders within 1%% (%.2f%%)" % (name, 100 * rel))


def part_instances():
    """Instances: each mesh written once, one node per instance."""
    scenes = fresh("inst_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    out = os.path.join(WORK, "instances", "instances.gltf")
    ok, text = write_with_addon(os.path.join(scenes, "instances.blend"), out)
    check(ok, "the instances scene is written")
    if not ok:
        print(text[-2000:])
        return
    with open(out) as f:
        doc = json.load(f)
    crates = [n for n in doc["nodes"] if "instance of" in n.get("name", "") and "mesh" in n]
    coll = {n["mesh"] for n in crates if n["name"].startswith("CrateInstance")}
    gn = {n["mesh"] for n in crates if n["name"].startswith("Points")}
    check(len(crates) == 7 and len(coll) == 1 and len(gn) == 1 and len(doc["meshes"]) == 3,
          "3 collection instances share one mesh, 4 geometry-node instances another (%d nodes, %d meshes)"
          % (len(crates), len(doc["meshes"])))
    xs = sorted(round(n["translation"][0], 3) for n in crates)
    check(xs == [-2.0, -1.5, -1.5, 0.0, 1.5, 1.5, 2.0], "at their places (x %s)" % xs)
    check(info(out)["triangles"] == 2 + 7 * 12, "photonbridge loads 2 + 7 x 12 triangles")


def part_validator():
    vdir = os.path.join(ROOT, "tools", "node_modules", "gltf-validator")
    if not shutil.which("node") or not os.path.isdir(vdir):
        print("skip: the Khronos glTF-Validator is not installed (npm gltf-validator in tools/; "
              "scripts/install-deps.sh installs it where npm is available)")
        return 77
    d = fresh("validator")
    for name in STATIC + ["cornell_box_moving_light"]:
        out = os.path.join(d, name, name + ".gltf")
        ok, _ = write_with_addon(sample_blend(name), out)
        p = subprocess.run(["node", os.path.join(HERE, "validate_gltf.js"), vdir, out], capture_output=True, text=True)
        print(p.stdout.strip())
        check(ok and p.returncode == 0 and " 0 errors, 0 warnings" in p.stdout,
              "%s: glTF-Validator: no errors, no warnings" % name)
    # The animated hand-off of "Render Animation as One Sequence".
    out = os.path.join(d, "anim", "cornell_caustics_moving_sphere.gltf")
    ok, _ = write_with_addon(sample_blend("cornell_caustics_moving_sphere"), out, "--animation")
    p = subprocess.run(["node", os.path.join(HERE, "validate_gltf.js"), vdir, out], capture_output=True, text=True)
    print(p.stdout.strip())
    check(ok and p.returncode == 0 and " 0 errors, 0 warnings" in p.stdout,
          "the animated hand-off (frames as node animation): no errors, no warnings")
    if ok:
        doc = info(out)
        # frames 0-48 at 24 fps: 2 s of animation
        check(doc.get("animations") == 1 and close(doc.get("animation_end_s", 0), 2.0, 1e-5),
              "the animated hand-off has the frame range as 0 .. %s s of animation" % doc.get("animation_end_s"))


VALIDATE_EVERY_RUN = ("badinput", "cancel")
f12_runs = []  # the F12 renders of this part so far: validated, or not


def render_f12(d, blend, settings, fmt="OPEN_EXR_MULTILAYER", frames=("-f", "1"), env=None, timeout=600):
    settings = dict(settings)
    out = os.path.join(d, "f_####")
    env = dict(env or blender_env())
    validating = env.get("PB_VK_VALIDATION", "0") not in ("", "0")
    if validating and f12_runs and PART not in VALIDATE_EVERY_RUN:
        env["PB_VK_VALIDATION"] = "0"
        validating = False
    f12_runs.append(validating)
    p = blender(["-o", out, "-F", fmt, "-x", "1"] + list(frames), setup=(blend, settings), env=env,
                timeout=timeout, check_rc=False)
    return p


def part_f12():
    d = fresh("f12")
    name = "spot_room"  # a texture, a spot light
    settings = dict(QUICK, percent="5", pass_z="1")
    p = render_f12(d, sample_blend(name), settings)
    out = os.path.join(d, "f_0001.exr")
    check(p.returncode == 0 and os.path.isfile(out), "F12 headless wrote %s" % out)
    if not os.path.isfile(out):
        print(p.stdout[-3000:])
        return
    f12 = exr(out)
    # The same file by the headless writer, rendered by the CLI at the same size.
    gltf = os.path.join(d, "scene.gltf")
    ok, _ = write_with_addon(sample_blend(name), gltf)
    w, h = f12["width"], f12["height"]
    cli_out = os.path.join(d, "cli.exr")
    subprocess.run([EXE, "render", gltf, "-o", cli_out, "--width", str(w), "--height", str(h), "--blender-layer",
                    "ViewLayer", "-q"] + QUICK_CLI, check=False)
    cli = exr(cli_out)
    # Equal to float rounding (1e-5 of each channel's peak), not bit for
    # bit: the photon store's order follows the device's scheduling
    # (tests/pylib/pbcheck.py, ROUNDING); a different setting or pass differs
    # by far more.
    rel = 0.0
    for c in "RGBA":
        a, b = f12["channels"]["ViewLayer.Combined." + c], cli["channels"]["ViewLayer.Combined." + c]
        peak = max(max((abs(v) for v in a), default=0.0), 1e-6)
        rel = max(rel, max((abs(x - y) for x, y in zip(a, b)), default=0.0) / peak if len(a) == len(b) else 1e9)
    check(ok and rel <= 1e-5, "F12's Combined equals `photonbridge render` of the written file to float rounding "
          "(%dx%d, largest difference %.3g of the peak)" % (w, h, rel))
    chans = set(f12["channels"])
    want = {"ViewLayer.Combined." + c for c in "RGBA"} | {"ViewLayer.Depth.Z"} | \
        {"ViewLayer.Normal." + c for c in "XYZ"} | \
        {"ViewLayer.%s.%s" % (pp, c) for pp in ("Emit", "Direct", "Indirect", "Caustic", "Albedo") for c in "RGB"}
    check(want <= chans, "the multilayer EXR has Blender's channels for every pass: %s" % sorted(chans))
    check(sum(f12["channels"]["ViewLayer.Direct.R"]) > 0 and sum(f12["channels"]["ViewLayer.Indirect.G"]) > 0,
          "Direct and Indirect hold light")
    check(not tmp_left(), "no temporary files left (%s)" % tmp_left())
    # Two view layers: Blender calls render() once per layer, and each call
    # fills its own layer of the result (begin_result(layer=...)); an engine
    # that loads its EXR into every layer blanks the others (the first layer
    # of the file came out black).
    dl = fresh("f12_layers")
    render_f12(dl, sample_blend(name), dict(settings, layers="Second"))
    lout = os.path.join(dl, "f_0001.exr")
    lay = exr(lout) if os.path.isfile(lout) else {"channels": {}}
    for ln in ("ViewLayer", "Second"):
        ch = lay["channels"].get(ln + ".Combined.G", [])
        rel = max((abs(x - y) for x, y in zip(ch, f12["channels"]["ViewLayer.Combined.G"])), default=1e9) / \
            max(max(f12["channels"]["ViewLayer.Combined.G"]), 1e-6) if len(ch) == w * h else 1e9
        check(rel <= 1e-5, "two view layers: layer %s equals the one-layer render to float rounding (%.3g)"
              % (ln, rel))
    # A border render (crop to border) equals that part of the full render.
    border = (0.25, 0.2, 0.75, 0.7)
    db = fresh("f12_border")
    p = render_f12(db, sample_blend(name), dict(settings, border="%g,%g,%g,%g" % border, crop="1"))
    bout = os.path.join(db, "f_0001.exr")
    check(os.path.isfile(bout), "a border render wrote its file")
    if os.path.isfile(bout):
        b = exr(bout)
        x0, x1 = int(border[0] * w), int(border[2] * w)
        y0, y1 = int(border[1] * h), int(border[3] * h)
        top = h - y1
        check(b["width"] == x1 - x0 and b["height"] == y1 - y0, "the border is %dx%d" % (x1 - x0, y1 - y0))
        worst = 0.0
        for c in "RGB":
            full, part = f12["channels"]["ViewLayer.Combined." + c], b["channels"]["ViewLayer.Combined." + c]
            peak = max(max((abs(v) for v in full), default=0.0), 1e-6)
            for y in range(b["height"]):
                for x in range(b["width"]):
                    worst = max(worst, abs(full[(y + top) * w + x + x0] - part[y * b["width"] + x]) / peak)
        check(worst <= 1e-5, "the border render equals the full render there to float rounding (largest "
              "difference %.3g of the peak)" % worst)


def child_pids(pid):
    out = []
    try:
        for t in os.listdir("/proc/%d/task" % pid):
            with open("/proc/%d/task/%s/children" % (pid, t)) as f:
                out += [int(x) for x in f.read().split()]
    except OSError:
        pass
    return out


def alive(pid):
    try:
        with open("/proc/%d/stat" % pid) as f:
            return f.read().split()[2] != "Z"
    except OSError:
        return False


def start_long_render(d, blend, extra_env=None):
    """Blender rendering a long F12 (many photon maps); returns (process, the
    photonbridge child's pid) once the first map is done."""
    settings = dict(QUICK, iterations=400, spp=400, percent="10")
    argv = BLENDER + ["-b", "--factory-startup", "--python-exit-code", "1", blend, "--python",
            os.path.join(HERE, "bl_setup.py"), "-o", os.path.join(d, "f_####"), "-F", "OPEN_EXR", "-f", "1", "--"] + \
        ["%s=%s" % kv for kv in settings.items()]
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env=blender_env(extra_env), bufsize=1)
    lines, child = [], None
    t0 = time.time()
    for line in proc.stdout:
        lines.append(line)
        if "photon map 1/" in line or "photon map 2/" in line:
            kids = [k for k in child_pids(proc.pid) if alive(k)]
            child = kids[0] if kids else None
            break
        if time.time() - t0 > 300:
            break
    return proc, child, lines


def finish(proc, lines, timeout=120):
    t0 = time.time()
    try:
        rest, _ = proc.communicate(timeout=timeout)
        lines.append(rest)
        return True, "".join(lines), time.time() - t0
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        return False, "".join(lines), time.time() - t0


def part_cancel():
    d = fresh("cancel")
    proc, child, lines = start_long_render(d, sample_blend("cornell_box"))
    check(child is not None, "the render started photonbridge (pid %s)" % child)
    proc.send_signal(signal.SIGINT)  # Blender's Ctrl-C: test_break() turns true
    ended, out, secs = finish(proc, lines)
    check(ended, "Blender returned %.1f s after Ctrl-C" % secs)
    check(proc.returncode is not None and proc.returncode >= 0,
          "Blender exited by itself (status %s), not by a signal" % proc.returncode)
    time.sleep(0.5)
    check(child is not None and not alive(child), "no photonbridge process left")
    check(not os.listdir(d), "no output written (%s)" % os.listdir(d))
    check(not tmp_left(), "no temporary file left (%s)" % tmp_left())


def centroid_x(img):
    """Mean x of the pixels where red dominates (the red box)."""
    r, g = img["channels"]["R"], img["channels"]["G"]
    w = img["width"]
    xs = [i % w for i, (a, b) in enumerate(zip(r, g)) if a > 2.0 * b and a > 1e-3]
    return sum(xs) / len(xs) if xs else None


def part_animation():
    scenes = fresh("anim_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    # The frames of -a (one still render each) run as jobs of one kept
    # `photonbridge batch -` session (cli.Job): the binary is started once.
    calls = os.path.join(WORK, "anim_calls.txt")
    wrapper = os.path.join(WORK, "anim_photonbridge")
    with open(wrapper, "w") as f:
        f.write("#!/bin/sh\necho \"$@\" >> '%s'\nexec '%s' \"$@\"\n" % (calls, EXE))
    os.chmod(wrapper, 0o755)
    for mode in ("frames", "sequence"):
        d = fresh("anim_" + mode)
        settings = dict(QUICK, animation_sequence="1" if mode == "sequence" else "0")
        if os.path.exists(calls):
            os.remove(calls)
        p = render_f12(d, os.path.join(scenes, "moving.blend"), settings, fmt="OPEN_EXR", frames=("-s", "1", "-e", "3",
                                                                                               "-a"),
                       env=blender_env({"PHOTONBRIDGE_BIN": wrapper}))
        started = open(calls).read().splitlines() if os.path.exists(calls) else []
        if mode == "frames":
            check(started == ["batch -"], "frames: the 3 still renders ran in one photonbridge session (%s)" % started)
        files = sorted(f for f in os.listdir(d) if f.endswith(".exr"))
        check(files == ["f_0001.exr", "f_0002.exr", "f_0003.exr"], "%s: -a wrote 3 frames (%s)" % (mode, files))
        if len(files) != 3:
            print(p.stdout[-3000:])
            continue
        imgs = [exr(os.path.join(d, f)) for f in files]
        xs = [centroid_x(i) for i in imgs]
        differ = all(imgs[i]["channels"]["R"] != imgs[i + 1]["channels"]["R"] for i in range(2))
        check(differ, "%s: the 3 frames differ" % mode)
        check(None not in xs and xs[0] < xs[1] < xs[2], "%s: the box moves right: centroid x %s" % (mode, xs))
        check(not tmp_left(), "%s: no temporary files left" % mode)


def part_unsupported():
    scenes = fresh("unsup_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    d = fresh("unsupported")
    p = render_f12(d, os.path.join(scenes, "unsupported.blend"), QUICK, fmt="OPEN_EXR")
    check(os.path.isfile(os.path.join(d, "f_0001.exr")), "the scene renders")
    check("material 'Noisy': node 'Noise Texture' (Noise Texture)" in p.stdout,
          "the warning names the material and the node")
    n = sum("node 'Noise Texture'" in line for line in p.stdout.splitlines() if line.startswith("Warning"))
    check(n == 1, "the warning is in the report once, not repeated from the CLI (%d)" % n)
    # A scene lit by its world alone is lit: no "no lights" warning, and a
    # grey world of strength 2 gives the floor a radiance near 0.5 * 2 * albedo.
    d = fresh("worldlit")
    p = render_f12(d, os.path.join(scenes, "worldlit.blend"), QUICK, fmt="OPEN_EXR")
    check("no lights" not in p.stdout + p.stderr, "world-lit scene: no 'no lights' warning")
    img = exr(os.path.join(d, "f_0001.exr")) if os.path.isfile(os.path.join(d, "f_0001.exr")) else None
    r = img["channels"]["R"] if img else []
    mean = sum(r) / len(r) if r else 0.0
    check(mean > 0.2, "world-lit scene: lit (mean R %.3f > 0.2)" % mean)


def part_mapping():
    scenes = fresh("mapping_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    gltf = os.path.join(WORK, "mapping.gltf")
    ok, _ = write_with_addon(os.path.join(scenes, "mapping.blend"), gltf)
    j = json.load(open(gltf)) if ok else {}
    xf = [m["extensions"]["PHOTONBRIDGE_blender"].get("textures", {}).get("baseColor", {}).get("extensions", {})
          .get("KHR_texture_transform") for m in j.get("materials", []) if m.get("name") == "Tiles"]
    check(bool(xf and xf[0]) and "KHR_texture_transform" in j.get("extensionsUsed", []),
          "the Mapping node is written as KHR_texture_transform (%s)" % xf)
    same_means(scenes, "mapping", "the mapped texture renders as the mapped UVs do", pixels=True)


def part_lightnodes():
    scenes = fresh("lightnodes_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    same_means(scenes, "lightnodes", "the light's node tree scales it as Cycles does")


def same_means(scenes, name, what, tol=0.01, pixels=False):
    """Renders NAME.blend and NAME_ref.blend (bl_scenes.py) through F12 and
    checks NAME renders with no untranslated node and the same mean RGB as
    its reference within tol."""
    means = {}
    for n in (name, name + "_ref"):
        d = fresh(n)
        p = render_f12(d, os.path.join(scenes, n + ".blend"), QUICK, fmt="OPEN_EXR")
        if n == name:
            bad = [line for line in p.stdout.splitlines() if line.startswith("Warning") and
                   ("not translated" in line or "grey Principled" in line or "is written" in line)]
            check(not bad, "%s: no node is reported untranslated %s" % (name, bad))
        f = os.path.join(d, "f_0001.exr")
        img = exr(f) if os.path.isfile(f) else None
        means[n] = [sum(img["channels"][c]) / len(img["channels"][c]) for c in "RGB"] if img else [0, 0, 0]
        if pixels:
            means[n + "_img"] = img
    if pixels:
        # Pixel for pixel: the mean absolute difference over the mean (a
        # wrong mapping moves the checker: tens of per cent).
        x, y = means[name + "_img"], means[name + "_ref_img"]
        d = 1.0
        if x and y and len(x["channels"]["G"]) == len(y["channels"]["G"]):
            d = max(sum(abs(p - q) for p, q in zip(x["channels"][c], y["channels"][c])) /
                    max(sum(y["channels"][c]), 1e-9) for c in "RGB")
        check(d <= tol, "%s: pixels differ by %.3f %% of the mean" % (what, 100 * d))
    a, b = means[name], means[name + "_ref"]
    worst = max(abs(x / y - 1) if y > 0 else 1 for x, y in zip(a, b))
    check(worst <= tol, "%s: mean RGB %s against %s (largest %.2f %%)"
          % (what, ["%.4f" % x for x in a], ["%.4f" % x for x in b], 100 * worst))


def part_floattex():
    scenes = fresh("floattex_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    gltf = os.path.join(WORK, "floattex.gltf")
    ok, _ = write_with_addon(os.path.join(scenes, "floattex.blend"), gltf)
    j = json.load(open(gltf)) if ok else {}
    fl = [j["images"][t["extensions"]["PHOTONBRIDGE_blender"]["source"]]["uri"] for t in j.get("textures", [])
          if "PHOTONBRIDGE_blender" in t.get("extensions", {})]
    check(len(fl) == 2 and all(u.endswith(".exr") for u in fl),
          "both float images are written at full precision beside their 8-bit fallbacks (%s)" % fl)
    # Written beside its own image file: the EXR is kept as it is, not
    # copied onto itself (SameFileError before).
    src = os.path.join(scenes, "paint.exr")
    before = open(src, "rb").read()
    here = os.path.join(scenes, "floattex_here.gltf")
    ok2, out2 = write_with_addon(os.path.join(scenes, "floattex.blend"), here)
    check(ok2 and "Traceback" not in out2 and open(src, "rb").read() == before,
          "written into the folder of its own EXR texture, the file is kept and the glTF written")
    same_means(scenes, "floattex", "float image textures render as their values do")
    # An image file that is not there: magenta, as in Cycles, with a warning.
    ok3, out3 = write_with_addon(os.path.join(scenes, "missingtex.blend"), os.path.join(WORK, "missingtex.gltf"))
    check(ok3 and "image 'gone.png': no pixels (missing file?); rendered magenta, as Cycles does" in out3,
          "a missing image file is reported and written as magenta")
    same_means(scenes, "missingtex", "a missing image renders as magenta does")


def part_vcolor():
    scenes = fresh("vcolor_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    gltf = os.path.join(WORK, "vcolor.gltf")
    ok, _ = write_with_addon(os.path.join(scenes, "vcolor.blend"), gltf)
    check(ok, "the writer wrote vcolor.gltf")
    if not ok:
        return
    j = json.load(open(gltf))
    mats = {m["name"]: m for m in j["materials"]}
    ext = lambda n: mats[n]["extensions"]["PHOTONBRIDGE_blender"]
    check(ext("PaintedRed").get("vertexColor") == "baseColor" and ext("PaintedBlue").get("vertexColor") == "color"
          and "vertexColor" not in ext("Plain"), "the extension names the input each attribute drives")
    with_col = sorted(j["materials"][p["material"]]["name"] for me in j["meshes"] for p in me["primitives"]
                      if "COLOR_0" in p["attributes"])
    check(with_col == ["PaintedBlue", "PaintedRed"], "COLOR_0 only on the painted primitives (%s)" % with_col)
    same_means(scenes, "vcolor", "the attributes render as the constants do")


def part_groups():
    scenes = fresh("groups_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    same_means(scenes, "groups", "the grouped BSDFs render as the plain ones")


def part_everyday():
    scenes = fresh("everyday_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    same_means(scenes, "plainmat", "a material without nodes and no material render as Cycles' Diffuse BSDFs",
               pixels=True)
    same_means(scenes, "override", "the view layer's Material Override renders on every object", pixels=True)
    # Pixel for pixel (both unmirrored: Cycles mirrors the image, photonbridge
    # cannot, and says so).
    same_means(scenes, "mirrored", "a camera and a spot light under a mirrored parent render as unmirrored",
               pixels=True)
    same_means(scenes, "sequence", "an image sequence renders its frame's file", pixels=True)
    same_means(scenes, "outputs", "an EEVEE-only Material Output and an empty Light Output render black")


def part_mix():
    scenes = fresh("mix_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    same_means(scenes, "mix", "the mixed and added shaders render as the single Principled BSDFs")


# Cycles 3.4 (blender -b --factory-startup, CPU, 128 samples, no denoising,
# 64 x 48, Filmic, EXR linear) channel means of bl_scenes.py's sky scenes:
# a floor and a cube under a Nishita Sky Texture, no lamp.
SKY_CYCLES = {"sky": [5.2734, 4.0883, 2.8857],        # Blender's defaults: sun 15 deg up, disc on
              "sky_low": [1.5893, 1.1431, 0.7754]}    # sun 5 deg up, rotated 1 rad
SKY_SETTINGS = dict(QUICK, photons=65536, spp=8)  # QUICK's 8192 photons: the 5-degree sun 3.8 % dark
SKY_TOL = 0.04  # measured with SKY_SETTINGS: within 1 %; the untranslated sky rendered 0.4 % as bright


def part_sky():
    scenes = fresh("sky_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    gltf = os.path.join(WORK, "sky.gltf")
    ok, _ = write_with_addon(os.path.join(scenes, "sky.blend"), gltf)
    check(ok, "the writer wrote sky.gltf")
    if ok:
        j = json.load(open(gltf))
        world = j["extensions"]["PHOTONBRIDGE_blender"]["world"]
        env = world.get("environment", {})
        check(env.get("uri", "").endswith(".hdr") and os.path.isfile(os.path.join(WORK, env["uri"])),
              "the sky is written as an .hdr environment (%s)" % env.get("uri"))
        suns = [n["extensions"]["PHOTONBRIDGE_blender"]["light"] for n in j["nodes"]
                if "light" in n.get("extensions", {}).get("PHOTONBRIDGE_blender", {})]
        check(len(suns) == 1 and suns[0]["type"] == "SUN" and abs(suns[0]["angle"] - 0.00951204) < 1e-6
              and 100 < suns[0]["strength"] < 150,
              "the sun disc is one soft sun of the node's sun size (%s)" % suns)
    for name, ref in SKY_CYCLES.items():
        d = fresh(name)
        p = render_f12(d, os.path.join(scenes, name + ".blend"), SKY_SETTINGS, fmt="OPEN_EXR")
        check("not translated" not in p.stdout, "%s: no node is reported untranslated" % name)
        f = os.path.join(d, "f_0001.exr")
        img = exr(f) if os.path.isfile(f) else None
        got = [sum(img["channels"][c]) / len(img["channels"][c]) for c in "RGB"] if img else [0, 0, 0]
        worst = max(abs(x / y - 1) for x, y in zip(got, ref))
        check(worst <= SKY_TOL, "%s renders as Cycles 3.4 does: mean RGB %s against %s (largest %.2f %%)"
              % (name, ["%.4f" % x for x in got], ref, 100 * worst))


def render_cycles(d, blend):
    """Cycles 3.4 renders BLEND (its own settings: bl_scenes.py's
    cycles_settings) to an EXR."""
    blender([blend, "-E", "CYCLES", "-o", os.path.join(d, "c_####"), "-F", "OPEN_EXR", "-x", "1", "-f", "1"])
    f = os.path.join(d, "c_0001.exr")
    return exr(f) if os.path.isfile(f) else None


def quarter_means(img):
    w, h = img["width"], img["height"]
    out = []
    for qy in range(2):
        for qx in range(2):
            px = [y * w + x for y in range(qy * h // 2, (qy + 1) * h // 2) for x in range(qx * w // 2, (qx + 1) * w // 2)]
            out.append([sum(img["channels"][c][i] for i in px) / len(px) for c in "RGB"])
    return out


def edge_width(img, rows):
    """The 10 %-90 % width (pixels) of the edge across the middle of `rows`,
    the plateau being the mean of their 8 leftmost columns."""
    w = img["width"]
    r = img["channels"]["R"]
    prof = [sum(r[y * w + x] for y in rows) / len(rows) for x in range(w)]
    top = sum(prof[:8]) / 8
    if top <= 0:
        return 0.0

    def cross(level):
        for x in range(1, w):
            a, b = prof[x - 1] / top, prof[x] / top
            if a >= level > b:
                return x - 1 + (a - level) / (a - b)
        return float(w)
    return cross(0.1) - cross(0.9)


# Per quarter and channel, relative to Cycles' mean or CAM_FLOOR, whichever is
# larger (emission only: no light transport between them). Measured: the
# panoramas within 0.3 %; cam_dof within 0.2 % where lit, 0.0011 apart in the
# quarter the far edge's blur barely reaches (0.0014 against 0.0025).
CAM_TOL = 0.03
CAM_FLOOR = 0.05
CAM_SETTINGS = dict(QUICK, spp=64)


def part_cameras():
    scenes = fresh("cam_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    gltf = os.path.join(WORK, "cam_dof.gltf")
    ok, _ = write_with_addon(os.path.join(scenes, "cam_dof.blend"), gltf)
    ext = json.load(open(gltf))["cameras"][0]["extensions"]["PHOTONBRIDGE_blender"] if ok else {}
    check(ext.get("apertureFstop") == 0.5 and abs(ext.get("focusDistance", 0) - 1.0) < 1e-6,
          "the writer carries depth of field in the camera extension (%s)" % ext)
    for name in ("cam_dof", "cam_equirect", "cam_fisheye", "cam_fisheye_eqd"):
        blend = os.path.join(scenes, name + ".blend")
        d = fresh(name)
        p = render_f12(d, blend, CAM_SETTINGS, fmt="OPEN_EXR")
        warned = [line for line in p.stdout.splitlines() if line.startswith("Warning") and "camera" in line]
        check(not warned, "%s: no camera warning %s" % (name, warned))
        f = os.path.join(d, "f_0001.exr")
        ours = exr(f) if os.path.isfile(f) else None
        ref = render_cycles(fresh(name + "_cycles"), blend)
        check(ours is not None and ref is not None, "%s: F12 and Cycles rendered" % name)
        if ours is None or ref is None:
            continue
        worst = 0.0
        for a, b in zip(quarter_means(ours), quarter_means(ref)):
            for x, y in zip(a, b):
                worst = max(worst, abs(x - y) / max(y, CAM_FLOOR))
        check(worst <= CAM_TOL, "%s renders as Cycles 3.4: channel means per quarter within %.1f %% (largest %.2f %%)"
              % (name, 100 * CAM_TOL, 100 * worst))
        if name == "cam_dof":
            rows = range(ours["height"] - 12, ours["height"])
            wo, wc = edge_width(ours, rows), edge_width(ref, rows)
            check(abs(wo / wc - 1) <= 0.15 and wc > 5,
                  "cam_dof: the far edge's 10-90 %% width %.2f px, Cycles' %.2f px" % (wo, wc))
            near = range(4, 14)
            wo, wc = edge_width(ours, near), edge_width(ref, near)
            check(wo < 2.5 and wc < 2.5, "cam_dof: the edge at the focus distance sharp (%.2f px, Cycles %.2f)"
                  % (wo, wc))


def part_badinput():
    scenes = fresh("bad_scenes")
    blender(["-P", os.path.join(HERE, "bl_scenes.py"), "--", scenes])
    blend = os.path.join(scenes, "moving.blend")

    def case(what, blend_file, needle, settings=None, env=None, out_dir=None, expect_file=False):
        d = out_dir or fresh("bad")
        t0 = time.time()
        p = render_f12(d, blend_file, dict(QUICK, **(settings or {})), fmt="OPEN_EXR", env=env, timeout=300)
        secs = time.time() - t0
        text = p.stdout + p.stderr
        for n in needle if isinstance(needle, list) else [needle]:
            found = n in text
            if not found:
                print(text[-2500:])
            check(found, "%s: the message says '%s' (%.1f s)" % (what, n, secs))
        made = os.path.isdir(d) and any(f.endswith(".exr") for f in os.listdir(d))
        check(made == expect_file, "%s: %s" % (what, "an image" if expect_file else "no image written"))
        check(not tmp_left(), "%s: no temporary files left" % what)

    env = blender_env({"PHOTONBRIDGE_BIN": os.path.join(WORK, "no", "photonbridge")})
    env["PATH"] = "/usr/bin:/bin"
    case("missing binary", blend, "photonbridge binary not found; looked in the add-on preferences (not set), "
         "$PHOTONBRIDGE_BIN (%s: not an executable file), PATH" % os.path.join(WORK, "no", "photonbridge"), env=env)
    # Blender itself refuses these before the engine runs.
    case("no camera", os.path.join(scenes, "nocamera.blend"), "Cannot render, no camera")
    case("no lights", os.path.join(scenes, "nolights.blend"), "no lights, no emissive materials and a black world",
         expect_file=True)
    case("zero-area light", os.path.join(scenes, "zero_area.blend"),
         "light 'Disk': area light of size 0 x 0 m emits nothing; left out", expect_file=True)
    case("only an empty mesh", os.path.join(scenes, "empty_mesh.blend"),
         ["object 'Edges': its mesh has no faces; left out", "(exit 7)"])
    case("negative light", os.path.join(scenes, "negative_light.blend"),
         "light 'Neg': negative power -100 is not rendered (photonbridge has no negative light); left out",
         expect_file=True)
    case("0-pixel image", blend, "Image too small", settings={"border": "0.5,0.5,0.5,0.9", "crop": "1"})
    blocker = os.path.join(WORK, "not_a_folder")
    with open(blocker, "w") as f:
        f.write("a file where the output folder should be\n")
    case("unwritable output", blend, "cannot save", out_dir=os.path.join(blocker, "out"))
    # A CLI killed mid-render: its exit status in Blender's report, no hang.
    d = fresh("killed")
    proc, child, lines = start_long_render(d, sample_blend("cornell_box"))
    check(child is not None, "killed CLI: photonbridge was running")
    if child:
        os.kill(child, signal.SIGKILL)
    ended, out, secs = finish(proc, lines)
    check(ended and "(exit -9)" in out, "killed CLI: Blender reports the exit status and returns (%.1f s)" % secs)
    check(not os.listdir(d), "killed CLI: no image written")
    check(not tmp_left(), "killed CLI: no temporary files left (%s)" % tmp_left())


def blender_version():
    p = subprocess.run(BLENDER + ["-b", "--factory-startup", "--python-exit-code", "1", "-P",
                                  os.path.join(HERE, "bl_version.py")],
                       capture_output=True, text=True, env=blender_env(), timeout=300)
    for line in p.stdout.splitlines():
        if line.startswith("BLENDER_VERSION "):
            return tuple(int(x) for x in line.split()[1:4])
    return (0, 0, 0)


def part_install():
    """Both ways Blender installs add-ons, from the zips `make
    blender-extension` makes: the legacy add-on (every Blender) and the
    extension (4.2+), each into fresh user folders, enabled and rendering."""
    d = fresh("install")
    p = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "blender_package.py"), d],
                       capture_output=True, text=True)
    check(p.returncode == 0, "blender_package.py made the zips: %s" % (p.stdout + p.stderr).strip())
    zips = {k: os.path.join(d, n) for n in os.listdir(d) for k in ("addon", "extension") if n.endswith(k + ".zip")}
    version = blender_version()
    kinds = [("legacy", zips.get("addon"))]
    if version >= (4, 2, 0):
        kinds.append(("extension", zips.get("extension")))
    for kind, z in kinds:
        user = fresh("install_user_" + kind)
        env = blender_env({"BLENDER_USER_RESOURCES": user, "BLENDER_USER_SCRIPTS": os.path.join(user, "scripts"),
                           "BLENDER_USER_CONFIG": os.path.join(user, "config")})
        out = os.path.join(d, kind + ".exr")
        p = subprocess.run(BLENDER + ["-b", "--factory-startup", "--python-exit-code", "1", "-P",
                                      os.path.join(HERE, "bl_install.py"), "--", kind, z or "missing.zip", out],
                           capture_output=True, text=True, env=env, timeout=600)
        print("\n".join(l for l in p.stdout.splitlines() if l.startswith(("ok   ", "FAIL "))))
        check(p.returncode == 0 and "0 failed" in p.stdout,
              "Blender %d.%d.%d: the %s zip installs, enables and renders" % (version + (kind,)))
        if p.returncode != 0:
            print(p.stdout[-3000:], p.stderr[-2000:])
        if os.path.isfile(out):
            img = exr(out)
            total = sum(sum(img["channels"][c]) for c in "RGB")
            check(total > 0, "%s: the render holds light" % kind)
    check(version >= (4, 2, 0) or len(kinds) == 1, "the extension is tested where Blender has extensions (4.2+)")


def part_lights45():
    """Blender 4.5's light settings (Exposure, Temperature, Normalize off on
    point, spot, area rectangle and disc and sun lights, Shadow off) as
    Cycles 4.5 computes them: the written powers against Cycles' formulas
    (scene/light.cpp Light::area, blender/light.cpp), then photonbridge's F12
    against Cycles 4.5's render of the same file."""
    if blender_version() < (4, 5, 0):
        print("skip: Blender 4.5's light settings need Blender 4.5 (this is %d.%d.%d)" % blender_version())
        return 77
    scenes = fresh("lights45_scenes")
    blender(["-P", os.path.join(HERE, "bl_lights45.py"), "--", scenes])
    blend = os.path.join(scenes, "lights45.blend")
    gltf = os.path.join(scenes, "lights45.gltf")
    doc = written(blend, gltf, "the scene")
    if doc is None:
        return
    lights = {n["name"]: n["extensions"]["PHOTONBRIDGE_blender"]["light"] for n in doc["nodes"]
              if "light" in n.get("extensions", {}).get("PHOTONBRIDGE_blender", {})}
    pi = math.pi
    want = {"Warm": ("power", 200.0 * 2.0), "Raw": ("power", 50.0 * 4 * pi * 0.25 ** 2),
            "Panel": ("power", 20.0 * 2.0 * 1.0 * 2 ** -0.5), "Disc": ("power", 10.0 * 0.6 * 0.6 * pi / 4),
            "Sun": ("strength", 1.0 * pi * math.sin(math.radians(5)) ** 2 * 8.0), "Ghost": ("power", 30.0)}
    for name, (key, value) in want.items():
        got = lights.get(name, {}).get(key)
        check(got is not None and close(got, value, 1e-5), "%s: %s %s W (Cycles 4.5: %.6g)" % (name, key, got, value))
    warm = lights.get("Warm", {}).get("color", [1, 1, 1])
    lum = 0.2126 * warm[0] + 0.7152 * warm[1] + 0.0722 * warm[2]
    check(warm[0] > warm[1] > warm[2] and close(lum, 1.0, 0.02),
          "Warm: colour x the 3000 K temperature colour %s (luminance %.3f)" % (["%.3f" % c for c in warm], lum))
    check(lights.get("Ghost", {}).get("castShadow") is False and lights.get("Warm", {}).get("castShadow") is True,
          "Ghost: Shadow off is written as castShadow false (others true)")
    # The reference (path tracing, 256 spp) within 1 %, F12 (the GPU
    # pipeline at small settings) within 2 % of Cycles 4.5. Cycles 3.4's
    # light models (area radiance P / (4 A), the spot's cosine) are 5.5 % off.
    mc, worst = against_cycles45("lights45", blend, gltf)
    check(mc is not None, "Cycles 4.5 and photonbridge rendered the scene")
    # Sphere lights (Soft Falloff off) close to the surfaces they light.
    sphere = os.path.join(scenes, "sphere45.blend")
    sg = os.path.join(scenes, "sphere45.gltf")
    sdoc = written(sphere, sg, "the sphere-light scene")
    if sdoc is None:
        return
    disc = os.path.join(scenes, "sphere45_disc.gltf")  # the same with 3.4's facing discs
    for n in sdoc["nodes"]:
        lt = n.get("extensions", {}).get("PHOTONBRIDGE_blender", {}).get("light")
        if lt is not None:
            check(lt.get("softFalloff") is False, "%s: Soft Falloff off is written" % n["name"])
            lt.pop("softFalloff", None)
    with open(disc, "w") as f:
        json.dump(sdoc, f)
    mc, _ = against_cycles45("sphere45", sphere, sg, "sphere lights, ")
    if mc is not None:
        worst = mean_off(reference_render(disc, os.path.join(WORK, "sphere45_cycles", "disc.exr")), mc)
        check(worst > 0.03, "the same lights as 3.4's facing discs are %.1f %% off: the scene tells the models "
              "apart" % (100 * worst))


def written(blend, gltf, what):
    """The add-on's glTF of blend as JSON, or None (checked)."""
    ok, text = write_with_addon(blend, gltf)
    check(ok, "%s is written" % what)
    if not ok:
        print(text[-3000:])
        return None
    with open(gltf) as f:
        return json.load(f)


def mean_rgb(path):
    img = exr(path) if os.path.isfile(path) else {"channels": {k: [0.0] for k in "RGB"}}
    return [sum(img["channels"][k]) / len(img["channels"][k]) for k in "RGB"]


def mean_off(path, mc):
    """The largest relative difference of path's mean RGB from mc."""
    return max(abs(x / y - 1) if y > 0 else 1 for x, y in zip(mean_rgb(path), mc))


def reference_render(gltf, out):
    subprocess.run([EXE, "reference", gltf, "-o", out, "--width", "64", "--height", "48", "--spp", "256", "-q"],
                   check=False)
    return out


def against_cycles45(name, blend, gltf, label=""):
    """Cycles 4.5's render of blend against photonbridge's reference of the
    written gltf (within 1 %) and F12 of blend (within 2 %), mean RGB:
    (Cycles' mean, or None when a render is missing; the largest difference)."""
    dc, df = fresh(name + "_cycles"), fresh(name + "_pb")
    blender([blend, "-E", "CYCLES", "-o", os.path.join(dc, "c_####"), "-F", "OPEN_EXR", "-x", "1", "-f", "1"])
    render_f12(df, blend, dict(QUICK, photons=65536, iterations=4, spp=16), fmt="OPEN_EXR")
    cf, pf = os.path.join(dc, "c_0001.exr"), os.path.join(df, "f_0001.exr")
    if not (os.path.isfile(cf) and os.path.isfile(pf)):
        return None, 1.0
    mc = mean_rgb(cf)
    rf = reference_render(gltf, os.path.join(dc, "reference.exr"))
    worst_all = 0.0
    for what, f, tol in (("the reference", rf, 0.01), ("F12", pf, 0.02)):
        worst = mean_off(f, mc)
        worst_all = max(worst_all, worst)
        check(worst <= tol, "%s%s: mean RGB %s against Cycles 4.5's %s (largest %.2f %%)"
              % (label, what, ["%.4f" % x for x in mean_rgb(f)], ["%.4f" % x for x in mc], 100 * worst))
    return mc, worst_all


def main():
    if BPY:
        # Installed by scripts/install-deps.sh on every machine: missing is
        # a failure, not a skip.
        if not os.access(BPY, os.X_OK):
            print("FAIL Blender 4.5 (bpy) is not installed at %s: run scripts/install-deps.sh" % BPY)
            return 1
    elif not shutil.which("blender"):
        print("skip: Blender is not installed (apt-get install blender; scripts/install-deps.sh)")
        return 77
    p = subprocess.run([EXE, "info", "--devices"], capture_output=True, text=True)
    if p.returncode != 0 and PART not in ("register", "validator", "writer"):
        print("skip: no Vulkan device")
        return 77
    os.makedirs(WORK, exist_ok=True)
    rc = globals()["part_" + PART]()
    if rc == 77:
        return 77
    if f12_runs:
        print("%d F12 renders, %d of them under the validation layers" % (len(f12_runs), sum(f12_runs)))
    print("%d passed, %d failed" % (0, len(failures)) if failures else "all checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
