"""The add-on's panels, Device menu and defaults, inside Blender (3.4:
`blender -b --factory-startup --python-exit-code 1 --python bl_ui.py --
ROOT EXE WORK`; 4.x: the bpy module's Python, `python bl_ui.py ROOT EXE
WORK`). EXE: the real photonbridge binary (its `render --help-all`).

  - panels: photonbridge's own Render Properties panels are registered with
    PHOTONBRIDGE (only) in COMPAT_ENGINES, poll for it and not for Cycles,
    sit under registered parents, and each draw (and draw_header) runs
    without error on a recording layout whose every prop() names a property
    that exists (and reads) and every operator() one that is registered;
    Cycles' own panels stay hidden;
  - the Device menu: with a fake binary (the add-on preferences' Binary)
    that prints a known `info --devices --json -`, the menu lists those
    names, runs the binary once (cached), and a choice reaches the CLI as
    --device N; a failing binary and a missing one make the menu say why;
  - defaults: every setting's default is `photonbridge render`'s, as its
    --help-all states them ("default X"), and its choices are the CLI's
    (the add-on's own settings are settings.ADDON_ONLY).

Prints "N passed, M failed"; exit 1 on a failure."""
import json
import os
import re
import stat
import subprocess
import sys
import traceback

import bpy
import addon_utils  # after bpy: the module puts Blender's scripts on sys.path

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
ROOT, EXE, WORK = argv[0], os.path.abspath(argv[1]), os.path.abspath(argv[2])
os.makedirs(WORK, exist_ok=True)
sys.path.insert(0, os.path.join(ROOT, "exporters", "blender"))
os.environ.pop("PHOTONBRIDGE_BIN", None)
os.environ["PATH"] = ":".join(p for p in os.environ.get("PATH", "").split(":")
                              if not os.path.exists(os.path.join(p, "photonbridge")))

passed = failed = 0


def check(ok, what):
    global passed, failed
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    passed, failed = passed + bool(ok), failed + (not ok)


mod = addon_utils.enable("photonbridge", default_set=True, handle_error=None)
check(mod is not None, "the add-on enables (%s)" % bpy.app.version_string)
from photonbridge import devices, settings, ui  # noqa: E402

scene = bpy.context.scene
scene.render.engine = "PHOTONBRIDGE"
s = scene.photonbridge
prefs = bpy.context.preferences.addons["photonbridge"].preferences

# ---- the fake binary -------------------------------------------------------------
FAKE_DEVICES = {"devices": [
    {"index": 0, "name": "llvmpipe (LLVM 15.0.6, 256 bits)", "type": "cpu", "driver": "llvmpipe",
     "usable": True, "default": False},
    {"index": 1, "name": "NVIDIA GeForce RTX 4090", "type": "discrete", "driver": "NVIDIA",
     "usable": True, "default": True}]}
calls = os.path.join(WORK, "fake_calls.txt")
fake = os.path.join(WORK, "fake_photonbridge")
with open(fake, "w") as f:
    f.write("#!/bin/sh\necho \"$@\" >> '%s'\n"
            "if [ \"$1 $2 $3 $4\" = 'info --devices --json -' ]; then cat <<'JSON'\n%s\nJSON\nexit 0; fi\n"
            "echo 'photonbridge: error: unexpected call' >&2; exit 2\n" % (calls, json.dumps(FAKE_DEVICES)))
broken = os.path.join(WORK, "broken_photonbridge")
with open(broken, "w") as f:
    f.write("#!/bin/sh\necho 'photonbridge info: error: no Vulkan driver found' >&2\nexit 5\n")
