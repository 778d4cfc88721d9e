#!/usr/bin/env python3
"""A shot on a one-node Slurm cluster (scripts/farm/slurm_render.py).

The test starts munged, slurmctld and slurmd itself (tests/farm/
slurm_cluster.py) in a private network namespace (it re-executes itself
under `unshare -n`, lo up with a second address), and stops every one by its
process id; afterwards no process naming the cluster's folder is left.

  submit  cornell_box_moving_light 0..5 (32 px, few photons) as 3 array
          tasks of 2 frames, warm-up 2; chunk 1's photonbridge is killed
          (SIGKILL, by its process id) after its first frame; the check job's
          summary names chunk 1 alone, killed, with its frames missing, and
          no partial frame or temporary is left; `resubmit` submits chunk 1
          alone and the shot completes; per-chunk logs exist; every frame
          equals the single-process render of the same frames after the
          same warm-up (frames a..b of `render --frames a-2:b`, to float
          rounding).

usage: slurm_check.py PHOTONBRIDGE EXR_PROBE ROOT WORKDIR
Exit 77 (one line) without slurm-wlm/munge, without permission for network
namespaces, or without a Vulkan device."""
import glob
import json
import os
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import slurm_cluster  # noqa: E402
from common import RENDER, ROUNDING, check, failures, fresh, has_device, run, sample, worst_rel  # noqa: E402

ONE_AT_A_TIME = ["--frames-in-flight", "1"]

EXE, PROBE, ROOT, WORK = [os.path.abspath(a) for a in sys.argv[1:5]]
FARM = os.path.join(ROOT, "scripts", "farm", "slurm_render.py")
WARM, CHUNK, FIRST, LAST = 2, 2, 0, 5


def find_chunk_render(cluster_dir, task_id):
    """The pid of the photonbridge render of array task `task_id` of this
    cluster, or None."""
    needle = b"SLURM_CONF=" + cluster_dir.encode()
    tid = b"SLURM_ARRAY_TASK_ID=%d" % task_id
    for e in os.listdir("/proc"):
        if not e.isdigit():
            continue
        try:
            with open("/proc/%s/cmdline" % e, "rb") as f:
                cmd = f.read().split(b"\0")
            with open("/proc/%s/environ" % e, "rb") as f:
                env = f.read().split(b"\0")
        except OSError:
            continue
        if (len(cmd) > 1 and cmd[0] == EXE.encode() and cmd[1] == b"render" and tid in env and
                any(v.startswith(needle) for v in env)):
            return int(e)
    return None


def farm(args, env, expect_rc=0):
    return run([sys.executable, FARM] + args, expect_rc=expect_rc, env=env)


