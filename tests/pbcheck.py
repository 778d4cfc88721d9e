"""The check tally the test scripts share: check(ok, what) counts a check
and prints "FAIL: what" when it fails; finish() prints "N passed, M failed"
(the line ctest's PASS_REGULAR_EXPRESSION looks for) and exits 1 on any
failure. Scripts in tests/ import it beside themselves."""
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
