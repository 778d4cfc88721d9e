"""The check tally the test scripts share: check(ok, what) counts a check
and prints "FAIL: what" when it fails; finish() prints "N passed, M failed"
(the line ctest's PASS_REGULAR_EXPRESSION looks for) and exits 1 on any
failure. Scripts in tests/ import it beside themselves."""
import os
import sys

checks = 0
problems = []


def check(ok, what):
    global checks
    checks += 1
    if not ok:
        problems.append(what)
        print("FAIL:", what)
    return bool(ok)


def finish(prefix=None):
    if prefix:
        print("%s: %d checks, %d failed" % (prefix, checks, len(problems)))
    print("%d passed, %d failed" % (checks - len(problems), len(problems)))
    sys.exit(1 if problems else 0)


def debian_python(script):
    """For a script whose imports of numpy or Pillow failed: runs it again
    under Debian's python3 (python3-numpy, python3-pil, which
    scripts/install-deps.sh installs) when this is another interpreter;
    else exits 77 (skipped), saying what it needs."""
    if sys.executable != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    print("%s: needs numpy and Pillow (python3-numpy, python3-pil)" % script)
    sys.exit(77)
