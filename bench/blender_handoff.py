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


def blender(args, extra_env=None, bpy_python=None):
    """Debian's blender, or with bpy_python Blender as a Python module through
    tests/blender/bpy_blender.py (the same command line)."""
    e = env()
    if extra_env:
        e.update(extra_env)
    cmd = [bpy_python, os.path.join(ROOT, "tests", "blender", "bpy_blender.py")] if bpy_python else ["blender"]
    t0 = time.perf_counter()
    p = subprocess.run(cmd + ["-b", "--factory-startup"] + args, capture_output=True, text=True, env=e)
    return p, time.perf_counter() - t0


def writer_time(blend, work, tag, bpy_python=None, runs=3):
    """(triangles, seconds of the add-on's writer alone: the median of runs)
    in one Blender."""
    times, tris = [], -1
    for i in range(runs):
        out = os.path.join(work, "%s_%d.gltf" % (tag, i))
        p, _ = blender([blend, "-P", os.path.join(ROOT, "exporters", "blender", "export_photonbridge.py"), "--", out],
                       bpy_python=bpy_python)
        m = re.search(r"export_photonbridge: (\d+) triangles.* in ([\d.]+) s", p.stdout)
        if not m:
            print(p.stdout[-2000:], p.stderr[-2000:])
            return -1, float("nan")
        tris = int(m.group(1))
        times.append(float(m.group(2)))
    return tris, sorted(times)[len(times) // 2]


def versions(a, big):
    """The writer's hand-off in Blender 3.4 (Debian) and Blender 4.5 (bpy),
    the same files (4.5 opens the 3.4 .blend through its versioning: the
    Principled BSDFs become v2), one run: BLENDER45.md."""
    rows = []
    for name, blend in (("sun_atrium", os.path.join(ROOT, "samples", "sun_atrium", "sun_atrium.blend")),
                        ("grid_1m", big)):
        t34 = writer_time(blend, a.cache, name + "_34")
        t45 = writer_time(blend, a.cache, name + "_45", bpy_python=a.bpy)
        rows.append((name, t34, t45))
    lines = ["| scene | triangles | writer, Blender 3.4.1 | writer, Blender 4.5.15 | 4.5 / 3.4 |", "|---|---:|---:|---:|---:|"]
    for name, (n34, s34), (n45, s45) in rows:
        lines.append("| %s | %d | %.2f s | %.2f s | %.2f |" % (name, n34, s34, s45, s45 / s34 if s34 > 0 else float("nan")))
    text = "\n".join(lines) + "\n"
    print(text)
    out = os.path.join(os.path.dirname(a.out), "BLENDER45.md")
    with open(out, "w") as f:
        f.write("# The add-on's hand-off in Blender 3.4 and 4.5 (bench/blender_handoff.py --bpy)\n\n" +
                time.strftime("%Y-%m-%d") + ", %s; the writer alone (export_photonbridge.py's own timer: "
                "instances, to_mesh, numpy, materials, the .gltf/.bin), median of 3 runs each, the two Blenders "
                "alternating scene by scene in one run; load average at start %.2f.\n\n" %
                (platform_line(), os.getloadavg()[0]) + text)
    return 0


def platform_line():
    import platform
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next((l.split(":", 1)[1].strip() for l in f if l.startswith("model name")), platform.machine())
    except OSError:
        cpu = platform.machine()
    return "%s, %d cores" % (cpu, os.cpu_count() or 0)


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
    ap.add_argument("--bpy", help="Python with bpy 4.5 (tools/bpy45/bin/python): compare the writer in 3.4 and 4.5")
    a = ap.parse_args()
    exe = os.path.abspath(a.exe)
    os.makedirs(a.cache, exist_ok=True)
    big = os.path.join(a.cache, "grid_1m.blend")
    if not os.path.isfile(big):
        blender(["--python-expr", SCENE_1M, "--", big])
    if a.bpy:
        return versions(a, big)
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
