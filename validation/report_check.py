#!/usr/bin/env python3
"""Checks a validation report page in headless Chromium, as a reader would see it.

    python3 validation/report_check.py DIR/index.html [--chromium PATH] [--work DIR]

1. Loads the page and reads the DOM after its scripts ran: every <img> must
   have loaded (the page counts them into body[data-images-loaded/failed]).
2. No console error or uncaught exception while the page loads.
3. The screenshot is not blank (png_check.py's test).
4. The comparison control works: the page opened at #mode=flip&show=A and at
   #mode=flip&show=B gives different pictures, and so do #mode=slider&pos=0
   and &pos=100 (the state the page reports in #cmp[data-state] must follow
   the address too).

Exit 0 when all hold, 1 otherwise, 77 without Chromium. Standard library only.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import png_check  # noqa: E402

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--hide-scrollbars", "--virtual-time-budget=4000"]


def chromium(exe, args, work):
    prof = tempfile.mkdtemp(dir=work)
    try:
        p = subprocess.run([exe] + FLAGS + ["--user-data-dir=" + prof] + args, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, timeout=120, universal_newlines=True)
        return p.returncode, p.stdout, p.stderr
    finally:
        shutil.rmtree(prof, ignore_errors=True)


def shot(exe, url, path, work):
    rc, _, err = chromium(exe, ["--window-size=1300,1300", "--screenshot=" + path, url], work)
    if rc != 0 or not os.path.isfile(path):
        raise RuntimeError("no screenshot of %s: %s" % (url, err.strip()[-300:]))
    with open(path, "rb") as f:
        return f.read()


def main(argv):
    ap = argparse.ArgumentParser()
    ap.add_argument("page")
    ap.add_argument("--chromium")
    ap.add_argument("--work")
    a = ap.parse_args(argv)
    exe = a.chromium or shutil.which("chromium") or shutil.which("chromium-browser")
    if not exe:
        print("skip: no chromium")
        return 77
    page = os.path.abspath(a.page)
    url = "file://" + page
    work = a.work or tempfile.mkdtemp(prefix="pb_report_check.")
    os.makedirs(work, exist_ok=True)
    fails = []

    rc, dom, err = chromium(exe, ["--enable-logging=stderr", "--v=0", "--dump-dom", url], work)
    m = re.search(r"<body[^>]*data-images-loaded=\"(\d+)\"[^>]*data-images-failed=\"(\d+)\"", dom)
    n_img = len(re.findall(r"<img\b[^>]*\bsrc=", dom))
    if not m:
        fails.append("the page did not report its images (scripts did not run?)")
    else:
        loaded, failed = int(m.group(1)), int(m.group(2))
        print("images: %d loaded, %d failed, %d in the page" % (loaded, failed, n_img))
        if failed or loaded < n_img:
            fails.append("%d of %d images did not load" % (n_img - loaded, n_img))
    console = [l for l in err.splitlines() if "CONSOLE" in l or "Uncaught" in l]
    bad = [l for l in console if re.search(r"Uncaught|Error|error", l)]
    print("console messages: %d, errors: %d" % (len(console), len(bad)))
    if bad:
        fails.append("console errors: " + " | ".join(bad[:3]))
    st = re.search(r"id=\"cmp\"[^>]*data-state=\"([^\"]*)\"", dom)
    if st:
        print("comparison state at load: %s" % st.group(1))

    try:
        base = os.path.join(work, "page.png")
        shot(exe, url, base, work)
        if png_check.main([base]) != 0:
            fails.append("the page screenshot is blank")
        has_cmp = 'id="cmp"' in dom
        if has_cmp:
            states = {}
            for tag, frag in (("flipA", "#mode=flip&show=A"), ("flipB", "#mode=flip&show=B"),
                              ("slide0", "#mode=slider&pos=0"), ("slide100", "#mode=slider&pos=100")):
                path = os.path.join(work, tag + ".png")
                states[tag] = shot(exe, url + frag, path, work)
                _, d2, _ = chromium(exe, ["--dump-dom", url + frag], work)
                s2 = re.search(r"id=\"cmp\"[^>]*data-state=\"([^\"]*)\"", d2)
                want = {"flipA": "flip:A", "flipB": "flip:B", "slide0": "slider:0", "slide100": "slider:100"}[tag]
                if not s2 or s2.group(1) != want:
                    fails.append("%s: the page says %s, not %s" % (frag, s2.group(1) if s2 else "nothing", want))
            # Chromium encodes the same picture to the same bytes, so equal
            # files mean the control changed nothing on the screen.
            for x, y in (("flipA", "flipB"), ("slide0", "slide100")):
                same = states[x] == states[y]
                print("%s vs %s: %s" % (x, y, "identical" if same else "different pictures"))
                if same:
                    fails.append("the comparison control does not change the picture (%s = %s)" % (x, y))
        else:
            print("no comparison control (fewer than two pictures)")
    except (RuntimeError, ValueError, subprocess.TimeoutExpired) as e:
        fails.append(str(e))

    for f in fails:
        print("FAIL: " + f)
    if not a.work:
        shutil.rmtree(work, ignore_errors=True)
    print("%d passed, %d failed" % (1 if not fails else 0, 1 if fails else 0))
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
