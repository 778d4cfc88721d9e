#!/usr/bin/env python3
"""A shot on a Slurm cluster as a job array (docs/farms.md).

  slurm_render.py submit SCENE --frames A:B -o OUT/f_####.exr --state DIR
                  [--chunk N] [--warmup W] [--photonbridge EXE] [--python PY]
                  [--sbatch ARG]... [--wait] [-- RENDER OPTIONS...]
  slurm_render.py resubmit --state DIR [--sbatch ARG]... [--wait]
  slurm_render.py status --state DIR
  slurm_render.py validate SCENE... --state DIR [--renderers LIST] [--photonbridge EXE]
                  [--sbatch ARG]... [--wait] [-- VALIDATE OPTIONS...]

submit cuts A..B into chunks of N frames (default 32), one array task per
chunk, each running `photonbridge render SCENE --frames a:b --warmup W -o
OUT ...` (the W frames before a rebuild the temporal history and are not
written; default 32; the photon seeds follow the frame number, so the
chunks' frames are those of one run of the shot up to history older than W
frames: docs/farms.md measures 32 to make a boundary invisible). A second
job, dependent on the whole array (afterany), checks every frame and writes
DIR/summary.json. --wait blocks until that check ends and exits with its
status. resubmit submits only the chunks the last check found failed (and a
new check); status prints the summary.

validate runs one array task per scene and renderer (--renderers, default
reference,photonbridge,povray,cycles; task i is scene i // R, renderer i % R):
`photonbridge validate SCENE --renderers R --render-only ...` into a staging
folder, renamed to DIR/validate/.stage/NAME/R once the renderer's record is
written (a killed task leaves only its temporary, which the check removes).
The dependent check job then writes each scene's report from its renderers'
folders (`validate SCENE --report-from ...`, renamed into DIR/validate/NAME),
DIR/summary.json and DIR/index.html (a link and each pair's PSNR/relMSE per
scene; "failed_chunks" there lists the failed tasks' indices, so resubmit
renders only the failed scene-renderer pairs again); status as above.

Everything lives in the state folder DIR, which must be on storage that the
submitting host and every node share (as OUT):
  plan.json              the shot: scene, frames, chunks, command line
  submissions.jsonl      one line per submission: job ids, array indices
  logs/chunk_I.log       each task's output (Slurm's -o, one per chunk;
                         a resubmission appends)
  logs/check_J.log       the check job's output
  status/chunk_I.json    a task's exit status: photonbridge's exit code and
                         its meaning (src/core/result.h), or the signal
  summary.json           the check: per chunk ok/failed, its exit status,
                         the frames missing; complete true/false
Every file is written atomically (a temporary then a rename); photonbridge
writes each frame so too, so a killed task leaves whole frames only (the
check removes and reports a killed writer's PATH.tmp.PID).

Exit status: 0 done (or submitted, without --wait); 1 frames failed (the
summary says which chunks); 2 bad command line; 3 sbatch or squeue failed."""
import argparse
import glob
import html
import json
import os
import shlex
import shutil
import signal
import subprocess
import sys
import time

# validate's renderers (validation/validate.py --renderers).
RENDERERS = ["reference", "photonbridge", "povray", "cycles"]

# src/core/result.h's table: photonbridge's exit codes.
EXIT_MEANING = {
    0: "ok", 1: "failed", 2: "bad command line", 3: "file could not be read or written",
    4: "scene file is not valid glTF", 5: "scene file breaks a glTF rule", 6: "scene uses an unsupported feature",
    7: "scene has nothing to render", 8: "image file is malformed", 9: "images do not match in size or channels",
    10: "input exceeds a size limit", 11: "out of memory", 12: "no usable Vulkan device", 13: "Vulkan call failed",
    14: "Vulkan device lost", 15: "component not built or not installed", 70: "internal error",
    127: "photonbridge not found on the node (--photonbridge)", 130: "interrupted (SIGINT)", 143: "interrupted (SIGTERM, e.g. scancel)",
}
EXR_MAGIC = b"\x76\x2f\x31\x01"
SELF = os.path.abspath(__file__)


