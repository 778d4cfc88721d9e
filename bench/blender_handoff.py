#!/usr/bin/env python3
"""The Blender render engine's hand-off and time to the first picture,
against Cycles on the same .blend (bench/README.md, "Blender hand-off").

For sun_atrium.blend (123,582 triangles) and a generated scene of about
1 M triangles (a subdivided grid under a sun, bench/blender_scene.py's
recipe, written into the cache folder):
  - writer: the add-on's depsgraph writer alone (export_photonbridge.py's
    own timer: instances, to_mesh, numpy, materials, the .gltf/.bin);
  - Blender's own glTF exporter on the same file, for scale;
  - F12 (`blender -b -E PHOTONBRIDGE -f 1`, 25 % resolution): the
    render-time stamps Blender prints with each engine status line: scene
    written (the hand-off), photonbridge loaded and uploaded, first photon
    map done (the first picture in the image editor, --preview-interval 0);
  - Cycles, same file and size, 1 sample, CPU: the time stamps of its
    'Sample 0/1' line (scene sync and BVH done) and 'Sample 1/1' (first
    picture).
Each Blender run's wall time includes Blender's start (about a second).

usage: blender_handoff.py PHOTONBRIDGE [--out FILE.md] [--cache DIR]"""
import argparse
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STAMP = re.compile(r"Time:(\d+):(\d+\.\d+) \| (.*)$")

SCENE_1M = """
import bpy, sys
bpy.ops.wm.read_factory_settings(use_empty=True)
sc = bpy.context.scene
sc.render.resolution_x, sc.render.resolution_y = 1280, 720
bpy.ops.mesh.primitive_grid_add(x_subdivisions=708, y_subdivisions=708, size=20.0)
grid = bpy.context.active_object
m = bpy.data.materials.new("Ground"); m.use_nodes = True
grid.data.materials.append(m)
sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", 'SUN'))
sun.data.energy = 4.0; sun.rotation_euler = (0.6, 0.2, 0.0)
sc.collection.objects.link(sun)
cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
cam.location = (0.0, -14.0, 8.0); cam.rotation_euler = (1.0, 0.0, 0.0)
sc.collection.objects.link(cam); sc.camera = cam
bpy.ops.wm.save_as_mainfile(filepath=sys.argv[sys.argv.index("--") + 1])
"""


def env():
    e = dict(os.environ)
    e["PATH"] = ":".join(p for p in e.get("PATH", "").split(":") if "pyenv" not in p)
    return e


def blender(args, extra_env=None):
    e = env()
    if extra_env:
        e.update(extra_env)
    t0 = time.perf_counter()
    p = subprocess.run(["blender", "-b", "--factory-startup"] + args, capture_output=True, text=True, env=e)
    return p, time.perf_counter() - t0


def stamps(text):
    """(seconds, message) of Blender's status lines."""
    out = []
    for line in text.splitlines():
        m = STAMP.search(line)
        if m:
            out.append((int(m.group(1)) * 60 + float(m.group(2)), m.group(3)))
    return out


def first(st, needle):
    for t, msg in st:
        if needle in msg:
            return t
    return float("nan")