def inside():
    slurm_cluster.setup_loopback()
    fresh(WORK)
    out = os.path.join(WORK, "shot")
    state = os.path.join(WORK, "state")
    cl = slurm_cluster.SlurmCluster(os.path.join(WORK, "cluster"), cpus=2)
    t0 = time.time()
    try:
        cl.start()
        print("cluster up in %.1f s" % (time.time() - t0))
        env = cl.env
        p = farm(["submit", sample(ROOT), "--frames", "%d:%d" % (FIRST, LAST), "--chunk", str(CHUNK),
                  "--warmup", str(WARM), "-o", out + "/f_##.exr", "--state", state, "--photonbridge", EXE,
                  "--"] + RENDER + ONE_AT_A_TIME, env)
        check(p.returncode == 0, "submit: the array and its check submitted")
        # Kill chunk 1's render while it runs: between its two frames' files,
        # which with frames in flight (render's default) follow each other
        # within one frame's last GPU pass, so the chunks render one frame at
        # a time here (ONE_AT_A_TIME) to leave the kill a frame's time.
        killed = None
        deadline = time.time() + 60
        while killed is None and time.time() < deadline:
            pid = find_chunk_render(cl.dir, 1)
            if pid and os.path.exists(out + "/f_02.exr"):  # after its first frame, before its last
                os.kill(pid, signal.SIGKILL)
                killed = pid
            else:
                time.sleep(0.01)
        check(killed is not None, "chunk 1's photonbridge found and killed (pid %s)" % killed)
        sub = [json.loads(l) for l in open(os.path.join(state, "submissions.jsonl"))]
        slurm_render_wait(sub[-1]["check_job"], env)
        p = farm(["status", "--state", state], env, expect_rc=1)
        check(p.returncode == 1, "status after the kill: exit 1")
        s = json.load(open(os.path.join(state, "summary.json")))
        check(s["failed_chunks"] == [1] and not s["complete"],
              "the summary names chunk 1 alone (%s)" % s["failed_chunks"])
        c1 = s["chunks"][1]
        check(c1["meaning"] == "killed by signal SIGKILL" and c1["exit"] == -9,
              "chunk 1's exit status surfaced: %s (%s)" % (c1["exit"], c1["meaning"]))
        check(all(os.path.exists(out + "/f_%02d.exr" % f) for f in (0, 1, 4, 5)),
              "chunks 0 and 2 wrote their frames")
        check(c1["missing_frames"] == [3] and not os.path.exists(out + "/f_03.exr"),
              "chunk 1 wrote frame 2 whole and nothing of frame 3 (missing %s)" % c1["missing_frames"])
        check(len(glob.glob(out + "/*.tmp.*")) == 0, "no temporary left in the output (removed: %d)" %
              len(s["removed_temporaries"]))
        check(all(os.path.exists(os.path.join(state, "logs", "chunk_%d.log" % i)) for i in range(3)),
              "one log per chunk")
        p = farm(["resubmit", "--state", state, "--wait"], env)
        check(p.returncode == 0, "resubmit --wait: exit 0, the shot complete")
        sub = [json.loads(l) for l in open(os.path.join(state, "submissions.jsonl"))]
        check(len(sub) == 2 and sub[0]["indices"] == [0, 1, 2] and sub[1]["indices"] == [1],
              "resubmit submitted chunk 1 alone (%s)" % [x["indices"] for x in sub])
        s = json.load(open(os.path.join(state, "summary.json")))
        check(s["complete"] and s["frames_ok"] == 6 and all(c["exit"] == 0 for c in s["chunks"]),
              "summary: 6 of 6 frames, every chunk exit 0")
        log1 = open(os.path.join(state, "logs", "chunk_1.log")).read()
        check(log1.count("slurm_render: chunk 1,") == 2, "chunk 1's log holds both attempts")
    except RuntimeError as e:
        check(False, "cluster: %s" % e)
    finally:
        cl.stop()
    check(not cl.leftovers, "nothing left behind after the cluster stopped (%s)" % cl.leftovers)
    print("cluster session %.1f s" % (time.time() - t0))
    # The frames against single-process renders of the same frames after the
    # same warm-up.
    for a in range(FIRST, LAST + 1, CHUNK):
        b = min(a + CHUNK - 1, LAST)
        ref = fresh(os.path.join(WORK, "ref_%d" % a))
        p = run([EXE, "render", sample(ROOT), "--frames=%d:%d" % (a - WARM, b), "-o", ref + "/f_##.exr"] + RENDER)
        check(p.returncode == 0, "single run %d:%d renders" % (a - WARM, b))
        for f in range(a, b + 1):
            if p.returncode != 0 or not os.path.exists(out + "/f_%02d.exr" % f):
                check(False, "frame %d present" % f)
                continue
            w = worst_rel(PROBE, out + "/f_%02d.exr" % f, ref + "/f_%02d.exr" % f)
            check(w <= ROUNDING, "frame %d from Slurm equals the single run's (%.3g of the peak)" % (f, w))


def slurm_render_wait(job, env):
    deadline = time.time() + 120
    while time.time() < deadline:
        p = subprocess.run(["squeue", "-h", "-j", job], capture_output=True, text=True, env=env)
        if p.returncode != 0 or not p.stdout.strip():
            return
        time.sleep(0.5)
    check(False, "check job %s ended within 120 s" % job)


if os.environ.get("PB_FARM_NETNS") != "1":
    slurm_cluster.enter_netns(__file__, has_device(EXE))
inside()
if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("all checks passed")