def die(code, msg):
    print("slurm_render: " + msg, file=sys.stderr)
    sys.exit(code)


def write_atomic(path, text):
    tmp = "%s.tmp.%d" % (path, os.getpid())
    with open(tmp, "w") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def write_json(path, obj):
    write_atomic(path, json.dumps(obj, indent=1) + "\n")


def load_plan(state):
    p = os.path.join(state, "plan.json")
    try:
        with open(p) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        die(2, "%s: no readable plan (%s); run 'submit' first" % (p, e))


def frame_path(pattern, frame):
    """The output name of a frame: the run of '#' replaced by the frame
    number, zero-padded (as photonbridge's pb_seq_frame_path)."""
    i = pattern.find("#")
    if i < 0:
        return pattern
    n = len(pattern[i:]) - len(pattern[i:].lstrip("#"))
    return pattern[:i] + ("%0*d" % (n, frame)) + pattern[i + n:]


def parse_frames(text):
    try:
        a, _, b = text.partition(":")
        first, last = int(a), int(b or a)
    except ValueError:
        die(2, "--frames '%s': expected A:B, two frame numbers" % text)
    if last < first:
        die(2, "--frames '%s': A > B" % text)
    return first, last


def exit_meaning(rc):
    if rc is None:
        return "no exit status: the task was killed or never ran"
    if rc < 0:
        try:
            return "killed by signal %s" % signal.Signals(-rc).name
        except ValueError:
            return "killed by signal %d" % -rc
    return EXIT_MEANING.get(rc, "exit code %d" % rc)


# ---- submitting ---------------------------------------------------------------

def sbatch(args, env=None):
    cmd = ["sbatch", "--parsable"] + args
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    except OSError as e:
        die(3, "sbatch: %s" % e)
    if p.returncode != 0:
        die(3, "sbatch failed (exit %d): %s" % (p.returncode, p.stderr.strip()))
    return p.stdout.strip().split(";")[0]


def log_prefix(plan):
    return "task" if plan.get("kind") == "validate" else "chunk"


def submit_chunks(plan, state, indices, extra):
    """One array job over `indices`, then the check job after it."""
    logs = os.path.join(state, "logs")
    name = plan["name"]
    py = shlex.quote(plan.get("python") or "python3")
    array = ",".join(str(i) for i in indices)
    job = sbatch(["--job-name", "pb-" + name, "--array", array, "--open-mode=append",
                  "--output", os.path.join(logs, log_prefix(plan) + "_%a.log"), "--chdir", state] + extra +
                 ["--wrap", "exec %s %s task %s" % (py, shlex.quote(SELF), shlex.quote(state))])
    check = sbatch(["--job-name", "pb-" + name + "-check", "--dependency", "afterany:" + job,
                    "--output", os.path.join(logs, "check_%j.log"), "--chdir", state] + extra +
                   ["--wrap", "exec %s %s check %s" % (py, shlex.quote(SELF), shlex.quote(state))])
    rec = {"time": time.time(), "array_job": job, "indices": list(indices), "check_job": check}
    with open(os.path.join(state, "submissions.jsonl"), "a") as f:
        f.write(json.dumps(rec) + "\n")
    print("slurm_render: submitted %s (%ss %s) and check %s" % (job, log_prefix(plan), array, check))
    return rec


def wait_job(job, poll=1.0):
    while True:
        p = subprocess.run(["squeue", "-h", "-j", job, "-o", "%i"], capture_output=True, text=True)
        if p.returncode != 0 and "Invalid job id" not in p.stderr:
            die(3, "squeue failed (exit %d): %s" % (p.returncode, p.stderr.strip()))
        if p.returncode != 0 or not p.stdout.strip():
            return
        time.sleep(poll)


def finish(state, rec, wait):
    if not wait:
        return 0
    wait_job(rec["check_job"])
    return print_summary(state)


