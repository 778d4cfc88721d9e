"""The Device menu: the Vulkan devices `photonbridge info --devices --json -`
lists, by name, run once per binary and cached (the menu is drawn often;
the binary is the one the add-on preferences, $PHOTONBRIDGE_BIN or PATH
give, cli.find_binary). The menu is a view of the stored integer
Scene.photonbridge.device (-1: the CLI's default choice), which reaches the
CLI as --device N; when the list cannot be had, the menu says why."""
import json
import subprocess

import bpy

from . import cli

TIMEOUT_S = 15
# Item values: DEFAULT_VALUE for "Default", device N as N + 1, ERROR_VALUE
# for the line that says why there is no list.
DEFAULT_VALUE = 0
ERROR_VALUE = 1 << 20

# binary path -> {"devices": [dict, ...], "error": str or None}
_cache = {}
# The enum's items, kept referenced (Blender keeps pointers to their strings).
_items = {}


def _prefs_binary(context):
    prefs = getattr(context, "preferences", None) or bpy.context.preferences
    addon = prefs.addons.get(__package__) if prefs else None
    return addon.preferences.binary if addon else ""


def query(exe):
    """The devices of `exe` (run once per path, then cached): {"devices":
    [...], "error": None} or {"devices": [], "error": "one line"}."""
    got = _cache.get(exe)
    if got is not None:
        return got
    try:
        p = subprocess.run([exe, "info", "--devices", "--json", "-"], stdin=subprocess.DEVNULL,
                           capture_output=True, text=True, timeout=TIMEOUT_S, errors="replace")
        if p.returncode != 0:
            lines = [l for l in (p.stderr or p.stdout).splitlines() if l.strip()]
            raise RuntimeError("%s (exit %d)" % (lines[-1] if lines else "no message", p.returncode))
        got = {"devices": list(json.loads(p.stdout)["devices"]), "error": None}
    except (OSError, ValueError, KeyError, TypeError, subprocess.SubprocessError, RuntimeError) as e:
        got = {"devices": [], "error": "photonbridge info --devices failed: %s" % e}
    _cache[exe] = got
    return got


def listing(context=None):
    """The devices of the binary the add-on uses now, as query()."""
    try:
        exe = cli.find_binary(_prefs_binary(context))
    except cli.BinaryNotFound as e:
        return {"devices": [], "error": str(e)}
    return query(exe)


def clear_cache():
    """Forget the lists (the next menu runs the binary again); the items
    already handed to Blender stay referenced."""
    _cache.clear()


def enum_items(self, context):
    got = listing(context)
    dev = getattr(self, "device", -1) if self is not None else -1
    key = (json.dumps(got, sort_keys=True), dev)
    if key in _items:  # the same list object for the same answer: no new strings
        return _items[key]
    items = [("DEFAULT", "Default", "The CLI's choice: a discrete GPU first, a CPU implementation last",
              'NONE', DEFAULT_VALUE)]
    known = set()
    for d in got["devices"]:
        i = int(d.get("index", len(known)))
        known.add(i)
        name = str(d.get("name", "device %d" % i))
        desc = "%s, %s%s (--device %d)%s" % (d.get("type", "?"), d.get("driver", "?"),
                                             ", ray queries" if d.get("ray_query") else "", i,
                                             "" if d.get("usable", True) else "; unusable: lacks " + str(d.get("missing", "?")))
        items.append(("DEVICE_%d" % i, "%s%s" % (name, " (default)" if d.get("default") else ""), desc, 'NONE', i + 1))
    if dev >= 0 and dev not in known:
        items.append(("DEVICE_%d" % dev, "Device %d (not listed)" % dev,
                      "The scene asks for device %d, which this machine's list lacks" % dev, 'ERROR', dev + 1))
    if got["error"]:
        items.append(("ERROR", "No device list: see the tooltip", got["error"], 'ERROR', ERROR_VALUE))
    _items[key] = items
    return items


def enum_get(self):
    return max(-1, self.device) + 1


def enum_set(self, value):
    if value != ERROR_VALUE:
        self.device = value - 1


class PHOTONBRIDGE_OT_refresh_devices(bpy.types.Operator):
    """Ask the photonbridge binary for its devices again"""
    bl_idname = "photonbridge.refresh_devices"
    bl_label = "Refresh Devices"
    bl_options = {'INTERNAL'}

    def execute(self, context):
        clear_cache()
        got = listing(context)
        if got["error"]:
            self.report({'WARNING'}, got["error"])
        return {'FINISHED'}


classes = (PHOTONBRIDGE_OT_refresh_devices,)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
