#!/usr/bin/env python3
"""Structure of an `export-peer` dump against what the loader reports.

    peer_dump_check.py PHOTONBRIDGE SCENE.gltf luxcore|mitsuba WORKDIR [--render PYTHON]

Dumps SCENE into WORKDIR/dump and checks, against `info --json`:
  - every mN.ply: the header is exactly binary little-endian, vertex
    `x y z nx ny nz s t` floats and face `list uchar uint vertex_indices`;
    the file size is the header's counts; every face is a triangle with
    indices inside the vertex list; normals are unit; positions inside the
    loader's bounds;
  - the PLYs' vertices and triangles add up to the loader's counts;
  - the scene file names every PLY and texture written, and every file it
    names exists; one light entry per loaded light; for Mitsuba the XML
    parses.
With --render, PYTHON (the peer's venv: tools/luxcore/bin/python or
tools/mitsuba3/bin/python) renders the dump with validation/peer_render.py
(32 px wide, 4 samples): the peer must accept it and give a finite,
non-black image. A missing PYTHON is a failure, not a skip.
Prints one line per check and "N passed, M failed".
"""
import glob
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET

passed = failed = 0


def check(cond, what):
    global passed, failed
    if cond:
        passed += 1
    else:
        failed += 1
        print("FAIL", what)


HEADER = ["format binary_little_endian 1.0", "property float x", "property float y", "property float z",
          "property float nx", "property float ny", "property float nz", "property float s", "property float t",
          "property list uchar uint vertex_indices"]


def read_ply(path, lo, hi):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    lines = [l for l in data[:end].decode("ascii").split("\n") if l and not l.startswith("comment")]
    check(lines[0] == "ply", f"{path}: magic")
    body = [l for l in lines if l.startswith(("format", "property"))]
    check(body == HEADER, f"{path}: header properties {body}")
    nv = int(re.search(r"element vertex (\d+)", data[:end].decode()).group(1))
    nt = int(re.search(r"element face (\d+)", data[:end].decode()).group(1))
    check(len(data) == end + nv * 32 + nt * 13, f"{path}: size {len(data)} for {nv} vertices, {nt} faces")
    verts = struct.unpack_from(f"<{nv * 8}f", data, end)
    bad_n = bad_p = 0
    for i in range(nv):
        x, y, z, nx, ny, nz = verts[i * 8:i * 8 + 6]
        if abs(math.sqrt(nx * nx + ny * ny + nz * nz) - 1) > 1e-3:
            bad_n += 1
        if not all(lo[k] - 1e-3 <= (x, y, z)[k] <= hi[k] + 1e-3 for k in range(3)):
            bad_p += 1
    check(bad_n == 0, f"{path}: {bad_n} normals not unit")
    check(bad_p == 0, f"{path}: {bad_p} positions outside the loader's bounds")
    off = end + nv * 32
    bad_f = 0
    for t in range(nt):
        n, a, b, c = struct.unpack_from("<BIII", data, off + t * 13)
        if n != 3 or max(a, b, c) >= nv:
            bad_f += 1
    check(bad_f == 0, f"{path}: {bad_f} faces not triangles or indices out of range")
    return nv, nt


def main():
    exe, scene, fmt, work = sys.argv[1:5]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    info_path = os.path.join(work, "info.json")
    subprocess.run([exe, "info", scene, "--json", info_path], check=True, stdout=subprocess.DEVNULL)
    info = json.load(open(info_path))
    dump = os.path.join(work, "dump")
    r = subprocess.run([exe, "export-peer", scene, "--format", fmt, "-o", dump, "--width", "32"],
                       capture_output=True, text=True)
    print(r.stdout, end="")
    check(r.returncode == 0, f"export-peer exit {r.returncode}: {r.stderr.strip()}")
    if r.returncode != 0:
        print(f"{passed} passed, {failed} failed")
        return 1
    lo, hi = info["bounds_min"], info["bounds_max"]
    plys = sorted(glob.glob(os.path.join(dump, "m*.ply")))
    tv = tt = 0
    for p in plys:
        nv, nt = read_ply(p, lo, hi)
        tv += nv
        tt += nt
    check(tt == info["triangles"], f"triangles: dump {tt}, loader {info['triangles']}")
    check(tv == info["vertices"], f"vertices: dump {tv}, loader {info['vertices']}")
    written = {os.path.basename(p) for p in plys} | {os.path.basename(p) for p in glob.glob(os.path.join(dump, "*.exr"))}
    text = open(os.path.join(dump, "scene.scn" if fmt == "luxcore" else "scene.xml")).read()
    if fmt == "luxcore":
        named = set(re.findall(r"^scene\.(?:shapes\.\w+\.ply|textures\.\w+\.file) = (\S+)$", text, re.M))
        lights = len(re.findall(r"^scene\.lights\.l\d+\.type = ", text, re.M))
        cfg = open(os.path.join(dump, "render.cfg")).read()
        check("scene.file = scene.scn" in cfg, "render.cfg names scene.scn")
        check(re.search(r"^film\.width = 32$", cfg, re.M) is not None, "render.cfg film.width 32")
    else:
        root = ET.fromstring(text)  # raises on malformed XML
        check(root.tag == "scene" and root.get("version") == "3.0.0", "scene.xml root")
        named = {e.get("value") for e in root.iter("string") if e.get("name") == "filename"}
        lights = sum(1 for e in root.findall("emitter") if e.get("type") in ("point", "spot", "directional"))
        check(root.find("sensor/film/integer[@name='width']").get("value") == "32", "scene.xml film width 32")
    check(named == written, f"files named {sorted(named)} == written {sorted(written)}")
    check(all(os.path.exists(os.path.join(dump, n)) for n in named), "named files exist")
    check(lights == len(info["lights"]), f"lights: dump {lights}, loader {len(info['lights'])}")
    print(f"{os.path.basename(scene)} {fmt}: {len(plys)} PLY, {tv} vertices, {tt} triangles")
    if len(sys.argv) > 6 and sys.argv[5] == "--render":
        py = sys.argv[6]
        if not os.access(py, os.X_OK):
            check(False, f"{py} missing: run scripts/install-deps.sh")
        else:
            out = os.path.join(work, "render.exr")
            here = os.path.dirname(os.path.abspath(__file__))
            r = subprocess.run([py, os.path.join(here, "..", "validation", "peer_render.py"), fmt, dump, out,
                                "--spp", "4", "--threads", "2"], capture_output=True, text=True, timeout=600)
            check(r.returncode == 0 and os.path.exists(out + ".json"),
                  f"{fmt} render exit {r.returncode}: {r.stderr.strip()[-400:]}")
            if os.path.exists(out + ".json"):
                res = json.load(open(out + ".json"))
                mean = res.get("mean_rgb", [0, 0, 0])
                print(f"{fmt} {res['version']}: mean RGB {mean}, {res['render_s']:.2f} s")
                check(all(math.isfinite(m) for m in mean) and max(mean) > 0, f"{fmt} image black or not finite")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