def cmd_submit(a, extra_render):
    first, last = parse_frames(a.frames)
    if a.chunk < 1:
        die(2, "--chunk %d: at least 1" % a.chunk)
    if a.warmup < 0:
        die(2, "--warmup %d: not negative" % a.warmup)
    if last > first and "#" not in a.output:
        die(2, "-o %s: a shot needs '#' in the name for the frame number" % a.output)
    state = os.path.abspath(a.state)
    for sub in ("", "logs", "status"):
        os.makedirs(os.path.join(state, sub), exist_ok=True)
    if os.path.exists(os.path.join(state, "plan.json")):
        die(2, "%s: already holds a shot (plan.json); use 'resubmit' or another --state" % state)
    os.makedirs(os.path.dirname(os.path.abspath(a.output)), exist_ok=True)
    chunks = [[f, min(f + a.chunk - 1, last)] for f in range(first, last + 1, a.chunk)]
    plan = {
        "name": os.path.splitext(os.path.basename(a.scene))[0],
        "scene": os.path.abspath(a.scene),
        "frames": [first, last],
        "chunk": a.chunk,
        "warmup": a.warmup,
        "output": os.path.abspath(a.output),
        "photonbridge": a.photonbridge,
        "python": a.python,
        "render_args": extra_render,
        "chunks": chunks,
    }
    write_json(os.path.join(state, "plan.json"), plan)
    rec = submit_chunks(plan, state, range(len(chunks)), a.sbatch or [])
    return finish(state, rec, a.wait)


def cmd_validate(a, extra):
    state = os.path.abspath(a.state)
    for sub in ("", "logs", "status", "validate"):
        os.makedirs(os.path.join(state, sub), exist_ok=True)
    if os.path.exists(os.path.join(state, "plan.json")):
        die(2, "%s: already holds a plan (plan.json); use 'resubmit' or another --state" % state)
    scenes, names = [], []
    for sc in a.scenes:
        # A file, or a sample's name (photonbridge validate resolves those).
        scenes.append(os.path.abspath(sc) if os.path.exists(sc) else sc)
        base = os.path.splitext(os.path.basename(sc))[0] or "scene"
        name, k = base, 2
        while name in names:
            name, k = "%s_%d" % (base, k), k + 1
        names.append(name)
    renderers = [r.strip() for r in a.renderers.split(",") if r.strip()]
    if not renderers or any(r not in RENDERERS for r in renderers) or len(set(renderers)) != len(renderers):
        die(2, "--renderers %s: a list of distinct names from %s" % (a.renderers, ",".join(RENDERERS)))
    plan = {"kind": "validate", "name": "validate", "scenes": scenes, "names": names, "renderers": renderers,
            "photonbridge": a.photonbridge, "python": a.python, "validate_args": extra,
            "out": os.path.join(state, "validate")}
    write_json(os.path.join(state, "plan.json"), plan)
    rec = submit_chunks(plan, state, range(len(scenes) * len(renderers)), a.sbatch or [])
    return finish(state, rec, a.wait)


def cmd_resubmit(a):
    state = os.path.abspath(a.state)
    plan = load_plan(state)
    summary = (check_validate if plan.get("kind") == "validate" else check_shot)(state, plan)  # on disk now
    failed = summary["failed_chunks"]
    if not failed:
        print("slurm_render: every task of %s is complete; nothing to resubmit" % state)
        return 0
    rec = submit_chunks(plan, state, failed, a.sbatch or [])
    return finish(state, rec, a.wait)


# ---- on the nodes ---------------------------------------------------------------

def render_command(plan, chunk):
    a, b = chunk
    return ([plan["photonbridge"], "render", plan["scene"], "--frames=%d:%d" % (a, b),
             "--warmup", str(plan["warmup"]), "-o", plan["output"]] + list(plan["render_args"]))


def run_child(cmd):
    """Runs cmd, passing scancel's SIGTERM on (photonbridge stops cleanly);
    its exit status (negative: the signal)."""
    try:
        child = subprocess.Popen(cmd)
    except OSError as e:
        print("slurm_render: %s: %s" % (cmd[0], e.strerror), flush=True)
        return 127

    def forward(sig, _frame):
        child.send_signal(sig)
    signal.signal(signal.SIGTERM, forward)
    signal.signal(signal.SIGINT, forward)
    return child.wait()