def measure(name, blend, exe, work):
    row = {"scene": name}
    out = os.path.join(work, name + ".gltf")
    p, wall = blender([blend, "-P", os.path.join(ROOT, "exporters", "blender", "export_photonbridge.py"), "--", out])
    m = re.search(r"export_photonbridge: (\d+) triangles.* in ([\d.]+) s", p.stdout)
    row["triangles"] = int(m.group(1)) if m else -1
    row["writer_s"] = float(m.group(2)) if m else float("nan")
    code = ("import numpy, sys\nif not hasattr(numpy, 'bool'): numpy.bool = bool\n"
            "import bpy, time\nt = time.perf_counter()\n"
            "bpy.ops.export_scene.gltf(filepath=%r, export_format='GLTF_SEPARATE', export_apply=True)\n"
            "print('GLTF_EXPORT %%.3f' %% (time.perf_counter() - t))\n" % os.path.join(work, name + "_blender.gltf"))
    p, _ = blender([blend, "--python-expr", code])
    m = re.search(r"GLTF_EXPORT ([\d.]+)", p.stdout)
    row["exporter_s"] = float(m.group(1)) if m else float("nan")
    scripts = os.path.join(work, "scripts")
    os.makedirs(os.path.join(scripts, "addons"), exist_ok=True)
    link = os.path.join(scripts, "addons", "photonbridge")
    if not os.path.islink(link):
        os.symlink(os.path.join(ROOT, "exporters", "blender", "photonbridge"), link)
    setup = ("import addon_utils, bpy\naddon_utils.enable('photonbridge', default_set=True)\n"
             "s = bpy.context.scene\ns.render.engine = 'PHOTONBRIDGE'\ns.render.resolution_percentage = 25\n"
             "p = s.photonbridge\np.iterations = 4\np.spp = 4\np.photons = 65536\np.preview_interval = 0\n")
    p, wall = blender([blend, "--python-expr", setup, "-o", os.path.join(work, name + "_pb_####"), "-F", "OPEN_EXR",
                       "-f", "1"], {"BLENDER_USER_SCRIPTS": scripts, "PHOTONBRIDGE_BIN": exe})
    st = stamps(p.stdout)
    m = re.search(r"scene written \(\d+ triangles, ([\d.]+) s\)", p.stdout)
    row["handoff_s"] = float(m.group(1)) if m else float("nan")
    row["pb_written_t"] = first(st, "scene written")
    row["pb_uploaded_t"] = first(st, "scene uploaded")
    row["pb_first_t"] = first(st, "photon map 1/")
    row["pb_done_t"] = first(st, "done in")
    code = ("import bpy\ns = bpy.context.scene\ns.render.engine = 'CYCLES'\ns.cycles.samples = 1\n"
            "s.cycles.use_denoising = False\ns.cycles.device = 'CPU'\ns.render.resolution_percentage = 25\n")
    p, wall = blender([blend, "--python-expr", code, "-o", os.path.join(work, name + "_cy_####"), "-F", "PNG", "-f", "1"])
    st = stamps(p.stdout)
    row["cycles_sync_t"] = first(st, "Sample 0/1")
    row["cycles_first_t"] = first(st, "Sample 1/1")
    return row


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "lavapipe", "blender", "HANDOFF.md"))
    ap.add_argument("--cache", default=os.path.join(ROOT, "bench", "cache", "blender"))
    a = ap.parse_args()
    exe = os.path.abspath(a.exe)
    os.makedirs(a.cache, exist_ok=True)
    big = os.path.join(a.cache, "grid_1m.blend")
    if not os.path.isfile(big):
        blender(["--python-expr", SCENE_1M, "--", big])
    rows = [measure("sun_atrium", os.path.join(ROOT, "samples", "sun_atrium", "sun_atrium.blend"), exe, a.cache),
            measure("grid_1m", big, exe, a.cache)]
    lines = ["| scene | triangles | writer alone | Blender's glTF exporter | F12 hand-off | photonbridge loaded + "
             "uploaded | first picture | done | Cycles sync + BVH | Cycles first picture (1 spp) |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        lines.append("| %s | %d | %.2f s | %.2f s | %.2f s | at %.2f s | at %.2f s | at %.2f s | at %.2f s | at %.2f s |" % (
            r["scene"], r["triangles"], r["writer_s"], r["exporter_s"], r["handoff_s"], r["pb_uploaded_t"],
            r["pb_first_t"], r["pb_done_t"], r["cycles_sync_t"], r["cycles_first_t"]))
    text = "\n".join(lines) + "\n"
    print(text)
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as f:
        f.write("# Blender hand-off (bench/blender_handoff.py)\n\n" + time.strftime("%Y-%m-%d") +
                ", 25 % of each scene's resolution, photonbridge on the default Vulkan device "
                "(4 maps of 2^16 paths, 4 spp), Cycles on the CPU (1 sample). Times after F12 are Blender's own "
                "render clock.\n\n" + text)


if __name__ == "__main__":
    sys.exit(main())
