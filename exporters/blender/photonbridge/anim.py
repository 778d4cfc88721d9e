"""The frame range as one glTF with animation, for "Render Animation as One
Sequence" (`photonbridge render --frames`).

The scene is written at the first frame (writer.py); then every frame of the
range is evaluated with RenderEngine.frame_set (the API Blender gives render
engines for other times) and each node's transform is sampled: instances,
lights and the camera, matched from frame to frame by instance_key. Nodes
that move get LINEAR translation/rotation/scale channels with one key per
frame at t = (frame - start) x fps_base / fps seconds (the extension's time,
exporters/blender/PHOTONBRIDGE_blender.md), the same sampling Blender's
exporter does with "Always Sample Animations". What glTF node animation
cannot carry (deforming meshes, changing light power or camera lens,
instances that appear later) is a warning; the frame at the start is
restored at the end."""
import os
import time

import numpy as np

from . import writer


def _trs_arrays(m):
    loc, rot, scale = m.decompose()
    return [loc.x, loc.y, loc.z], [rot.x, rot.y, rot.z, rot.w], [scale.x, scale.y, scale.z]


def write_sequence_gltf(engine, depsgraph, path, camera):
    """Writes frames scene.frame_start .. frame_end of `depsgraph` to `path`
    with node animation; engine: the RenderEngine (for frame_set). Returns
    the writer's report."""
    t0 = time.perf_counter()
    scene = depsgraph.scene
    start, end, current = scene.frame_start, scene.frame_end, scene.frame_current
    fps = scene.render.fps / scene.render.fps_base
    engine.frame_set(start, 0.0)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    w = writer.SceneWriter(depsgraph, path, camera)
    w.collect()
    cam = w.camera or scene.camera
    samples = {key: [] for key in w.node_of}
    counts = {}
    lens0 = cam.data.lens if cam is not None and cam.type == 'CAMERA' else None
    for f in range(start, end + 1):
        engine.frame_set(f, 0.0)
        seen = set()
        for inst in depsgraph.object_instances:
            obj = inst.object
            key = writer.instance_key(inst)
            if key not in samples:
                if obj.type in writer.GEOMETRY_TYPES or obj.type == 'LIGHT':
                    w.warn("object '%s' appears after the first frame; it is not in the sequence" % obj.name)
                continue
            m = writer.rigid_matrix(inst.matrix_world) if obj.type == 'LIGHT' else writer.node_matrix(inst)
            samples[key].append(_trs_arrays(m))
            seen.add(key)
            if obj.type in writer.GEOMETRY_TYPES and len(obj.data.vertices if obj.type == 'MESH' else ()) != \
                    counts.setdefault(key, len(obj.data.vertices) if obj.type == 'MESH' else 0):
                w.warn("object '%s': its mesh changes over the frames; the sequence moves it rigidly" % obj.name)
        if cam is not None and "camera" in samples:
            ce = cam.evaluated_get(depsgraph)
            samples["camera"].append(_trs_arrays(writer.rigid_matrix(ce.matrix_world)))
            seen.add("camera")
            if lens0 is not None and abs(ce.data.lens - lens0) > 1e-6:
                w.warn("camera '%s': its lens changes over the frames; the sequence keeps the first" % cam.name)
        for key in samples:
            if key not in seen and samples[key]:
                samples[key].append(samples[key][-1])  # hidden this frame: held
    engine.frame_set(current, 0.0)
    times = np.array([(f - start) / fps for f in range(start, end + 1)], np.float32)
    channels, anim_samplers = [], []
    t_acc = None
    for key, keys in samples.items():
        if len(keys) != len(times):
            continue
        node = w.node_of[key]
        for path_index, (name, kind) in enumerate((("translation", "VEC3"), ("rotation", "VEC4"),
                                                    ("scale", "VEC3"))):
            values = np.array([k[path_index] for k in keys], np.float32)
            if name == "rotation":  # the shorter arc between keys (no sign flips)
                for i in range(1, len(values)):
                    if np.dot(values[i], values[i - 1]) < 0:
                        values[i] = -values[i]
            if np.all(np.abs(values - values[0]) < 1e-7):
                continue
            if t_acc is None:
                t_acc = w.doc.accessor(times.reshape(-1, 1), "SCALAR", target=None, minmax=True)
            out = w.doc.accessor(values, kind, target=None)
            anim_samplers.append({"input": t_acc, "output": out, "interpolation": "LINEAR"})
            channels.append({"sampler": len(anim_samplers) - 1, "target": {"node": node, "path": name}})
    if channels:
        w.doc.j["animations"] = [{"name": "Blender frames %d-%d" % (start, end), "channels": channels,
                                  "samplers": anim_samplers}]
    return w.finish(t0, (start, end))