def replace_dir(stage, final):
    """stage renamed to final, an old final removed after (one rename is
    what readers can see)."""
    old = final + ".old.%d" % os.getpid()
    if os.path.exists(final):
        os.rename(final, old)
    os.rename(stage, final)
    shutil.rmtree(old, ignore_errors=True)


def task_of(plan, i):
    """Task i of a validate plan: (scene index, renderer)."""
    rs = plan["renderers"]
    return i // len(rs), rs[i % len(rs)]


def task_validate(state, plan, i):
    si, renderer = task_of(plan, i)
    scene, name = plan["scenes"][si], plan["names"][si]
    status = os.path.join(state, "status", "task_%d.json" % i)
    try:
        os.unlink(status)
    except FileNotFoundError:
        pass
    sdir = os.path.join(plan["out"], ".stage", name)
    os.makedirs(sdir, exist_ok=True)
    final = os.path.join(sdir, renderer)
    stage = os.path.join(sdir, ".%s.tmp.%d" % (renderer, os.getpid()))
    cmd = ([plan["photonbridge"], "validate", scene, "--out", stage, "--renderers", renderer, "--render-only"] +
           list(plan["validate_args"]))
    print("slurm_render: task %d (%s, %s), job %s on %s: %s" %
          (i, name, renderer, os.environ.get("SLURM_JOB_ID", "?"), os.uname().nodename,
           " ".join(shlex.quote(c) for c in cmd)), flush=True)
    t0 = time.time()
    rc = run_child(cmd)
    # The renderer's record (also a failure's, with its reason, for the
    # report) goes into place as a whole; without one there is nothing to keep.
    if os.path.isfile(os.path.join(stage, "render_%s.json" % renderer)):
        replace_dir(stage, final)
    else:
        shutil.rmtree(stage, ignore_errors=True)
    rec = {"task": i, "scene": scene, "name": name, "renderer": renderer, "exit": rc, "meaning": exit_meaning(rc),
           "job": os.environ.get("SLURM_JOB_ID"), "node": os.uname().nodename,
           "seconds": round(time.time() - t0, 3)}
    write_json(status, rec)
    print("slurm_render: task %d (%s, %s): exit %d (%s) after %.1f s" %
          (i, name, renderer, rc, rec["meaning"], rec["seconds"]), flush=True)
    sys.exit(rc if rc >= 0 else 128 - rc)


def cmd_task(state):
    plan = load_plan(state)
    if plan.get("kind") == "validate":
        n = len(plan["scenes"]) * len(plan["renderers"])
        try:
            i = int(os.environ["SLURM_ARRAY_TASK_ID"])
        except (KeyError, ValueError):
            i = -1
        if not 0 <= i < n:
            die(2, "task: SLURM_ARRAY_TASK_ID missing or outside the plan's %d tasks" % n)
        return task_validate(state, plan, i)
    try:
        i = int(os.environ["SLURM_ARRAY_TASK_ID"])
        chunk = plan["chunks"][i]
    except (KeyError, ValueError, IndexError):
        die(2, "task: SLURM_ARRAY_TASK_ID missing or outside the plan's %d chunks" % len(plan["chunks"]))
    status = os.path.join(state, "status", "chunk_%d.json" % i)
    try:  # a resubmitted chunk starts without its old status
        os.unlink(status)
    except FileNotFoundError:
        pass
    cmd = render_command(plan, chunk)
    print("slurm_render: chunk %d, frames %d-%d, job %s on %s: %s" %
          (i, chunk[0], chunk[1], os.environ.get("SLURM_JOB_ID", "?"), os.uname().nodename,
           " ".join(shlex.quote(c) for c in cmd)), flush=True)
    t0 = time.time()
    rc = run_child(cmd)
    rec = {"chunk": i, "frames": chunk, "exit": rc, "meaning": exit_meaning(rc),
           "job": os.environ.get("SLURM_JOB_ID"), "array_job": os.environ.get("SLURM_ARRAY_JOB_ID"),
           "node": os.uname().nodename, "seconds": round(time.time() - t0, 3)}
    write_json(status, rec)
    print("slurm_render: chunk %d: exit %d (%s) after %.1f s" % (i, rc, rec["meaning"], rec["seconds"]), flush=True)
    sys.exit(rc if rc >= 0 else 128 - rc)


