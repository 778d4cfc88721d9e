#!/usr/bin/env python3
"""Packs the Blender add-on (exporters/blender/photonbridge) as the two zips
Blender installs:

  photonbridge-VERSION-addon.zip      the legacy add-on (bl_info), for
      Blender 3.4 to 5.x: Preferences > Add-ons > Install from Disk
      (4.2+: the menu's "Install from Disk" under Add-ons, marked legacy);
      the zip holds the folder photonbridge/.
  photonbridge-VERSION-extension.zip  the Blender 4.2+ extension
      (blender_manifest.toml at the zip's root, as `blender --command
      extension build` lays it out): Get Extensions > Install from Disk,
      or drag it onto Blender.

Only the package's own files go in (no __pycache__). The version must be
the same in CMakeLists.txt (the CLI), bl_info and the manifest; a mismatch
is an error naming both.

usage: blender_package.py OUT_DIR"""
import os
import re
import sys
import zipfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PKG = os.path.join(ROOT, "exporters", "blender", "photonbridge")


def versions():
    with open(os.path.join(ROOT, "CMakeLists.txt")) as f:
        cli = re.search(r"project\(photonbridge VERSION ([0-9.]+)", f.read()).group(1)
    with open(os.path.join(PKG, "__init__.py")) as f:
        m = re.search(r'"version":\s*\((\d+),\s*(\d+),\s*(\d+)\)', f.read())
        addon = ".".join(m.groups())
    with open(os.path.join(PKG, "blender_manifest.toml")) as f:
        manifest = re.search(r'^version\s*=\s*"([^"]+)"', f.read(), re.M).group(1)
    return cli, addon, manifest


def files():
    for dirpath, dirnames, filenames in os.walk(PKG):
        dirnames[:] = sorted(d for d in dirnames if d != "__pycache__")
        for name in sorted(filenames):
            if name.endswith((".pyc", ".pyo")):
                continue
            full = os.path.join(dirpath, name)
            yield full, os.path.relpath(full, PKG)


def main(argv):
    if len(argv) != 2:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    out = os.path.abspath(argv[1])
    cli, addon, manifest = versions()
    if not cli == addon == manifest:
        print("blender_package: versions differ: CMakeLists.txt %s, bl_info %s, blender_manifest.toml %s"
              % (cli, addon, manifest), file=sys.stderr)
        return 1
    os.makedirs(out, exist_ok=True)
    made = []
    for kind, prefix in (("addon", "photonbridge/"), ("extension", "")):
        path = os.path.join(out, "photonbridge-%s-%s.zip" % (cli, kind))
        tmp = path + ".tmp"
        with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
            for full, rel in files():
                z.write(full, prefix + rel.replace(os.sep, "/"))
        os.replace(tmp, path)  # never a half-written zip under the final name
        made.append(path)
    for p in made:
        print("blender_package: %s" % p)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
