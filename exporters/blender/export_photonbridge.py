"""Headless hand-off: the photonbridge render engine's glTF writer on a
.blend, without rendering (the same writer as F12 and File > Export >
photonbridge glTF).

    blender -b scene.blend --factory-startup --python-exit-code 1 \\
        -P exporters/blender/export_photonbridge.py -- OUT.gltf [--frame N | --animation] [--json REPORT.json]

--animation writes the scene's frame range as one glTF with node animation,
as "Render Animation as One Sequence" hands it to `photonbridge render
--frames` (anim.py).

Prints one line with the counts and the time the writer took; --json writes
them (and the warnings) as JSON."""
import argparse
import json
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from photonbridge import anim, writer  # noqa: E402


class SceneFrames:
    """anim.write_sequence_gltf's engine outside a render: frame_set moves
    the scene (RenderEngine.frame_set inside one)."""

    def __init__(self, scene):
        self.scene = scene

    def frame_set(self, frame, subframe):
        self.scene.frame_set(frame, subframe=subframe)


def main(argv):
    ap = argparse.ArgumentParser(prog="export_photonbridge.py")
    ap.add_argument("out", help="the .gltf to write (a .bin and images beside it)")
    ap.add_argument("--frame", type=int, help="scene frame to write (default: the current one)")
    ap.add_argument("--animation", action="store_true", help="the frame range as one glTF with node animation")
    ap.add_argument("--json", help="write the report (counts, seconds, warnings) as JSON")
    args = ap.parse_args(argv)
    scene = bpy.context.scene
    if args.frame is not None:
        scene.frame_set(args.frame)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    if args.animation:
        report = anim.write_sequence_gltf(SceneFrames(scene), depsgraph, os.path.abspath(args.out), None)
    else:
        report = writer.write_gltf(depsgraph, os.path.abspath(args.out))
    for w in report.warnings:
        print("export_photonbridge: warning: " + w)
    for w in report.notes:
        print("export_photonbridge: note: " + w)
    print("export_photonbridge: %d triangles, %d meshes, %d instances, %d lights in %.3f s -> %s"
          % (report.triangles, report.meshes, report.instances, report.lights, report.seconds, args.out))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"triangles": report.triangles, "meshes": report.meshes, "instances": report.instances,
                       "lights": report.lights, "seconds": report.seconds, "warnings": report.warnings,
                       "notes": report.notes}, f, indent=1)


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
