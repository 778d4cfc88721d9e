#!/usr/bin/env python3
"""Cross-renderer validation report for one scene (issue 7, part 4).

    python3 validation/validate.py SCENE --out DIR --exe build/photonbridge \
        [--width 128] [--spp 16] [--ref-spp 64] [--pov-quality medium] \
        [--cycles-spp 64] [--no-cycles] [--no-gpu] [--no-povray] [--threads N] \
        [--direct-only] [--ocio-config F] [--display D] [--view V] [--look L]

`photonbridge validate` runs this script. SCENE is a glTF file or the name of
a sample (samples/NAME/NAME.gltf). Renders, all at the same width (the height
follows the camera's aspect in every renderer):

  reference     photonbridge reference (CPU, Embree): PT, SPPM when the scene
                has caustics; --estimate-noise gives its own noise
  photonbridge  photonbridge render (GPU pipeline)
  povray        photonbridge export-pov + validation/run_povray.sh
  cycles        validation/run_cycles.sh (when Blender is installed and SCENE
                is a sample that exporters/blender/make_samples.py builds)

Every EXR goes through `photonbridge display` with the same OCIO options, and
every pair through `photonbridge compare --json --heatmap` (the shared
src/metrics code; the earlier renderer of the list above is the pair's
reference). Writes DIR/index.html (images side by side, heat maps, metric
table, times, settings, tool versions) and DIR/report.json (the same numbers).
A renderer that is missing or fails is listed with the reason and left out of
the comparisons; the exit status is 0 when the reference and at least one
other renderer produced an image, 1 otherwise, 2 on usage errors.

Only the Python standard library is used.
"""
import argparse
import html
import json
import os
import shutil
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
ORDER = ["reference", "cycles", "povray", "photonbridge"]
LABEL = {"reference": "photonbridge reference (CPU)", "photonbridge": "photonbridge render (GPU)",
         "povray": "POV-Ray 3.7", "cycles": "Blender Cycles"}


def run(cmd, log=None, cwd=None, timeout=1800):
    t0 = time.time()
    try:
        p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           timeout=timeout, universal_newlines=True)
        rc, out = p.returncode, p.stdout
    except FileNotFoundError as e:
        rc, out = 127, str(e)
    except subprocess.TimeoutExpired:
        rc, out = 124, "timed out after %d s" % timeout
    dt = time.time() - t0
    if log:
        with open(log, "w") as f:
            f.write("$ " + " ".join(cmd) + "\n" + out + "\nexit=%d wall_s=%.3f\n" % (rc, dt))
    return rc, out, dt


def tool_version(cmd, match=None):
    rc, out, _ = run(cmd, timeout=120)
    lines = [l.strip() for l in out.splitlines() if l.strip() and (not match or match in l)]
    if rc != 0 or not lines:
        return None
    return lines[0]


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def resolve_scene(scene):
    if os.path.isfile(scene):
        path = os.path.abspath(scene)
    else:
        path = os.path.join(ROOT, "samples", scene, scene + ".gltf")
        if not os.path.isfile(path):
            return None, None
    name = os.path.splitext(os.path.basename(path))[0]
    sample = name if os.path.abspath(os.path.join(ROOT, "samples", name, name + ".gltf")) == path else None
    return path, sample


CREATED = None  # the output folder, when this run created it (removed if interrupted)


class Terminated(Exception):
    pass


def progress(what):
    """One stderr line as each renderer starts (progress goes to stderr)."""
    print("validate: %s ..." % what, file=sys.stderr, flush=True)


