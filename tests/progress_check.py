#!/usr/bin/env python3
"""render's progress on stderr. On a terminal (a pty here): one redrawn line
(\\r) naming the stages (loading, BVH, photon map k/N, writing) and the time
left, cleared before the summary; with -q nothing at all; with
--progress-lines the machine lines only, unchanged. Not on a terminal: no
\\r, and a short render prints no progress lines (they come at most every
few seconds). render --frames draws the same line per frame."""
import os, pty, re, select, subprocess, sys, tempfile

exe, root = sys.argv[1], sys.argv[2]
scene = os.path.join(root, "samples", "cornell_box", "cornell_box.gltf")
problems = []
checks = 0


def check(ok, what):
    global checks
    checks += 1
    if not ok:
        problems.append(what)


def run_tty(argv):
    """argv with stderr on a pty; returns (exit code, what the pty got)."""
    master, slave = pty.openpty()
    p = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=slave)
    os.close(slave)
    out = b""
    while True:
        r, _, _ = select.select([master], [], [], 1.0)
        if r:
            try:
                chunk = os.read(master, 65536)
            except OSError:
                chunk = b""
            if not chunk:
                break
            out += chunk
        elif p.poll() is not None:
            break
    p.wait(timeout=600)
    os.close(master)
    return p.returncode, out.decode("utf-8", "replace")


with tempfile.TemporaryDirectory() as d:
    base = [exe, "render", scene, "-o", os.path.join(d, "x.exr"), "--width", "16", "--photons", "4096"]
    rc, err = run_tty(base + ["--iterations", "3"])
    check(rc == 0, "render on a terminal: exit %d: %s" % (rc, err[-300:]))
    for stage in ("render: loading scene", "building BVH", "photon map 0/3", "photon map 3/3", "writing "):
        check(stage in err, "terminal: no stage %r in %r" % (stage, err[-400:]))
    check("\r" in err and re.search(r"about [0-9.]+s left", err), "terminal: no redrawn line with the time left")
    summary = [l for l in re.split(r"[\r\n]+", err) if l.startswith("render: 16x")]
    check(len(summary) == 1, "terminal: the summary line once: %r" % summary)

    rc, err = run_tty(base + ["-q"])
    check(rc == 0 and err.strip() == "", "-q on a terminal prints nothing: %r" % err[-300:])

    rc, err = run_tty(base + ["--progress-lines", "--iterations", "2"])
    lines = [l for l in err.replace("\r\n", "\n").split("\n") if l.strip()]
    prog = [l for l in lines if l.startswith("photonbridge progress: ")]
    check(rc == 0 and len(prog) >= 4 and "photon map" not in err and "\r" not in err.replace("\r\n", "\n"),
          "--progress-lines: only its lines and the summary: %r" % lines)
    check(any(re.fullmatch(r'photonbridge progress: \{"event": "iteration", "iteration": 1, "iterations": 2, '
                           r'"samples": 1, "spp": 2, "elapsed_s": [0-9.]+, "preview": null\}', l) for l in prog),
          "--progress-lines: the iteration line changed: %r" % prog)

    p = subprocess.run(base, capture_output=True, text=True, timeout=600)
    check(p.returncode == 0 and "\r" not in p.stderr and "photon map" not in p.stderr,
          "not a terminal: a short render prints no progress: %r" % p.stderr)

    # A longer one (the time limit: 6 s) prints a plain line after 5 s.
    p = subprocess.run(base + ["--time-limit", "6"], capture_output=True, text=True, timeout=600)
    plain = [l for l in p.stderr.splitlines() if l.startswith("render: photon map")]
    check(p.returncode == 0 and "\r" not in p.stderr and 1 <= len(plain) <= 2 and
          all(re.search(r"\([0-9.]+s, about [0-9.]+s left\)$", l) for l in plain),
          "not a terminal: plain lines every few seconds: %r" % p.stderr)

    rc, err = run_tty([exe, "render", scene, "-o", os.path.join(d, "f_#.exr"), "--width", "16", "--photons", "4096",
                       "--frames", "1:2"])
    check(rc == 0 and "frame 0/2" in err and "frame 2/2" in err, "--frames on a terminal: %r" % err[-400:])

for m in problems:
    print("FAIL:", m)
print(f"{checks - len(problems)} passed, {len(problems)} failed")
sys.exit(1 if problems else 0)
