#!/usr/bin/env python3
"""photonbridge batch: render jobs in one process.

- Each job's pictures are those of `photonbridge render` with the same line
  (the same EXR, PSNR inf), also for a job that runs after other scenes.
- The second job of a scene takes every pipeline from the device's cache
  (pipelines_created 0, pipelines_reused > 0 in its line); a job with
  --validation gets a device of its own and passes the validation layer.
- A job that fails (a missing scene, a bad option) reports its exit code in
  its line, the jobs after it run, and batch exits with the first failure's
  code; quoted paths with spaces are read as one word.
- From standard input each job runs as its line arrives; a bad line is that
  job's error (exit 2) and the next jobs run.
- A broken jobs file (unterminated quote, a command other than render, a
  missing file) is a one-line error naming the file and line, with exit code
  2 (3 for a missing file), before any job runs (no output written).

usage: batch_check.py PHOTONBRIDGE WORKDIR"""
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
FAILED = []


def check(ok, what):
    print("%s %s" % ("ok  " if ok else "FAIL", what))
    if not ok:
        FAILED.append(what)


def batch(exe, jobs_path, env=None):
    p = subprocess.run([exe, "batch", jobs_path], capture_output=True, text=True, timeout=900, env=env)
    lines = [json.loads(l) for l in p.stdout.splitlines() if l.startswith("{")]
    return p.returncode, lines, p.stderr


def same(exe, a, b):
    p = subprocess.run([exe, "compare", a, b], capture_output=True, text=True)
    return p.returncode == 0 and "PSNR       inf" in p.stdout


