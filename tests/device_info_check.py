#!/usr/bin/env python3
"""`photonbridge info --devices --json -`: every device says its driver
(driverName and driverInfo, VkPhysicalDeviceDriverProperties) and whether it
has VK_KHR_acceleration_structure and the ray-query path, the text listing
says the same. With --mesa25 ICD (tools/mesa25's lavapipe, installed by
scripts/install-deps.sh; a missing ICD fails, it is not skipped): the driver
is Mesa 25 and has both, and PB_GPU_MASK_FEATURES=ray-query hides them."""
import json, os, subprocess, sys

exe = sys.argv[1]
icd = sys.argv[3] if len(sys.argv) > 3 and sys.argv[2] == "--mesa25" else None
problems = []
checks = 0


def check(ok, what):
    global checks
    checks += 1
    if not ok:
        problems.append(what)


def info(env_extra, json_out=True):
    env = dict(os.environ, **env_extra)
    args = [exe, "info", "--devices"] + (["--json", "-"] if json_out else [])
    p = subprocess.run(args, capture_output=True, text=True, timeout=300, env=env)
    if p.returncode != 0:
        print(f"info --devices failed ({p.returncode}): {p.stderr.strip()}")
        sys.exit(1)
    return json.loads(p.stdout) if json_out else p.stdout


env = {}
if icd:
    if not os.path.isfile(icd):
        print(f"{icd} is missing: run scripts/install-deps.sh (it unpacks Mesa 25's lavapipe into tools/mesa25)")
        sys.exit(1)
    env = {"VK_ICD_FILENAMES": icd}
j = info(env)
devs = j.get("devices", [])
check(len(devs) >= 1, "no device listed")
for d in devs:
    for k in ("driver", "driver_info"):
        check(isinstance(d.get(k), str), f"device {d.get('index')}: {k} = {d.get(k)!r}")
    for k in ("acceleration_structure", "ray_query"):
        check(isinstance(d.get(k), bool), f"device {d.get('index')}: {k} = {d.get(k)!r}")
    check(not d.get("ray_query") or d.get("acceleration_structure"),
          f"device {d.get('index')}: ray_query without acceleration_structure")
    print(f"device {d.get('index')}: {d.get('name')} driver {d.get('driver')!r} {d.get('driver_info')!r} "
          f"acceleration_structure={d.get('acceleration_structure')} ray_query={d.get('ray_query')}")
text = info(env, json_out=False)
check("ray queries " in text and "acceleration structures " in text, "text listing lacks the ray-query columns")
if icd:
    check(len(devs) == 1, f"{len(devs)} devices with the Mesa 25 ICD alone")
    d = devs[0] if devs else {}
    check(d.get("driver") == "llvmpipe", f"driver {d.get('driver')!r}, expected llvmpipe")
    check(str(d.get("driver_info", "")).startswith("Mesa 25."), f"driver_info {d.get('driver_info')!r}, expected Mesa 25.x")
    check(d.get("acceleration_structure") is True, "Mesa 25 lavapipe: acceleration_structure not true")
    check(d.get("ray_query") is True, "Mesa 25 lavapipe: ray_query not true")
    check(d.get("usable") is True, "Mesa 25 lavapipe: not usable")
    m = info(dict(env, PB_GPU_MASK_FEATURES="ray-query"))
    md = m.get("devices", [{}])[0]
    check(md.get("ray_query") is False and md.get("acceleration_structure") is False,
          "PB_GPU_MASK_FEATURES=ray-query: still %r / %r" % (md.get("acceleration_structure"), md.get("ray_query")))
for p in problems:
    print("FAIL:", p)
print(f"{checks - len(problems)} passed, {len(problems)} failed")
sys.exit(1 if problems else 0)
