#!/usr/bin/env python3
"""`photonbridge validate` on a one-node Slurm cluster
(scripts/farm/slurm_render.py validate), the cluster as in slurm_check.py
(started and stopped by this test in its own network namespace).

  cornell_box (24 px) and a scene that does not exist, with the reference
  and the GPU renderer (--renderers; POV-Ray and Cycles left out to stay
  quick): one array task per scene and renderer (4), then the check job
  writing each scene's report from its renderers' folders: summary.json has
  cornell_box ok with its photonbridge-vs-reference pair and the missing
  scene failed with validate's exit 2 ("bad command line") in both its
  tasks; DIR/index.html links cornell_box's report page, whose two renders
  were rendered by two tasks; no staging temporary is left; `resubmit`
  submits the failed scene's two tasks alone (and they fail again: exit 1);
  nothing is left running afterwards.

usage: slurm_validate_check.py PHOTONBRIDGE ROOT WORKDIR
Exit 77 (one line) as slurm_check.py."""
import glob
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import slurm_cluster  # noqa: E402
from common import check, failures, fresh, has_device, run  # noqa: E402

EXE, ROOT, WORK = [os.path.abspath(a) for a in sys.argv[1:4]]
FARM = os.path.join(ROOT, "scripts", "farm", "slurm_render.py")
VALIDATE = ["--width", "24", "--spp", "1", "--ref-spp", "4", "--threads", "1", "--no-povray", "--no-cycles"]


def inside():
    slurm_cluster.setup_loopback()
    fresh(WORK)
    state = os.path.join(WORK, "state")
    missing_scene = os.path.join(WORK, "no_such_scene.gltf")
    cl = slurm_cluster.SlurmCluster(os.path.join(WORK, "cluster"), cpus=2)
    t0 = time.time()
    try:
        cl.start()
        env = cl.env
        p = run([sys.executable, FARM, "validate", "cornell_box", missing_scene, "--state", state,
                 "--renderers", "reference,photonbridge", "--photonbridge", EXE, "--wait", "--"] + VALIDATE,
                expect_rc=1, env=env)
        check(p.returncode == 1, "validate --wait: exit 1 (one scene failed)")
        s = json.load(open(os.path.join(state, "summary.json")))
        sc = s["scenes"]
        check(len(sc) == 2 and sc[0]["ok"] and sc[0]["name"] == "cornell_box", "cornell_box validated")
        pair = [q for q in sc[0]["pairs"] if q["test"] == "photonbridge" and q["reference"] == "reference"]
        check(len(pair) == 1 and pair[0]["psnr_db"] and pair[0]["psnr_db"] > 5,
              "cornell_box: the photonbridge vs reference pair in the summary (%s)" % pair)
        check(not sc[1]["ok"] and sc[1]["exit"] == 2 and sc[1]["meaning"] == "bad command line" and
              [t["exit"] for t in sc[1]["tasks"]] == [2, 2],
              "the missing scene failed with validate's exit 2 in both tasks (%s, %s)" %
              (sc[1]["exit"], sc[1]["meaning"]))
        check(s["failed_chunks"] == [2, 3] and not s["complete"], "the summary names tasks 2 and 3 alone (%s)" %
              s["failed_chunks"])
        rep = json.load(open(os.path.join(state, "validate", "cornell_box", "report.json")))
        tasks = {r["name"]: r.get("command") for r in rep["renders"] if r["status"] == "ok"}
        # Each render's command wrote into its own task's staging folder
        # (validate/.stage/cornell_box/.NAME.tmp.PID, renamed after).
        check(sorted(tasks) == ["photonbridge", "reference"] and
              all(("/.stage/cornell_box/.%s.tmp." % n) in " ".join(c or []) for n, c in tasks.items()),
              "cornell_box's report: the two renders, each from its own task (%s)" % tasks)
        page = open(os.path.join(state, "index.html")).read()
        check('href="validate/cornell_box/index.html"' in page and
              os.path.exists(os.path.join(state, "validate", "cornell_box", "index.html")),
              "index.html links cornell_box's report page")
        check(not glob.glob(os.path.join(state, "validate", ".*.tmp.*")) and
              not glob.glob(os.path.join(state, "validate", ".stage", "*", ".*.tmp.*")), "no staging temporary left")
        check(all(os.path.exists(os.path.join(state, "logs", "task_%d.log" % i)) for i in range(4)),
              "one log per task")
        p = run([sys.executable, FARM, "resubmit", "--state", state, "--wait"], expect_rc=1, env=env)
        sub = [json.loads(l) for l in open(os.path.join(state, "submissions.jsonl"))]
        check(p.returncode == 1 and [x["indices"] for x in sub] == [[0, 1, 2, 3], [2, 3]],
              "resubmit: the failed scene's tasks alone, failing again (exit %d, %s)" % (p.returncode,
                                                                               [x["indices"] for x in sub]))
    except RuntimeError as e:
        check(False, "cluster: %s" % e)
    finally:
        cl.stop()
    check(not cl.leftovers, "nothing left behind after the cluster stopped (%s)" % cl.leftovers)
    print("cluster session %.1f s" % (time.time() - t0))


if os.environ.get("PB_FARM_NETNS") != "1":
    slurm_cluster.enter_netns(__file__, has_device(EXE))
inside()
if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("all checks passed")