def main(argv):
    exe, work = argv[1], argv[2]
    if subprocess.run([exe, "info", "--devices"], capture_output=True).returncode:
        print("skip: no Vulkan device")
        return 77
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    env = dict(os.environ, PB_VK_VALIDATION="0")
    box = os.path.join(ROOT, "samples", "cornell_box", "cornell_box.gltf")
    blender = os.path.join(ROOT, "tests", "data", "principled2", "diffuse")
    spaced = os.path.join(work, "a folder")
    shutil.copytree(blender, spaced)
    mat = os.path.join(spaced, "diffuse.gltf")
    small = "--width 32 --spp 4 --photons 4096 -q"
    out = lambda n: os.path.join(work, n)
    jobs = [
        "# a comment, then a blank line",
        "",
        "render %s -o %s %s" % (box, out("box1.exr"), small),
        "render '%s' -o %s %s" % (mat, out("mat1.exr"), small),
        "render %s -o %s %s --seed 3 --json %s" % (box, out("box2.exr"), small, out("box2.json")),
        "render \"%s\" -o %s %s" % (mat, out("mat2.exr"), small),
        "render %s -o %s %s" % (os.path.join(work, "missing.gltf"), out("missing.exr"), small),
        "render %s -o %s %s --no-such-option" % (box, out("bad.exr"), small),
        "render %s -o %s %s --validation" % (box, out("box_valid.exr"), small),
    ]
    path = out("jobs.txt")
    with open(path, "w") as f:
        f.write("\n".join(jobs) + "\n")
    rc, lines, err = batch(exe, path, env)
    print(err.strip()[-2000:])
    check(len(lines) == 7, "one line for each of the 7 jobs (%d)" % len(lines))
    check([l.get("line") for l in lines] == [3, 4, 5, 6, 7, 8, 9], "each line names its line in the file")
    codes = [l.get("exit") for l in lines]
    check(codes == [0, 0, 0, 0, 3, 2, 0], "exit codes per job [0,0,0,0,3,2,0] (%s)" % codes)
    check(rc == 3, "batch exits with the first failed job's code, 3 (%d)" % rc)
    if len(lines) == 7:
        check(lines[0]["pipelines_created"] > 0, "the first job creates its pipelines (%d)" % lines[0]["pipelines_created"])
        check(lines[2]["pipelines_created"] == 0 and lines[2]["pipelines_reused"] > 0,
              "the second glTF job takes every pipeline from the cache (created %d, reused %d)" % (
                  lines[2]["pipelines_created"], lines[2]["pipelines_reused"]))
        check(lines[3]["pipelines_created"] == 0 and lines[3]["pipelines_reused"] > 0,
              "the second Blender-material job takes every pipeline from the cache (created %d, reused %d)" % (
                  lines[3]["pipelines_created"], lines[3]["pipelines_reused"]))
        pj = json.load(open(out("box2.json"))).get("pipelines", {}) if os.path.exists(out("box2.json")) else {}
        check(pj.get("created") == 0 and pj.get("from_cache") == lines[2]["pipelines_reused"],
              "the job's render --json counts the same pipelines (%s)" % pj)
        check(lines[6]["pipelines_reused"] == 0, "a job with --validation gets a device of its own (reused %d)" %
              lines[6]["pipelines_reused"])
    check("missing.gltf" in err and "--no-such-option" in err, "the failed jobs' errors are on stderr")
    check(not os.path.exists(out("bad.exr")) and not os.path.exists(out("missing.exr")), "failed jobs write nothing")
    # The same lines as separate processes: the same pictures.
    for name, line in (("box1", jobs[2]), ("mat1", jobs[3]), ("box2", jobs[4].split(" --json")[0]), ("mat2", jobs[5])):
        words = line.replace("'", "").replace('"', "").split(" -o ")
        scene = words[0][len("render "):]
        rest = words[1].split()
        one = out(name + "_alone.exr")
        p = subprocess.run([exe, "render", scene, "-o", one] + rest[1:], capture_output=True, text=True, env=env)
        check(p.returncode == 0 and same(exe, out(name + ".exr"), one),
              "%s: the batch's EXR equals render's in a process of its own" % name)
    check(same(exe, out("box1.exr"), out("box_valid.exr")), "the validated job's picture is the same")

    # Broken files: an error naming file and line, nothing rendered.
    for tag, body, code, words in (
            ("quote", "render %s -o %s %s\nrender 'open -o x.exr\n" % (box, out("q.exr"), small), 2,
             ["quote.txt:2", "unterminated quote"]),
            ("command", "render %s -o %s %s\nreference %s -o x.exr\n" % (box, out("c.exr"), small, box), 2,
             ["command.txt:2", "'reference'"]),
            ("backslash", "render %s -o %s %s \\\n" % (box, out("b.exr"), small), 2,
             ["backslash.txt:1", "backslash"])):
        jp = out(tag + ".txt")
        with open(jp, "w") as f:
            f.write(body)
        rc, lines, err = batch(exe, jp, env)
        msg = err.strip().splitlines()
        check(rc == code and len(msg) == 1 and all(w in msg[0] for w in words) and not lines and
              not os.path.exists(out(tag[0] + ".exr")),
              "%s: exit %d, one line naming %s, no job run (%d, %s)" % (tag, code, words[0], rc, msg))
    # Standard input: each job runs as its line arrives, a bad line is that
    # job's error and the session goes on.
    p = subprocess.Popen([exe, "batch", "-"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=env)
    got = []
    for line in (jobs[2].replace("box1", "stream1"), "render 'open quote", jobs[2].replace("box1", "stream2")):
        p.stdin.write(line + "\n")
        p.stdin.flush()
        got.append(json.loads(p.stdout.readline()))  # the job's line before the next is sent
    p.stdin.close()
    err = p.stderr.read()
    rc = p.wait(timeout=300)
    check([g["exit"] for g in got] == [0, 2, 0] and [g["line"] for g in got] == [1, 2, 3],
          "stdin: each job's line comes before the next is sent, exits [0, 2, 0] (%s)" % got)
    check(got[2]["pipelines_created"] == 0 and got[2]["pipelines_reused"] > 0,
          "stdin: the third line's job takes its pipelines from the cache")
    check(rc == 2 and "standard input:2: unterminated quote" in err, "stdin: exit 2, the bad line named (%d)" % rc)
    check(same(exe, out("stream2.exr"), out("box1.exr")), "stdin: the same picture as the file's job")
    rc, lines, err = batch(exe, out("no_such_jobs.txt"), env)
    check(rc == 3 and "no_such_jobs.txt" in err and len(err.strip().splitlines()) == 1,
          "a missing jobs file: exit 3, one line naming it (%d)" % rc)
    print("%d failed" % len(FAILED))
    return 1 if FAILED else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
