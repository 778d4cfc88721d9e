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
(the halt test runs only there); --engine photongi adds PhotonGI's indirect
and caustic caches (--photons, --caustic-photons), --engine bidirvm renders
with BIDIRVMCPU (VCM) instead. Mitsuba 3: the `path` integrator of
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
    engine = "PATHCPU"
    if a.engine == "photongi":
        # PATHCPU with both PhotonGI caches (LuxCore's PhotonGICache, the
        # properties of pgicproperties.cpp): the indirect cache traced once
        # before rendering, visibility-guided, automatic lookup radius; the
        # caustic cache retraced every 8 spp with its radius shrinking by
        # 0.96 down to 3 mm. Photon paths up to 64 events (the core's
        # default 4 cuts a closed room's indirect light); no persistent file.
        for k, v in (("path.photongi.sampler.type", "METROPOLIS"),
                     ("path.photongi.photon.maxcount", a.photons),
                     ("path.photongi.photon.maxdepth", 64),
                     ("path.photongi.indirect.enabled", 1),
                     ("path.photongi.indirect.maxsize", a.indirect_maxsize),
                     ("path.photongi.indirect.haltthreshold", a.pgi_halt),
                     ("path.photongi.caustic.enabled", 1),
                     ("path.photongi.caustic.maxsize", a.caustic_photons),
                     ("path.photongi.caustic.lookup.radius", 0.075),
                     ("path.photongi.caustic.updatespp", 8),
                     ("path.photongi.caustic.updatespp.radiusreduction", 0.96),
                     ("path.photongi.caustic.updatespp.minradius", 0.003),
                     ("path.photongi.persistent.file", "")):
            props.Set(lc.Property(k, v))
    elif a.engine == "bidirvm":
        # Vertex connection and merging (a progressive photon-mapping
        # estimator with a shrinking merge radius): BIDIRVMCPU with its
        # defaults (start radius 0.003 x the scene's radius, alpha 0.95),
        # --light-paths light paths a pass (LuxCore's default 16384; a pass
        # traces as many eye paths, so it adds light-paths / pixels samples
        # per pixel: measured, 16 spp a pass at 32x32), both path depths at
        # 64. The film filter is a 1-pixel box (half-width 0.5): with NONE,
        # LuxCore 2.11 drops the light paths' splats (measured on
        # cornell_caustics: the image at about half the reference's mean).
        engine = "BIDIRVMCPU"
        for k, v in (("renderengine.type", engine), ("light.maxdepth", 64), ("path.maxdepth", 64),
                     ("film.filter.type", "BOX"), ("film.filter.width", 0.5),
                     ("bidirvm.lightpath.count", a.light_paths)):
            props.Set(lc.Property(k, v))
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
    if os.environ.get("PB_PEER_LOG"):
        with open(os.environ["PB_PEER_LOG"], "w") as f:
            f.write("\n".join(log) + "\n")
    pgi = {}
    for line in log:  # PhotonGI's counts, from its log lines (photongicache.cpp)
        for key, pat in (("photons_traced", "PhotonGI total photon traced: "),
                         ("indirect_photons_stored", "PhotonGI total radiance photon stored: "),
                         ("caustic_photons_stored", "PhotonGI total caustic photon stored: "),
                         ("indirect_radius", "PhotonGI best indirect cache radius: ")):
            if pat in line:
                try:
                    pgi[key] = float(line.split(pat, 1)[1].split()[0])
                except (ValueError, IndexError):
                    pass
    return {"peer": "luxcore", "version": lc.Version(), "engine": engine, "luxcore_engine": a.engine,
            "spp_reached": passes, "photongi": pgi or None,
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
    p.add_argument("--engine", choices=["path", "photongi", "bidirvm"], default="path",
                   help="LuxCore: PATHCPU (path), PATHCPU + PhotonGI indirect and caustic caches, BIDIRVMCPU")
    p.add_argument("--photons", type=int, default=2000000, help="LuxCore PhotonGI: photon.maxcount")
    p.add_argument("--pgi-halt", type=float, default=0.05,
                   help="LuxCore PhotonGI: indirect.haltthreshold (0.05 LuxCore's 'final', 0.15 its 'preview')")
    p.add_argument("--indirect-maxsize", type=int, default=0,
                   help="LuxCore PhotonGI: indirect.maxsize (0: trace until --pgi-halt)")
    p.add_argument("--light-paths", type=int, default=16384, help="LuxCore BIDIRVMCPU: bidirvm.lightpath.count")
    p.add_argument("--caustic-photons", type=int, default=100000, help="LuxCore PhotonGI: caustic.maxsize")
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
