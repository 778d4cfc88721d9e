#!/usr/bin/env python3
"""The scheduler's overhead per task: a shot on the one-node
Slurm cluster of tests/farm/slurm_cluster.py (re-executed under
`unshare -n`, root) against one process rendering the same frames.

The cluster gets CPUs=1, so the array's tasks run one after another and
the wall time from `submit` to the end of the check job, less the sum of the
chunks' photonbridge times (status/chunk_I.json), is the scheduler's and
the wrapper's overhead (plus the check job). Prints the per-chunk times
and the model for N nodes: T(N) = ceil(chunks / N) * (t_chunk + o) + t_check.

usage: farm_slurm.py PHOTONBRIDGE ROOT WORKDIR [--frames 48] [--chunk 8] [--warmup 0] [--size 32]"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

ROOT_GUESS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
sys.path.insert(0, os.path.join(ROOT_GUESS, "tests", "farm"))
import slurm_cluster  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe")
    ap.add_argument("root")
    ap.add_argument("work")
    ap.add_argument("--scene", default="cornell_box_moving_light")
    ap.add_argument("--frames", type=int, default=48)
    ap.add_argument("--chunk", type=int, default=8)
    ap.add_argument("--warmup", type=int, default=0)
    ap.add_argument("--size", type=int, default=32)
    ap.add_argument("--photons", type=int, default=8192)
    a = ap.parse_args()
    if os.environ.get("PB_FARM_NETNS") != "1":
        env = dict(os.environ, PB_FARM_NETNS="1")
        sys.exit(subprocess.run(["unshare", "-n", sys.executable, os.path.abspath(__file__)] + sys.argv[1:],
                                env=env).returncode)
    exe, root, work = (os.path.abspath(x) for x in (a.exe, a.root, a.work))
    scene = os.path.join(root, "samples", a.scene, a.scene + ".gltf")
    opts = ["--width", str(a.size), "--height", str(a.size), "--photons", str(a.photons), "-q"]
    subprocess.run(["rm", "-rf", work], check=True)
    os.makedirs(work + "/one")
    t0 = time.time()
    subprocess.run([exe, "render", scene, "--frames=%d:%d" % (-a.warmup, a.frames - 1), "-o",
                    work + "/one/f_###.exr"] + opts, check=True)
    t_one = time.time() - t0
    slurm_cluster.setup_loopback()
    with slurm_cluster.SlurmCluster(os.path.join(work, "cluster"), cpus=1) as cl:
        state = os.path.join(work, "state")
        t0 = time.time()
        subprocess.run([sys.executable, os.path.join(root, "scripts", "farm", "slurm_render.py"), "submit", scene,
                        "--frames", "0:%d" % (a.frames - 1), "--chunk", str(a.chunk), "--warmup", str(a.warmup),
                        "-o", work + "/shot/f_###.exr", "--state", state, "--photonbridge", exe, "--wait", "--"] +
                       opts, check=True, env=cl.env)
        t_slurm = time.time() - t0
    st = [json.load(open(os.path.join(state, "status", f))) for f in sorted(os.listdir(os.path.join(state, "status")))]
    times = [s["seconds"] for s in st]
    n = len(times)
    o = (t_slurm - sum(times)) / n
    print("one process: %d frames (+%d warm-up) of %s at %d px, %d photons: %.1f s" %
          (a.frames, a.warmup, a.scene, a.size, a.photons, t_one))
    print("slurm, 1 CPU: %d tasks of %d frames (+%d warm-up): %.1f s wall; photonbridge per chunk %s s "
          "(sum %.1f); overhead per task (scheduling, wrapper, check job shared) %.2f s" %
          (n, a.chunk, a.warmup, t_slurm, " ".join("%.1f" % t for t in times), sum(times), o))
    tc = sum(times) / n
    for nodes in (1, 2, 4, 6):
        print("model, %d node(s): %.1f s" % (nodes, math.ceil(n / nodes) * (tc + o)))
    print("leftovers: %s" % cl.leftovers)


if __name__ == "__main__":
    main()