def write_atomic(path, text):
    tmp = "%s.tmp.%d" % (path, os.getpid())
    try:
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def main(argv):
    ap = argparse.ArgumentParser(prog="validate.py")
    ap.add_argument("scene")
    ap.add_argument("--out", required=True)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "photonbridge"))
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--spp", type=int, default=16, help="photonbridge render samples per pixel")
    ap.add_argument("--ref-spp", type=int, default=64, help="reference samples per pixel")
    ap.add_argument("--pov-quality", default="medium", choices=["draft", "medium", "high", "direct"])
    ap.add_argument("--cycles-spp", type=int, default=64)
    ap.add_argument("--threads", type=int, default=0, help="CPU threads for reference/POV-Ray/Cycles (0: all)")
    ap.add_argument("--direct-only", action="store_true",
                    help="direct light only everywhere: reference --max-bounces 1, render --direct-only, "
                         "POV-Ray quality direct, Cycles --bounces 0")
    ap.add_argument("--no-gpu", action="store_true")
    ap.add_argument("--no-povray", action="store_true")
    ap.add_argument("--no-cycles", action="store_true")
    ap.add_argument("--ocio-config")
    ap.add_argument("--display")
    ap.add_argument("--view")
    ap.add_argument("--look")
    a = ap.parse_args(argv)

    scene, sample = resolve_scene(a.scene)
    if not scene:
        print("validate: %s: no such scene file or sample" % a.scene, file=sys.stderr)
        return 2
    if not os.access(a.exe, os.X_OK):
        print("validate: %s: photonbridge executable not found (--exe)" % a.exe, file=sys.stderr)
        return 2
    exe = os.path.abspath(a.exe)
    out = os.path.abspath(a.out)
    global CREATED
    try:
        if not os.path.exists(out):
            CREATED = out
        os.makedirs(out, exist_ok=True)
    except OSError as e:  # one line and the result table's PB_ERR_IO (3), not a traceback
        print("photonbridge validate: error: %s: cannot create the output folder: %s" % (out, e.strerror),
              file=sys.stderr)
        return 3
    color = []
    for k in ("ocio_config", "display", "view", "look"):
        v = getattr(a, k)
        if v:
            color += ["--" + k.replace("_", "-"), v]
    if a.direct_only:
        a.pov_quality = "direct"

    renders = {}

    def record(name, status, reason=None, **kw):
        r = {"name": name, "label": LABEL[name], "status": status}
        if reason:
            r["reason"] = reason
        r.update(kw)
        renders[name] = r
        print("validate: %-12s %s%s" % (name, status, (": " + reason) if reason else ""))

    # Reference (CPU).
    progress("reference")
    exr = os.path.join(out, "reference.exr")
    cmd = [exe, "reference", scene, "-o", exr, "--width", str(a.width), "--spp", str(a.ref_spp),
           "--estimate-noise", "--json", os.path.join(out, "reference.json"), "-q"]
    if a.threads:
        cmd += ["--threads", str(a.threads)]
    if a.direct_only:
        cmd += ["--max-bounces", "1"]
    rc, o, dt = run(cmd, os.path.join(out, "reference.log"))
    st = read_json(os.path.join(out, "reference.json")) or {}
    if rc == 0 and os.path.isfile(exr):
        record("reference", "ok", exr="reference.exr", wall_s=round(dt, 3), render_s=st.get("time_s"),
               settings={"spp": st.get("spp"), "mode": st.get("mode"), "max_bounces": st.get("max_bounces"),
                         "seed": st.get("seed"), "threads": st.get("threads"),
                         "photon_paths": st.get("photon_paths")},
               noise=st.get("noise"), command=cmd)
    else:
        record("reference", "failed", "exit %d: %s" % (rc, o.strip()[-300:]), command=cmd)

    # photonbridge render (GPU).
    progress("photonbridge render")
    if a.no_gpu:
        record("photonbridge", "skipped", "--no-gpu")
    else:
        exr = os.path.join(out, "photonbridge.exr")
        cmd = [exe, "render", scene, "-o", exr, "--width", str(a.width), "--spp", str(a.spp),
               "--json", os.path.join(out, "photonbridge.json"), "-q"]
        if a.direct_only:
            cmd += ["--direct-only"]
        rc, o, dt = run(cmd, os.path.join(out, "photonbridge.log"))
        st = read_json(os.path.join(out, "photonbridge.json")) or {}
        if rc == 0 and os.path.isfile(exr):
            record("photonbridge", "ok", exr="photonbridge.exr", wall_s=round(dt, 3),
                   render_s=(st["wall_ms"] / 1000.0) if isinstance(st.get("wall_ms"), (int, float)) else None,
                   settings={"spp": a.spp, "direct_only": a.direct_only, "device": st.get("device")},
                   command=cmd)
        else:
            record("photonbridge", "failed", "exit %d: %s" % (rc, o.strip()[-300:]), command=cmd)

    # POV-Ray.
    progress("POV-Ray")
    if a.no_povray:
        record("povray", "skipped", "--no-povray")
    elif not shutil.which("povray"):
        record("povray", "unavailable", "povray not installed")
    else:
        pdir = os.path.join(out, "povray")
        os.makedirs(pdir, exist_ok=True)
        pov = os.path.join(pdir, "scene.pov")
        exr = os.path.join(out, "povray.exr")
        cmd1 = [exe, "export-pov", scene, "-o", pov, "--width", str(a.width), "--quality", a.pov_quality]
        rc, o, _ = run(cmd1, os.path.join(out, "povray-export.log"))
        notes = [l for l in o.splitlines() if l.startswith("note:")]
        if rc != 0:
            record("povray", "failed", "export-pov exit %d: %s" % (rc, o.strip()[-300:]), command=cmd1)
        else:
            extra = ["--", "+WT%d" % a.threads] if a.threads else []
            cmd2 = ["sh", os.path.join(HERE, "run_povray.sh"), pov, exr] + extra
            rc, o, dt = run(cmd2, os.path.join(out, "povray-run.log"))
            if rc == 0 and os.path.isfile(exr):
                wall = None
                try:
                    for l in open(exr + ".log"):
                        if l.startswith("wall_s="):
                            wall = float(l.split("=", 1)[1])
                except OSError:
                    pass
                record("povray", "ok", exr="povray.exr", wall_s=round(dt, 3), render_s=wall,
                       settings={"quality": a.pov_quality, "antialias": "run_povray.sh default",
                                 "notes": notes}, command=cmd1 + [";"] + cmd2)
            else:
                record("povray", "failed", "run_povray exit %d: %s" % (rc, o.strip()[-300:]),
                       command=cmd1 + [";"] + cmd2)

    # Cycles.
    progress("Cycles")
    if a.no_cycles:
        record("cycles", "skipped", "--no-cycles")
    elif not shutil.which(os.environ.get("BLENDER", "blender")):
        record("cycles", "unavailable", "blender not installed")
    elif not sample:
        record("cycles", "unavailable", "not a sample built by exporters/blender/make_samples.py")
    else:
        exr = os.path.join(out, "cycles.exr")
        cmd = ["sh", os.path.join(HERE, "run_cycles.sh"), sample, exr, "--width", str(a.width),
               "--samples", str(a.cycles_spp)]
        if a.threads:
            cmd += ["--threads", str(a.threads)]
        if a.direct_only:
            cmd += ["--bounces", "0"]
        rc, o, dt = run(cmd, os.path.join(out, "cycles-run.log"))
        st = read_json(exr + ".json") or {}
        if rc == 0 and os.path.isfile(exr):
            record("cycles", "ok", exr="cycles.exr", wall_s=round(dt, 3), render_s=st.get("render_s"),
                   settings={"samples": st.get("samples"), "bounces": st.get("bounces"),
                             "seed": st.get("seed"), "denoising": False, "clamping": False},
                   command=cmd)
        else:
            record("cycles", "failed", "exit %d: %s" % (rc, o.strip()[-300:]), command=cmd)

    ok = [n for n in ORDER if renders.get(n, {}).get("status") == "ok"]

    # Display images, all through the same OCIO view.
    display_name = None
    for n in ok:
        png = n + ".png"
        cmd = [exe, "display", os.path.join(out, renders[n]["exr"]), "-o", os.path.join(out, png)] + color
        rc, o, _ = run(cmd, os.path.join(out, n + "-display.log"))
        if rc == 0:
            renders[n]["png"] = png
        else:
            renders[n]["display_error"] = o.strip()[-300:]

    # Every pair through the shared metrics.
    pairs = []
    for i, r in enumerate(ok):
        for t in ok[i + 1:]:
            tag = "%s_vs_%s" % (t, r)
            js = os.path.join(out, "cmp_" + tag + ".json")
            heat = "heat_" + tag + ".png"
            cmd = [exe, "compare", os.path.join(out, renders[t]["exr"]), os.path.join(out, renders[r]["exr"]),
                   "--json", js, "--heatmap", os.path.join(out, heat), "-q"] + color
            rc, o, _ = run(cmd, os.path.join(out, "cmp_" + tag + ".log"))
            m = read_json(js) if rc == 0 else None
            p = {"test": t, "reference": r}
            if m:
                display_name = display_name or m.get("display")
                p.update({k: m.get(k) for k in ("width", "height", "rmse", "relmse", "psnr_db", "ssim",
                                                "max_abs_error", "nonfinite_values")})
                p["heatmap"] = heat if os.path.isfile(os.path.join(out, heat)) else None
            else:
                p["error"] = o.strip()[-300:]
            pairs.append(p)

    versions = {
        "photonbridge": tool_version([exe, "--version"]),
        "povray": tool_version(["povray", "--version"], "POV-Ray") if shutil.which("povray") else None,
        "blender": tool_version([os.environ.get("BLENDER", "blender"), "--version"], "Blender")
        if shutil.which(os.environ.get("BLENDER", "blender")) else None,
        "opencolorio": None,
        "python": sys.version.split()[0],
    }
    rc, o, _ = run(["pkg-config", "--modversion", "OpenColorIO"], timeout=30)
    if rc == 0 and o.strip():
        versions["opencolorio"] = o.strip()
    report = {
        "scene": scene, "sample": sample, "width": a.width, "direct_only": a.direct_only,
        "display": display_name or "sRGB / Standard (built-in)", "color_options": color,
        "metrics_note": "RMSE and relMSE (mean of (t-r)^2/(r^2+0.01)) on scene-linear RGB; PSNR and SSIM "
                        "on the display image through the OCIO view above (src/metrics, photonbridge compare)",
        "renders": [renders[n] for n in ORDER if n in renders], "pairs": pairs, "versions": versions,
        "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    # Written to a temporary and renamed: an interrupted run leaves no
    # half-written report.
    write_atomic(os.path.join(out, "report.json"), json.dumps(report, indent=1))
    write_atomic(os.path.join(out, "index.html"), render_html(report))
    print("validate: wrote %s and %s" % (os.path.join(out, "index.html"), os.path.join(out, "report.json")))
    return 0 if "reference" in ok and len(ok) >= 2 else 1


def fmt(v, spec):
    if v is None:
        return "—"
    try:
        return format(v, spec)
    except (TypeError, ValueError):
        return html.escape(str(v))


def render_html(rep):
    e = html.escape
    h = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>photonbridge validation: %s</title>"
         % e(os.path.basename(rep["scene"])),
         "<style>body{font-family:sans-serif;margin:16px;background:#fafafa}"
         "table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid #bbb;padding:3px 8px;"
         "font-size:13px}th{background:#e4e4e4}img{image-rendering:pixelated;width:256px;"
         "border:1px solid #888;background:#333}.fig{display:inline-block;margin:4px;text-align:center;"
         "font-size:13px}.bad{color:#b00}</style></head><body>",
         "<h1>Validation: %s</h1>" % e(os.path.basename(rep["scene"])),
         "<p>Scene <code>%s</code>, width %d px%s. Every picture through the same OCIO view: <b>%s</b>.</p>"
         % (e(rep["scene"]), rep["width"], ", direct light only" if rep["direct_only"] else "",
            e(rep["display"])),
         "<h2>Images</h2><div>"]
    for r in rep["renders"]:
        if r.get("png"):
            h.append("<div class='fig'><img src='%s' alt='%s'><br>%s</div>" % (e(r["png"]), e(r["name"]),
                                                                               e(r["label"])))
    h.append("</div>")
    h.append("<h2>Per-pixel error (relative: sqrt(mean over RGB of (t-r)^2/(r^2+0.01)), viridis, each map scaled to its own 99th percentile; test vs reference)</h2><div>")
    for p in rep["pairs"]:
        if p.get("heatmap"):
            h.append("<div class='fig'><img src='%s' alt='heat'><br>%s vs %s</div>"
                     % (e(p["heatmap"]), e(p["test"]), e(p["reference"])))
    h.append("</div><h2>Metrics</h2><p>%s</p>" % e(rep["metrics_note"]))
    h.append("<table><tr><th>test</th><th>reference</th><th>size</th><th>RMSE</th><th>relMSE</th>"
             "<th>PSNR dB</th><th>SSIM</th><th>max abs</th></tr>")
    for p in rep["pairs"]:
        if "error" in p:
            h.append("<tr><td>%s</td><td>%s</td><td colspan=6 class='bad'>%s</td></tr>"
                     % (e(p["test"]), e(p["reference"]), e(p["error"])))
            continue
        h.append("<tr><td>%s</td><td>%s</td><td>%sx%s</td><td>%s</td><td>%s</td><td>%s</td><td>%s</td>"
                 "<td>%s</td></tr>" % (e(p["test"]), e(p["reference"]), p.get("width"), p.get("height"),
                                       fmt(p.get("rmse"), ".4g"), fmt(p.get("relmse"), ".4g"),
                                       fmt(p.get("psnr_db"), ".2f"), fmt(p.get("ssim"), ".4f"),
                                       fmt(p.get("max_abs_error"), ".4g")))
    h.append("</table><h2>Renders: times and settings</h2><table><tr><th>renderer</th><th>status</th>"
             "<th>render s</th><th>wall s</th><th>settings</th></tr>")
    for r in rep["renders"]:
        st = r.get("settings", {})
        if r.get("noise"):
            st = dict(st, noise=r["noise"])
        h.append("<tr><td>%s</td><td%s>%s</td><td>%s</td><td>%s</td><td><code>%s</code></td></tr>"
                 % (e(r["label"]), "" if r["status"] == "ok" else " class='bad'",
                    e(r["status"] + (": " + r["reason"] if r.get("reason") else "")),
                    fmt(r.get("render_s"), ".3f"), fmt(r.get("wall_s"), ".3f"), e(json.dumps(st))))
    h.append("</table><h2>Tool versions</h2><table>")
    for k, v in rep["versions"].items():
        h.append("<tr><th>%s</th><td>%s</td></tr>" % (e(k), e(v or "not available")))
    h.append("</table><p>Numbers: <a href='report.json'>report.json</a>. Created %s.</p></body></html>\n"
             % e(rep["created"]))
    return "\n".join(h)


def on_term(sig, frame):
    raise Terminated()


if __name__ == "__main__":
    # photonbridge validate passes SIGINT/SIGTERM on to this script's process
    # group (the renderers remove their own temporaries) and prints the one
    # line itself; a folder this run created goes with it.
    signal.signal(signal.SIGTERM, on_term)
    try:
        sys.exit(main(sys.argv[1:]))
    except (KeyboardInterrupt, Terminated) as e:
        if CREATED:
            shutil.rmtree(CREATED, ignore_errors=True)
        sys.exit(143 if isinstance(e, Terminated) else 130)