def frame_ok(path):
    try:
        with open(path, "rb") as f:
            return f.read(4) == EXR_MAGIC
    except OSError:
        return False


def check_shot(state, plan):
    chunks, failed, stale = [], [], []
    for i, (a, b) in enumerate(plan["chunks"]):
        st = None
        try:
            with open(os.path.join(state, "status", "chunk_%d.json" % i)) as f:
                st = json.load(f)
        except (OSError, ValueError):
            pass
        missing = []
        for fr in range(a, b + 1):
            p = frame_path(plan["output"], fr)
            for t in glob.glob(glob.escape(p) + ".tmp.*"):  # a killed writer's temporary
                stale.append(t)
                try:
                    os.unlink(t)
                except OSError:
                    pass
            if not frame_ok(p):
                missing.append(fr)
        rc = st["exit"] if st else None
        ok = rc == 0 and not missing
        chunks.append({"chunk": i, "frames": [a, b], "ok": ok, "exit": rc, "meaning": exit_meaning(rc),
                       "missing_frames": missing, "log": os.path.join(state, "logs", "chunk_%d.log" % i)})
        if not ok:
            failed.append(i)
    n = plan["frames"][1] - plan["frames"][0] + 1
    return {"scene": plan["scene"], "output": plan["output"], "frames": n,
            "frames_ok": n - sum(len(c["missing_frames"]) for c in chunks),
            "complete": not failed, "failed_chunks": failed, "removed_temporaries": stale, "chunks": chunks}


def check_validate(state, plan, write_reports=False):
    """Each scene's tasks' statuses; with write_reports (the check job), its
    report from the renderers' folders, `validate --report-from`, staged and
    renamed into DIR/validate/NAME."""
    scenes, failed, stale = [], [], []
    out = plan["out"]
    for t in (glob.glob(os.path.join(glob.escape(out), ".*.tmp.*")) +  # a killed writer's staging folder
              glob.glob(os.path.join(glob.escape(out), ".stage", "*", ".*.tmp.*"))):
        stale.append(t)
        shutil.rmtree(t, ignore_errors=True)
    nr = len(plan["renderers"])
    for si, (scene, name) in enumerate(zip(plan["scenes"], plan["names"])):
        tasks, rc = [], None
        for ri, renderer in enumerate(plan["renderers"]):
            i = si * nr + ri
            st = None
            try:
                with open(os.path.join(state, "status", "task_%d.json" % i)) as f:
                    st = json.load(f)
            except (OSError, ValueError):
                pass
            trc = st["exit"] if st else None
            tasks.append({"task": i, "renderer": renderer, "exit": trc, "meaning": exit_meaning(trc),
                          "log": os.path.join(state, "logs", "task_%d.log" % i)})
            if trc != 0:
                failed.append(i)
                rc = trc if rc in (None, 0) else rc
        dirs = [os.path.join(out, ".stage", name, r) for r in plan["renderers"]]
        dirs = [d for d in dirs if os.path.isdir(d)]
        report_rc = None
        if write_reports and dirs:
            stage = os.path.join(out, ".%s.tmp.%d" % (name, os.getpid()))
            cmd = ([plan["photonbridge"], "validate", scene, "--out", stage, "--report-from", ",".join(dirs)] +
                   list(plan["validate_args"]))
            print("slurm_render: report of %s: %s" % (name, " ".join(shlex.quote(c) for c in cmd)), flush=True)
            report_rc = run_child(cmd)
            if os.path.isfile(os.path.join(stage, "report.json")):
                replace_dir(stage, os.path.join(out, name))
            else:
                shutil.rmtree(stage, ignore_errors=True)
        if rc in (None, 0) and report_rc not in (None, 0):
            rc = report_rc
        elif rc is None and all(t["exit"] == 0 for t in tasks):
            rc = 0
        report, pairs = os.path.join(out, name, "report.json"), []
        try:
            with open(report) as f:
                rep = json.load(f)
            pairs = [{"test": p.get("test"), "reference": p.get("reference"), "psnr_db": p.get("psnr_db"),
                      "relmse": p.get("relmse"), "ssim": p.get("ssim")} for p in rep.get("pairs", [])]
            renders = [{"name": r.get("name"), "status": r.get("status")} for r in rep.get("renders", [])]
        except (OSError, ValueError):
            report, renders = None, []
        ok = rc == 0 and report is not None
        scenes.append({"scene": scene, "name": name, "ok": ok, "exit": rc, "meaning": exit_meaning(rc),
                       "report": report, "page": os.path.join(out, name, "index.html") if report else None,
                       "renders": renders, "pairs": pairs, "tasks": tasks})
    return {"kind": "validate", "scenes": scenes, "complete": all(c["ok"] for c in scenes), "failed_chunks": failed,
            "removed_temporaries": stale}