for p in (fake, broken):
    os.chmod(p, os.stat(p).st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
if os.path.exists(calls):
    os.remove(calls)


# ---- panels -------------------------------------------------------------------
class Recorder:
    """A UILayout stand-in: checks what the draw code asks of it."""

    def __init__(self, log):
        self.log = log

    def _sub(self, *a, **k):
        return Recorder(self.log)

    column = row = split = box = column_flow = grid_flow = _sub

    def prop(self, data, name, **kw):
        ok = name in data.bl_rna.properties
        if ok:
            getattr(data, name)  # the getter (and an enum's items) runs
        self.log.append(("prop", type(data).__name__, name, ok))

    def label(self, text="", **kw):
        self.log.append(("label", text, True))

    def operator(self, idname, **kw):
        cat, name = idname.split(".")
        ok = name in dir(getattr(bpy.ops, cat))  # the registered ones (any name has a wrapper)
        if ok:
            getattr(getattr(bpy.ops, cat), name).get_rna_type()
        self.log.append(("operator", idname, ok))

    def separator(self, **kw):
        pass


panels = [c for c in ui.classes if issubclass(c, bpy.types.Panel)]
names = [c.__name__ for c in panels]
for want in ("PHOTONBRIDGE_PT_sampling", "PHOTONBRIDGE_PT_sampling_render", "PHOTONBRIDGE_PT_sampling_viewport",
             "PHOTONBRIDGE_PT_sampling_advanced", "PHOTONBRIDGE_PT_light_paths",
             "PHOTONBRIDGE_PT_light_paths_max_bounces", "PHOTONBRIDGE_PT_light_paths_caustics",
             "PHOTONBRIDGE_PT_film", "PHOTONBRIDGE_PT_performance"):
    check(want in names and hasattr(bpy.types, want), "panel %s registered" % want)


class Ctx:  # what the panels read of a context
    def __init__(self, engine):
        self.engine = engine
        self.scene = bpy.context.scene
        self.preferences = bpy.context.preferences


for c in panels:
    t = getattr(bpy.types, c.__name__, None)
    check(t is not None and getattr(c, "is_registered", True), "%s: registered" % c.__name__)
    check(c.COMPAT_ENGINES == {"PHOTONBRIDGE"}, "%s: COMPAT_ENGINES %s" % (c.__name__, c.COMPAT_ENGINES))
    check(c.bl_context == "render" and c.bl_space_type == 'PROPERTIES', "%s: in Render Properties" % c.__name__)
    parent = getattr(c, "bl_parent_id", "")
    check(not parent or parent in names, "%s: parent %s is one of photonbridge's panels" % (c.__name__, parent or "-"))
    check(c.poll(Ctx("PHOTONBRIDGE")) and not c.poll(Ctx("CYCLES")), "%s: polls for photonbridge only" % c.__name__)
    for fn in ("draw_header", "draw"):
        if fn not in c.__dict__:
            continue
        log = []
        me = type("P", (), {"layout": Recorder(log), "split_layout": c.split_layout})()
        try:
            getattr(c, fn)(me, Ctx("PHOTONBRIDGE"))
            err = None
        except Exception:
            err = traceback.format_exc()
        bad = [e for e in log if not e[-1]]
        check(err is None and not bad, "%s.%s draws: %d items, %s" % (
            c.__name__, fn, len(log), err or (("bad: %s" % bad) if bad else "all exist")))

drawn = set()
for c in panels:
    for fn in ("draw_header", "draw"):
        if fn in c.__dict__:
            log = []
            getattr(c, fn)(type("P", (), {"layout": Recorder(log), "split_layout": c.split_layout})(), Ctx("PHOTONBRIDGE"))
            drawn |= {e[2] for e in log if e[0] == "prop" and e[1] == "PhotonbridgeSettings"}
# Every setting is drawn somewhere (device through its menu). image_maps
# and image_map_resolution show with the Environment Maps tracer.
s.tracer = "images"
for c in panels:
    if "draw" in c.__dict__:
        log = []
        c.draw(type("P", (), {"layout": Recorder(log), "split_layout": c.split_layout})(), Ctx("PHOTONBRIDGE"))
        drawn |= {e[2] for e in log if e[0] == "prop" and e[1] == "PhotonbridgeSettings"}
s.tracer = "bvh"
props = [p.identifier for p in settings.PhotonbridgeSettings.bl_rna.properties if p.identifier not in ("rna_type", "name")]
missing = sorted(set(props) - drawn - {"device"})
check(not missing, "every photonbridge setting is drawn in a panel (missing: %s)" % missing)
if hasattr(scene, "cycles"):
    log = []
    ui.PHOTONBRIDGE_PT_light_paths_max_bounces.draw(
        type("P", (), {"layout": Recorder(log), "split_layout": ui.PhotonbridgePanel.split_layout})(),
        Ctx("PHOTONBRIDGE"))
    check(("prop", "CyclesRenderSettings", "max_bounces", True) in log,
          "Light Paths > Max Bounces draws Cycles' max_bounces: %s" % [e for e in log if e[0] == "prop"])
for name in ("CYCLES_RENDER_PT_light_paths", "CYCLES_RENDER_PT_film", "CYCLES_RENDER_PT_performance"):
    t = getattr(bpy.types, name, None)
    check(t is None or "PHOTONBRIDGE" not in t.COMPAT_ENGINES, "Cycles' %s stays hidden" % name)
for name in ("RENDER_PT_color_management", "RENDER_PT_format", "RENDER_PT_output"):
    check("PHOTONBRIDGE" in getattr(bpy.types, name).COMPAT_ENGINES, "%s shows for photonbridge" % name)

# ---- the Device menu -----------------------------------------------------------------
devices.clear_cache()
prefs.binary = fake


items = [(i[0], i[1], i[2]) for i in devices.enum_items(s, bpy.context)]
check([i[1] for i in items] == ["Default", "llvmpipe (LLVM 15.0.6, 256 bits)", "NVIDIA GeForce RTX 4090 (default)"],
      "the menu lists the binary's devices by name: %s" % [i[1] for i in items])
check(s.device_menu == "DEFAULT" and s.device == -1 and "--device" not in settings.cli_args(s),
      "Default: device -1, no --device")
s.device_menu = "DEVICE_1"
args = settings.cli_args(s)
check(s.device == 1 and args[args.index("--device") + 1] == "1", "NVIDIA chosen: --device 1 (%s)" % args[-2:])
s.device_menu = "DEVICE_0"
args = settings.cli_args(s)
check(s.device == 0 and args[args.index("--device") + 1] == "0", "llvmpipe chosen: --device 0")
args = settings.cli_args(s, sequence=True, serve=True)
check(args[args.index("--device") + 1] == "0", "the viewport's serve gets --device 0 too")
s.device = 7
items = devices.enum_items(s, bpy.context)
check(s.device_menu == "DEVICE_7" and any(i[0] == "DEVICE_7" and "not listed" in i[1] for i in items),
      "a stored device this machine lacks stays, marked not listed")
s.device_menu = "DEFAULT"
for _ in range(5):
    devices.enum_items(s, bpy.context)
n_calls = len(open(calls).read().splitlines()) if os.path.exists(calls) else 0
check(n_calls == 1, "the binary ran once for the menu (cached): %d calls" % n_calls)

devices.clear_cache()
prefs.binary = broken
items = devices.enum_items(s, bpy.context)
err = devices.listing(bpy.context)["error"] or ""
check(items[-1][0] == "ERROR" and "no Vulkan driver found" in items[-1][2] and "exit 5" in err,
      "a failing binary: the menu says so (%s)" % err)
s.device_menu = "ERROR"
check(s.device == -1, "choosing the error line changes nothing")
devices.clear_cache()
prefs.binary = ""
err = devices.listing(bpy.context)["error"] or ""
items = devices.enum_items(s, bpy.context)
check(items[-1][0] == "ERROR" and "binary not found" in err, "no binary: the menu says so (%s)" % err[:80])
log = []
ui.PHOTONBRIDGE_PT_performance.draw(type("P", (), {"layout": Recorder(log),
                                                   "split_layout": ui.PhotonbridgePanel.split_layout})(),
                                    Ctx("PHOTONBRIDGE"))
check(any(e[0] == "label" and "not found" in e[1] for e in log), "Performance shows the error under the menu")
# The real binary: the menu is what its `info --devices --json -` lists.
devices.clear_cache()
prefs.binary = EXE
p = subprocess.run([EXE, "info", "--devices", "--json", "-"], capture_output=True, text=True, timeout=120)
items = devices.enum_items(s, bpy.context)
if p.returncode == 0:
    real = json.loads(p.stdout)["devices"]
    check([i[1].replace(" (default)", "") for i in items[1:]] == [d["name"] for d in real],
          "with the real binary: Default + its %d device(s) %s" % (len(real), [i[1] for i in items[1:]]))
else:
    check(items[-1][0] == "ERROR", "the real binary lists no devices here (exit %d): the menu says so" % p.returncode)
prefs.binary = fake

# ---- the viewport: every setting of the table goes to serve's "settings"
# request; the device, and a setting turning to or from "automatic" (a
# value the request cannot carry: Photon Bounces 0), restart serve
from photonbridge import viewport  # noqa: E402
base = viewport.fixed_args(scene)
base_req = viewport.Viewport._settings(None, scene)
for attr, val in (("spp", 4), ("photons", 1000), ("progressive", not s.progressive), ("caustic_filter", 2.0),
                  ("first_bounce", "rsm"), ("estimator", "knn"), ("glossy_path_roughness", 0.5)):
    old = getattr(s, attr)
    setattr(s, attr, val)
    fixed, req = viewport.fixed_args(scene), viewport.Viewport._settings(None, scene)
    setattr(s, attr, old)
    check(fixed == base and req != base_req, "%s: sent live, no serve restart (%s)" % (attr, fixed))
for attr, val in (("blender_bounces", not s.blender_bounces), ("device", 0), ("photon_bounces", 3)):
    old = getattr(s, attr)
    setattr(s, attr, val)
    check(viewport.fixed_args(scene) != base, "%s: serve restarts (%s)" % (attr, viewport.fixed_args(scene)))
    setattr(s, attr, old)
check(viewport.noise_threshold(scene) == 0.0, "the viewport's stream has no noise threshold by default")
s.use_viewport_noise_threshold = True
check(viewport.noise_threshold(scene) == 0.05 and viewport.fixed_args(scene) == base,
      "Viewport Noise Threshold on: the stream rests at 0.05, no serve restart")
s.use_viewport_noise_threshold = False
s.estimator = "knn"
check("--estimator" in viewport.serve_args(scene) and "--estimator" in settings.cli_args(s),
      "Estimator: render's --estimator and serve's")
s.estimator = "lbvh"

# ---- defaults: the CLI's ------------------------------------------------------------------
text = subprocess.run([EXE, "render", "--help-all"], capture_output=True, text=True, timeout=60).stdout
helps, cur = {}, None
for line in text.splitlines():
    m = re.match(r"^  --([a-z0-9-]+)", line)
    if m:
        cur = m.group(1)
        helps[cur] = line[m.end():].strip()
    elif cur and line.startswith("     "):
        helps[cur] += " " + line.strip()
    else:
        cur = None
check(len(helps) > 40, "render --help-all lists %d options" % len(helps))


def cli_default(opt):
    # "(default X", "; default X" or "(default: X" (words: unset)
    m = re.search(r"[(;,]\s*default:? ([^,;:)\s]+)", helps.get(opt, ""))
    return m.group(1) if m else None


def cli_choices(opt):
    m = re.search(r"\{([^}]*)\}\s*$", helps.get(opt, ""))
    return [x.strip() for x in m.group(1).split(",")] if m else None


def number(v):
    if v is None:
        return None
    if "^" in v:
        b, e = v.split("^")
        return float(b) ** float(e)
    return float(v)


rna = settings.PhotonbridgeSettings.bl_rna.properties
# property: (CLI option, how the CLI states its default, the add-on's value that means it)
UNSET = {"unbounded", "Russian", "a"}  # "default: unbounded", "Russian roulette ...", "a discrete GPU first"
MAP = {"photons": "photons", "iterations": "iterations", "spp": "spp", "seed": "seed", "first_bounce": "first-bounce",
       "tracer": "tracer", "image_maps": "image-maps", "image_map_resolution": "image-map-resolution",
       "filter_passes": "atrous-iterations", "estimator": "estimator", "caustic_filter": "smoothing-caustic",
       "photon_bounces": "photon-bounces", "specular_depth": "max-specular-depth", "device": "device",
       "traversal": "traversal",
       "time_limit": "time-limit", "progressive": "progressive", "noise_threshold": "noise-threshold"}
for p in props:
    check(p in MAP or p in settings.ADDON_ONLY or p in settings.TABLE_PROPERTIES,
          "setting %s: a CLI option's, the add-on's own or one of the settings table's" % p)
# The rest of the settings table: a property each, of the row's id, with its
# default and range, and an option of `photonbridge render`; Blender's
# wording and the table agree on the ones with the artist's names.
table = settings.BY_ID
for sid in settings.TABLE_PROPERTIES:
    t, prop = table[sid], rna[sid]
    check(("--" + t["cli"])[2:] in helps, "%s: --%s is an option of `photonbridge render`" % (sid, t["cli"]))
    if prop.type == 'ENUM':
        check(prop.default == t["default"], "%s: default %s, the table's %s" % (sid, prop.default, t["default"]))
    else:
        check(abs(float(prop.default) - float(t["default"])) <= 1e-6, "%s: default %s, the table's %s" %
              (sid, prop.default, t["default"]))
    if t["kind"] in ("u32", "f64") and t["max"] is not None:
        check(abs(prop.hard_max - t["max"]) <= 1e-6 * max(1.0, t["max"]) and prop.hard_min <= t["min"],
              "%s: range up to %s, the table's [%s, %s]" % (sid, prop.hard_max, t["min"], t["max"]))
for p, sid in settings.PROPERTY_SETTING.items():
    t, prop = table[sid], rna[p]
    if t["kind"] in ("u32", "f64") and t["max"] is not None and p != "caustic_filter":
        check(abs(prop.hard_max - t["max"]) <= 1e-6 * max(1.0, t["max"]),
              "%s: at most %s, as the table's --%s" % (p, prop.hard_max, t["cli"]))
# A table setting changed reaches the command line (and back: its default
# passes nothing); one that needs another choice passes only with it.
fresh0 = bpy.data.scenes.new("table").photonbridge
fresh0.glossy_path_roughness = 0.5
fresh0.knn_k = 16
a0 = settings.cli_args(fresh0)
check("--glossy-path-roughness" in a0 and a0[a0.index("--glossy-path-roughness") + 1] == "0.5" and
      "--knn-k" not in a0, "Glossy Path Roughness 0.5 passes --glossy-path-roughness 0.5, Nearest Photons "
      "without the knn estimator nothing: %s" % a0)
fresh0.estimator = "knn"
a0 = settings.cli_args(fresh0)
check("--knn-k" in a0 and a0[a0.index("--knn-k") + 1] == "16", "with the knn estimator --knn-k 16: %s" % a0)
req, automatic = settings.request_settings(fresh0)
check(req.get("knn_k") == 16 and req.get("estimator") == "knn" and req.get("glossy_path_roughness") == 0.5 and
      "photon_bounces" in automatic and "upsample_levels" not in automatic,
      "the viewport's request carries them, Photon Bounces 0 left to serve: %s %s" % (req, automatic))
for p, val in sorted(settings.FINAL_RENDER.items()):
    d = rna[p].default
    check(abs(d - val) <= 1e-6 if isinstance(val, float) else d == val,
          "%s: F12's final-render default %s (the add-on's own)" % (p, val))
for p, opt in sorted(MAP.items()):
    check(opt in helps, "--%s is an option of `photonbridge render`" % opt)
    if p in settings.FINAL_RENDER:
        continue
    prop = rna[p]
    d, default = cli_default(opt), prop.default
    if prop.type == 'ENUM':
        choices = cli_choices(opt)
        ids = [i.identifier for i in prop.enum_items]
        check(d == default, "%s: default %s, the CLI's %s" % (p, default, d))
        check(choices is not None and set(ids) <= set(choices), "%s: choices %s among the CLI's %s" % (p, ids, choices))
    elif prop.type == 'BOOLEAN':  # a flag: off unless given
        check(default is False, "%s: off by default, as the CLI's flag --%s" % (p, opt))
    elif d in UNSET:
        check(default in (0, -1), "%s: default %s (unset), the CLI's '%s...'" % (p, default, d))
    elif d is None:  # stated nowhere: off (--time-limit)
        check(default == 0, "%s: default %s, the CLI's (none stated: off)" % (p, default))
    else:
        check(abs(number(d) - default) <= 1e-6 * max(1.0, abs(default)), "%s: default %s, the CLI's %s" % (p, default, d))
check(cli_default("max-bounces") == "unbounded" and cli_default("iterations") == "as" and
      "0.03" in helps.get("noise-threshold", ""),
      "the CLI's bare render is what FINAL_RENDER departs from: unbounded paths, photon maps to the noise "
      "threshold 0.03 (--max-bounces' default: %s, --iterations': %s)" %
      (cli_default("max-bounces"), cli_default("iterations")))
# A new scene's command line: every option it passes at the CLI's default.
fresh = bpy.data.scenes.new("defaults")
args = settings.cli_args(fresh.photonbridge)
pairs, i = {}, 0
while i < len(args):  # options and their values; a flag (--progressive) has none
    val = args[i + 1] if i + 1 < len(args) and not args[i + 1].startswith("--") else None
    pairs[args[i]] = val
    i += 2 if val is not None else 1
check(set(a for a in args if a.startswith("--")) ==
      {"--photons", "--iterations", "--spp", "--first-bounce", "--tracer", "--seed", "--progressive", "--max-bounces"},
      "a new scene passes the always-given options and F12's: %s" % args)
check(pairs.get("--iterations") == "16" and pairs.get("--spp") == "16", "a new scene renders 16 maps at 16 spp: %s" % args)
for k, v in pairs.items():
    if k in ("--iterations", "--spp", "--progressive", "--max-bounces"):
        continue
    d = cli_default(k[2:])
    same = (v == d) if not re.match(r"^[0-9.^]+$", d or "") else abs(number(v) - number(d)) < 1e-9
    check(same, "a new scene's %s %s is the CLI's default %s" % (k, v, d))
fresh.photonbridge.use_noise_threshold = True  # Cycles' switch: on, F12 passes its threshold
a2 = settings.cli_args(fresh.photonbridge)
check("--noise-threshold" in a2 and a2[a2.index("--noise-threshold") + 1] == "0.02" and
      "--noise-threshold" not in settings.cli_args(fresh.photonbridge, sequence=True) and
      "--noise-threshold" not in settings.cli_args(fresh.photonbridge, serve=True),
      "Noise Threshold on: F12 passes --noise-threshold 0.02 (not a sequence, not the viewport): %s" % a2)
fresh.photonbridge.use_noise_threshold = False
check(rna["viewport_samples"].default == 1024 and rna["preview_interval"].default == 2.0,
      "the add-on's own: Viewport Samples 1024, Refresh 2 s")

print("%d passed, %d failed" % (passed, failed))
sys.stdout.flush()
os._exit(1 if failed else 0)
