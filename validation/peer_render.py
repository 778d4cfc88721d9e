#!/usr/bin/env python3
"""Renders a `photonbridge export-peer` folder with its peer, to a linear EXR.

    tools/luxcore/bin/python  validation/peer_render.py luxcore DIR OUT.exr [--spp N] [--threads N] [--seed N]
    tools/mitsuba3/bin/python validation/peer_render.py mitsuba DIR OUT.exr [--spp N] [--threads N] [--seed N]
                                                                  [--variant scalar_rgb|llvm_ad_rgb]

Run each peer in its own process and interpreter (tools/luxcore, tools/mitsuba3:
scripts/install-deps.sh): both wheels carry their own TBB and Embree.
Writes OUT.exr (float, R G B, top row first) and OUT.exr.json (peer version,
settings, seconds to build the scene and to render, the image's mean RGB). LuxCore prints its own
lines on stdout; this script's one-line summary goes to stderr.

LuxCore: PATHCPU as DIR/render.cfg says (2 threads, no pixel filter, Sobol
without adaptivity, depth 64), halting at --spp, polled through UpdateStats
(the halt test runs only there). Mitsuba 3: the `path` integrator of
DIR/scene.xml; "2 threads" is one Dr.Jit worker plus the calling thread.
"""
import argparse
import json
import os
import sys
import time


def render_luxcore(a):
    import pyluxcore as lc
    log = []
    lc.Init(log.append)
    os.chdir(a.dir)
    t0 = time.monotonic()
    props = lc.Properties("render.cfg")
    props.Set(lc.Property("batch.haltspp", a.spp))
    props.Set(lc.Property("native.threads.count", a.threads))
    props.Set(lc.Property("renderengine.seed", a.seed + 1))
    props.Set(lc.Property("film.outputs.0.filename", a.out))
    config = lc.RenderConfig(props)
    session = lc.RenderSession(config)
    t1 = time.monotonic()
    session.Start()
    while True:
        time.sleep(0.02)
        session.UpdateStats()
        if session.HasDone():
            break
    stats = session.GetStats()
    passes = stats.Get("stats.renderengine.pass").GetInt()
    film = session.GetFilm()
    film.SaveOutputs()
    import numpy as np
    rgb = np.zeros(film.GetWidth() * film.GetHeight() * 3, np.float32)
    film.GetOutputFloat(lc.FilmOutputType.RGB, rgb)
    session.Stop()
    t2 = time.monotonic()
    return {"peer": "luxcore", "version": lc.Version(), "engine": "PATHCPU", "spp_reached": passes,
            "build_s": t1 - t0, "render_s": t2 - t1, "mean_rgb": rgb.reshape(-1, 3).mean(axis=0).tolist()}


def render_mitsuba(a):
    import mitsuba as mi
    import drjit as dr
    mi.set_variant(a.variant)
    # Dr.Jit's pool with one worker (the calling thread helping: "2
    # threads", as `mitsuba -t 2`) hangs in drjit 1.5.0 (a textured scene's
    # render, any Bitmap.write; measured), so the pool gets --threads workers
    # and the caller only waits: pin the process (taskset) to bound the cores.
    dr.set_thread_count(max(a.threads, 2))
    t0 = time.monotonic()
    scene = mi.load_file(os.path.join(a.dir, "scene.xml"), spp=str(a.spp))
    t1 = time.monotonic()
    img = mi.render(scene, spp=a.spp, seed=a.seed)
    bmp = mi.Bitmap(img, mi.Bitmap.PixelFormat.RGB)
    bmp.write(a.out)
    t2 = time.monotonic()
    import numpy as np
    mean = np.asarray(img, dtype=np.float64).reshape(-1, 3).mean(axis=0).tolist()
    return {"peer": "mitsuba", "version": mi.__version__, "drjit": dr.__version__, "variant": a.variant,
            "spp_reached": a.spp, "build_s": t1 - t0, "render_s": t2 - t1, "mean_rgb": mean}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("peer", choices=["luxcore", "mitsuba"])
    p.add_argument("dir")
    p.add_argument("out")
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--variant", default="scalar_rgb")
    a = p.parse_args()
    a.dir = os.path.abspath(a.dir)
    a.out = os.path.abspath(a.out)
    info = render_luxcore(a) if a.peer == "luxcore" else render_mitsuba(a)
    info.update({"spp": a.spp, "threads": a.threads, "seed": a.seed, "scene_dir": a.dir})
    with open(a.out + ".json", "w") as f:
        json.dump(info, f, indent=1)
    print(f"peer_render: {a.peer} {info['version']} {a.out} ({info['spp_reached']} spp, "
          f"{info['render_s']:.2f} s)", file=sys.stderr)
    sys.stderr.flush()
    sys.stdout.flush()
    # pyluxcore 2.11.2 calls its Python log handler while the interpreter
    # finalises and aborts (GIL not held): leave without finalising.
    os._exit(0)


if __name__ == "__main__":
    main()