def validate_index(state, s):
    """DIR/index.html: every scene's report page and its pairs' metrics."""
    def esc(x):
        return html.escape(str(x))
    rows = []
    for c in s["scenes"]:
        link = ('<a href="%s">%s</a>' % (esc(os.path.relpath(c["page"], state)), esc(c["name"])) if c["page"]
                else esc(c["name"]))
        pairs = "<br>".join("%s vs %s: %.2f dB, relMSE %.4g" % (esc(p["test"]), esc(p["reference"]),
                                                                  p["psnr_db"] or 0, p["relmse"] or 0)
                            for p in c["pairs"]) or "-"
        rows.append("<tr><td>%s</td><td>%s</td><td>%s</td></tr>" %
                    (link, "ok" if c["ok"] else "failed: " + esc(c["meaning"]), pairs))
    return ("<!doctype html><meta charset=utf-8><title>photonbridge validate on Slurm</title>"
            "<h1>photonbridge validate: %d of %d scenes</h1><table border=1 cellpadding=4>"
            "<tr><th>scene</th><th>status</th><th>pairs</th></tr>%s</table>\n" %
            (sum(1 for c in s["scenes"] if c["ok"]), len(s["scenes"]), "".join(rows)))


def cmd_check(state):
    plan = load_plan(state)
    if plan.get("kind") == "validate":
        s = check_validate(state, plan, write_reports=True)
        s["check_job"] = os.environ.get("SLURM_JOB_ID")
        write_json(os.path.join(state, "summary.json"), s)
        write_atomic(os.path.join(state, "index.html"), validate_index(state, s))
        for c in s["scenes"]:
            for t in c["tasks"]:
                if t["exit"] != 0:
                    print("slurm_render: task %d (%s, %s) failed: %s; log %s" %
                          (t["task"], c["name"], t["renderer"], t["meaning"], t["log"]))
        print("slurm_render: %d of %d scenes validated; %s/index.html" %
              (sum(1 for c in s["scenes"] if c["ok"]), len(s["scenes"]), state))
        sys.exit(0 if s["complete"] else 1)
    s = check_shot(state, plan)
    s["check_job"] = os.environ.get("SLURM_JOB_ID")
    write_json(os.path.join(state, "summary.json"), s)
    for c in s["chunks"]:
        if not c["ok"]:
            print("slurm_render: chunk %d (frames %d-%d) failed: %s; %d frame(s) missing; log %s" %
                  (c["chunk"], c["frames"][0], c["frames"][1], c["meaning"], len(c["missing_frames"]), c["log"]))
    print("slurm_render: %d of %d frames written%s" %
          (s["frames_ok"], s["frames"], "" if s["complete"] else "; resubmit: slurm_render.py resubmit --state " + state))
    sys.exit(0 if s["complete"] else 1)


