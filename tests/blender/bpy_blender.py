"""The `blender` command line over Blender as a Python module (bpy 4.5 LTS,
installed by scripts/install-deps.sh into tools/bpy45), so that the add-on's
tests (blender_check.py) drive Blender 4.5 exactly as they drive Debian's
Blender 3.4:

  python bpy_blender.py [-b] [--factory-startup] [--python-exit-code N]
                        [FILE.blend] [-P|--python SCRIPT] [--python-expr CODE]
                        [-E ENGINE]
                        [-o PATH] [-F FORMAT] [-x 0|1] [-s N] [-e N]
                        [-f N | -a] [-- ARGS...]

Arguments run in order, as Blender runs them (creator_args.cc): a .blend is
opened, a script runs with sys.argv holding the whole command line (so it
finds its own arguments after '--'), -f renders and writes one frame, -a the
frame range. A script that raises exits with the --python-exit-code status;
a render Blender refuses (no camera, a 0-pixel border) prints Blender's
message and goes on, as `blender -b` does. The module has no window manager,
so the viewport is not reachable this way (BLENDER4.md §6)."""
import os
import re
import runpy
import sys
import traceback


def main(argv):
    import bpy

    exit_code = 0
    i = 0
    while i < len(argv):
        a = argv[i]
        nxt = argv[i + 1] if i + 1 < len(argv) else None
        if a == "--":
            break
        if a in ("-b", "--background", "--factory-startup", "-noaudio"):
            i += 1
            continue
        if a == "--python-exit-code":
            exit_code = int(nxt)
            i += 2
            continue
        if a in ("-P", "--python", "--python-expr"):
            # A script that raises: the traceback, then the exit code (Blender's
            # --python-exit-code; 0 goes on with the next argument).
            try:
                if a == "--python-expr":
                    exec(compile(nxt, "<string>", "exec"), {"__name__": "__main__"})
                else:
                    runpy.run_path(nxt, run_name="__main__")
            except SystemExit:
                raise
            except BaseException:
                traceback.print_exc()
                if exit_code:
                    return exit_code
            i += 2
            continue
        scene = bpy.context.scene
        if a in ("-E", "--engine"):
            scene.render.engine = nxt
        elif a in ("-o", "--render-output"):
            scene.render.filepath = nxt
        elif a in ("-F", "--render-format"):
            scene.render.image_settings.file_format = nxt
        elif a in ("-x", "--use-extension"):
            scene.render.use_file_extension = nxt == "1"
        elif a in ("-s", "--frame-start"):
            scene.frame_start = int(nxt)
        elif a in ("-e", "--frame-end"):
            scene.frame_end = int(nxt)
        elif a in ("-f", "--render-frame"):
            frame = int(nxt)
            scene.frame_set(frame)
            # `blender -f` writes the frame's file name (the last run of #
            # is the zero-padded frame, else 4 digits are appended); the
            # module's write_still uses the path as it is.
            pattern = scene.render.filepath
            scene.render.filepath = frame_path(pattern, frame)
            try:
                render(bpy, write_still=True)
            finally:
                scene.render.filepath = pattern
        elif a in ("-a", "--render-anim"):
            render(bpy, animation=True)
            i += 1
            continue
        elif not a.startswith("-"):
            bpy.ops.wm.open_mainfile(filepath=os.path.abspath(a))
            i += 1
            continue
        else:
            print("bpy_blender: unknown argument %s" % a, file=sys.stderr)
            return 2
        i += 2
    return 0


def frame_path(pattern, frame):
    m = list(re.finditer(r"#+", pattern))
    if not m:
        return pattern + "%04d" % frame
    last = m[-1]
    return pattern[:last.start()] + "%0*d" % (len(last.group()), frame) + pattern[last.end():]


def render(bpy, **kw):
    """One render as `blender -b -f/-a` does it: Blender's refusal (no
    camera, an empty border) is printed, not raised."""
    try:
        bpy.ops.render.render(**kw)
    except RuntimeError as e:
        print(str(e).strip(), flush=True)


def remove_session_tempdir():
    """Blender's own session folder (TMPDIR/blender_XXXXXX), which the
    blender binary removes on exit and os._exit below would leave."""
    try:
        import bpy
        import shutil
        d = bpy.app.tempdir
        if d and os.path.basename(os.path.normpath(d)).startswith("blender_"):
            shutil.rmtree(d, ignore_errors=True)
    except Exception:
        pass


if __name__ == "__main__":
    try:
        rc = main(sys.argv[1:])
    finally:
        remove_session_tempdir()
    sys.stdout.flush()
    sys.stderr.flush()
    # The module's interpreter shutdown can outlive a render's threads;
    # leave at once with the status, as the blender binary does.
    os._exit(rc)
