#!/usr/bin/env python3
"""The device a render runs on, named honestly: `render --json` says its
type next to its name; on a CPU Vulkan device (lavapipe, SwiftShader) one
warning line on stderr says the GPU pipeline runs there, much slower than on
a GPU (none with -q, none on a GPU); `serve` warns the same and names the
type in its ready event; validate's page and the demo name it the same way."""
import json, os, subprocess, sys, tempfile

exe, root = sys.argv[1], sys.argv[2]
scene = os.path.join(root, "samples", "cornell_box", "cornell_box.gltf")
problems = []
checks = 0


def check(ok, what):
    global checks
    checks += 1
    if not ok:
        problems.append(what)


with tempfile.TemporaryDirectory() as d:
    base = [exe, "render", scene, "-o", os.path.join(d, "x.exr"), "--width", "16", "--direct-only"]
    p = subprocess.run(base + ["--json", "-"], capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        print(f"render failed ({p.returncode}): {p.stderr.strip()}")
        sys.exit(1)
    j = json.loads(p.stdout)
    check(isinstance(j.get("device"), str) and j["device"], "device: %r" % j.get("device"))
    check(j.get("device_type") in ("discrete", "integrated", "virtual", "cpu", "other"),
          "device_type: %r" % j.get("device_type"))
    warned = [l for l in p.stderr.splitlines() if "CPU Vulkan device" in l]
    if j.get("device_type") == "cpu":
        check(len(warned) == 1 and warned[0].startswith("warning: ") and j["device"] in warned[0] and
              "much slower than on a GPU" in warned[0], "CPU device warning: %r" % warned)
    else:
        check(not warned, "a warning about a CPU device on %s: %r" % (j.get("device_type"), warned))
    q = subprocess.run(base + ["-q"], capture_output=True, text=True, timeout=600)
    check(q.returncode == 0 and "CPU Vulkan device" not in q.stderr, "-q still warns: %r" % q.stderr)
    # serve (the Blender viewport's process) the same, and its ready event
    # carries the device's type for the add-on.
    sv = subprocess.run([exe, "serve", scene], input='{"cmd": "quit"}\n', capture_output=True, text=True,
                        timeout=600)
    ready = json.loads(sv.stdout.splitlines()[0]) if sv.stdout.strip() else {}
    check(sv.returncode == 0 and ready.get("device") == j["device"] and
          ready.get("device_type") == j.get("device_type"), "serve's ready event: %r (exit %d)" % (ready, sv.returncode))
    sw = [l for l in sv.stderr.splitlines() if "CPU Vulkan device" in l]
    if j.get("device_type") == "cpu":
        check(len(sw) == 1 and sw[0].startswith("warning: serve: ") and j["device"] in sw[0],
              "serve's CPU device warning: %r" % sw)
    else:
        check(not sw, "serve warns of a CPU device on %s: %r" % (j.get("device_type"), sw))
    sq = subprocess.run([exe, "serve", scene, "-q"], input='{"cmd": "quit"}\n', capture_output=True, text=True,
                        timeout=600)
    check(sq.returncode == 0 and "CPU Vulkan device" not in sq.stderr, "serve -q still warns: %r" % sq.stderr)

sys.path.insert(0, os.path.join(root, "validation"))
import validate  # noqa: E402

check(validate.photonbridge_label({"device": "llvmpipe (LLVM 15.0.7, 256 bits)", "device_type": "cpu"}) ==
      "photonbridge render: GPU pipeline on llvmpipe (LLVM 15.0.7, 256 bits) (CPU Vulkan device)", "page label (cpu)")
check("CPU" not in validate.photonbridge_label({"device": "NVIDIA H100", "device_type": "discrete"}), "page label (gpu)")
demo = open(os.path.join(root, "scripts", "demo.sh")).read()
check("CPU Vulkan device" in demo and "device_type" in demo, "demo.sh does not name a CPU Vulkan device")

for m in problems:
    print("FAIL:", m)
print(f"{checks - len(problems)} passed, {len(problems)} failed")
sys.exit(1 if problems else 0)