def print_summary(state):
    p = os.path.join(state, "summary.json")
    try:
        with open(p) as f:
            s = json.load(f)
    except (OSError, ValueError) as e:
        die(1, "%s: no summary (%s): the check job did not run; see %s/logs" % (p, e, state))
    if s.get("kind") == "validate":
        for c in s["scenes"]:
            print("scene %s: %s%s" % (c["name"], "ok" if c["ok"] else "failed: " + c["meaning"],
                                           "".join("; %s vs %s %.2f dB" % (q["test"], q["reference"], q["psnr_db"] or 0)
                                                   for q in c["pairs"])))
        print("%s: %d of %d scenes; %s" % (state, sum(1 for c in s["scenes"] if c["ok"]), len(s["scenes"]),
                                           "complete" if s["complete"] else "tasks %s failed" % s["failed_chunks"]))
        return 0 if s["complete"] else 1
    for c in s["chunks"]:
        if not c["ok"]:
            print("chunk %d (frames %d-%d): %s, %d frame(s) missing (%s)" %
                  (c["chunk"], c["frames"][0], c["frames"][1], c["meaning"], len(c["missing_frames"]), c["log"]))
    print("%s: %d of %d frames; %s" % (state, s["frames_ok"], s["frames"],
                                       "complete" if s["complete"] else "chunks %s failed" % s["failed_chunks"]))
    return 0 if s["complete"] else 1


def main(argv):
    if len(argv) >= 2 and argv[0] in ("task", "check"):
        return cmd_task(os.path.abspath(argv[1])) if argv[0] == "task" else cmd_check(os.path.abspath(argv[1]))
    extra_render = []
    if "--" in argv:
        k = argv.index("--")
        argv, extra_render = argv[:k], argv[k + 1:]
    ap = argparse.ArgumentParser(prog="slurm_render.py", description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("submit", help="submit a shot")
    s.add_argument("scene")
    s.add_argument("--frames", required=True, help="A:B")
    s.add_argument("-o", "--output", required=True, help="output pattern, a run of '#' for the frame number")
    s.add_argument("--state", required=True, help="state folder on shared storage")
    s.add_argument("--chunk", type=int, default=32, help="frames per array task (default 32)")
    s.add_argument("--warmup", type=int, default=32, help="warm-up frames per task (default 32)")
    s.add_argument("--photonbridge", default="photonbridge", help="the executable on the nodes")
    s.add_argument("--python", default="python3", help="Python 3 on the nodes, to run this script's tasks")
    s.add_argument("--sbatch", action="append", help="an extra sbatch option (repeatable), e.g. --sbatch=--gres=gpu:1")
    s.add_argument("--wait", action="store_true", help="wait for the check; exit 1 when frames failed")
    r = sub.add_parser("resubmit", help="submit the chunks the last check found failed")
    r.add_argument("--state", required=True)
    r.add_argument("--sbatch", action="append")
    r.add_argument("--wait", action="store_true")
    t = sub.add_parser("status", help="print the last check's summary")
    t.add_argument("--state", required=True)
    v = sub.add_parser("validate", help="submit photonbridge validate, one task per scene and renderer")
    v.add_argument("scenes", nargs="+", metavar="SCENE")
    v.add_argument("--renderers", default=",".join(RENDERERS),
                   help="the renderers, one task each per scene (default %s)" % ",".join(RENDERERS))
    v.add_argument("--state", required=True)
    v.add_argument("--photonbridge", default="photonbridge")
    v.add_argument("--python", default="python3")
    v.add_argument("--sbatch", action="append")
    v.add_argument("--wait", action="store_true")
    a = ap.parse_args(argv)
    if a.cmd == "submit":
        return cmd_submit(a, extra_render)
    if a.cmd == "validate":
        return cmd_validate(a, extra_render)
    if extra_render:
        die(2, "'--' and render options only with submit")
    if a.cmd == "resubmit":
        return cmd_resubmit(a)
    return print_summary(os.path.abspath(a.state))


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
