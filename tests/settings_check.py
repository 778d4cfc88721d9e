"""The settings table reaches every surface with the same range
(src/render/settings.h): for each row of the add-on's copy of the table
(settings_table.py, itself checked against the binary), `render`, `view`
and `serve` list the option exactly where the row offers it, and each
refuses a value past the row's range with the same bound, before any
work (exit 2, the option named).

usage: settings_check.py PHOTONBRIDGE SETTINGS_TABLE_PY"""
import importlib.util
import os
import subprocess
import sys

exe, table_py = sys.argv[1], sys.argv[2]
spec = importlib.util.spec_from_file_location("settings_table", table_py)
table = importlib.util.module_from_spec(spec)
spec.loader.exec_module(table)
scene = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "samples", "cornell_box", "cornell_box.gltf")

passed = failed = 0


def check(ok, what):
    global passed, failed
    print(("ok   " if ok else "FAIL ") + what)
    passed, failed = passed + bool(ok), failed + (not ok)


def run(args):
    p = subprocess.run([exe] + args, capture_output=True, text=True, timeout=60,
                       env=dict(os.environ, DISPLAY="", WAYLAND_DISPLAY=""))
    return p.returncode, p.stdout + p.stderr


helps = {c: run([c, "--help-all"])[1] for c in ("render", "view", "serve")}
surface_of = {"render": "render", "view": "live", "serve": "live"}
check(len(table.SETTINGS) >= 30, "the table has %d settings" % len(table.SETTINGS))
for t in table.SETTINGS:
    opt = "--" + t["cli"]
    for c, text in helps.items():
        # an option's own line: two spaces, the option (help lines wrap further in)
        listed = any(line.startswith("  " + opt) and line[2 + len(opt):][:1] in (" ", "")
                     for line in text.splitlines())
        want = surface_of[c] in t["surfaces"]
        check(listed == want, "%s --help-all %s %s" % (c, "lists" if want else "does not list", opt))
    if t["kind"] not in ("u32", "f64") or t["max"] is None:
        continue
    over = t["max"] + 1 if t["kind"] == "u32" else t["max"] * 2 + 1
    value = str(int(over)) if t["kind"] == "u32" else "%g" % over
    bound = ("[%d, %d]" % (t["min"], t["max"])) if t["kind"] == "u32" else None
    for c in ("render", "view", "serve"):
        if surface_of[c] not in t["surfaces"]:
            continue
        args = [c, scene, opt, value] + (["-o", "/tmp/pb_settings_never.exr"] if c == "render" else [])
        rc, out = run(args)
        ok = rc == 2 and (opt + ": " + value + " is outside") in out and (bound is None or bound in out)
        check(ok, "%s %s %s: exit %d, the bound %s named" % (c, opt, value, rc, bound or "[%g, %g]" % (t["min"], t["max"])))
# A serve key is the row's id; a flag on by default is cleared by its option.
for t in table.SETTINGS:
    if t["kind"] == "bool" and t["default"]:
        check(t["cli"].startswith("no-"), "%s: on by default, its option --%s clears it" % (t["id"], t["cli"]))
rc, out = run(["settings"])
check(rc == 0 and all(("--" + t["cli"]) in out and ('"%s"' % t["id"]) in out for t in table.SETTINGS),
      "settings lists every option with its serve key")
print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
