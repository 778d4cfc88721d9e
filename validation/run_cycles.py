"""Render a scene with Cycles, headless, from one of three sources of the
Cycles scene:

  --blend FILE   a .blend as the artist set it up: its own node trees,
                 lights, world and active camera (the render settings are
                 the unbiased ones below; its border is ignored);

  --scene NAME   a photonbridge sample, built by the very Blender script the
                 glTF was exported from (exporters/blender/make_samples.py);
                 --materials principled (default: Blender's Principled BSDFs
                 and lights, as the artist set them) or bsdf (the scene as its
                 glTF export means it: each material as the Cycles BSDF of
                 its glTF meaning, a Diffuse BSDF for Lambertian ones, a
                 sharp Glossy BSDF of the base colour for mirrors, a sharp
                 Glass BSDF for glass, and spots with glTF's profile as in
                 cycles_gltf.convert_lights);
  --gltf FILE    any .gltf / .glb through Blender's glTF importer, with
                 every material rebuilt as glTF's metallic-roughness model
                 from Cycles nodes (validation/cycles_gltf.py; --materials
                 gltf, the default) or the importer's Principled BSDFs
                 (--materials principled), lights in photonbridge's units and
                 photonbridge's camera (--info: `photonbridge info --json`).

    blender -b --factory-startup --python-exit-code 1 -P validation/run_cycles.py -- \\
        (--scene NAME | --gltf FILE --info INFO.json | --blend FILE) --out OUT.exr [--width W] [--height H] \\
        [--samples N] [--threads N] [--seed N] [--bounces N] [--materials M] [--halves]
    blender -b --factory-startup --python-exit-code 1 -P validation/run_cycles.py -- --jobs JOBS.json

Writes OUT (32-bit float OpenEXR, RGB, scene-linear Rec.709) and OUT.json:
render time, samples, bounces, Blender version, the source and its material
model, and `notes` (what this Cycles scene models differently from
photonbridge). --halves renders two independent halves (seeds hashed from N,
half the samples each) to OUT.a.exr and OUT.b.exr and writes their average
as OUT, so that the image's own noise can be measured as photonbridge
reference --estimate-noise does. A file the glTF path cannot read: OUT.json
holds "error" (one line: "Blender's glTF importer: ..." for what the importer
refuses), nothing else is written, exit status 1.

Settings chosen for an unbiased reference: no denoising, no clamping,
blur_glossy 0 (no caustic blurring), reflective and refractive caustics on,
light_sampling_threshold 0 (no light culled), a 1-pixel box pixel filter (the
reference's uniform jitter; Cycles' default is a 1.5-pixel Blackman-Harris),
no shadow-terminator offsets (the reference has none), bounces 64
(--bounces; transparent 64), fixed seed.
"""
import argparse
import importlib.util
import json
import os
import sys
import time
import traceback

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)  # gltf_json, for cycles_gltf


def load_module(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def load_samples_module():
    return load_module("pb_make_samples", os.path.join(ROOT, "exporters", "blender", "make_samples.py"))


def configure(sc, out, samples, threads, seed, bounces):
    """Cycles settings for an unbiased reference (see the module comment),
    32-bit float RGB EXR output to `out`. cycles_calib.py uses them too."""
    r = sc.render
    r.engine = 'CYCLES'
    cy = sc.cycles
    cy.device = 'CPU'
    cy.samples = samples
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.seed = seed
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0
    cy.caustics_reflective = True
    cy.caustics_refractive = True
    cy.light_sampling_threshold = 0.0
    cy.max_bounces = bounces
    cy.diffuse_bounces = bounces
    cy.glossy_bounces = bounces
    cy.transmission_bounces = bounces
    cy.transparent_max_bounces = 64
    cy.pixel_filter_type = 'BOX'
    cy.filter_width = 1.0
    for ob in sc.objects:
        if ob.type == 'MESH':
            ob.cycles.shadow_terminator_offset = 0.0
            ob.cycles.shadow_terminator_geometry_offset = 0.0
    if threads:
        r.threads_mode = 'FIXED'
        r.threads = threads
    r.film_transparent = False
    s = r.image_settings
    s.file_format = 'OPEN_EXR'
    s.color_mode = 'RGB'
    s.color_depth = '32'
    s.exr_codec = 'ZIP'
    r.filepath = out
    r.use_file_extension = False


def simple_bsdfs(cg):
    """The samples' Principled materials as the Cycles BSDFs they mean in
    glTF (make_samples.py uses three kinds: Lambertian, perfect mirror, clear
    glass; mirrors with glTF's metal Fresnel, which a sharp lobe can take at
    n . wo). Textures are linearised as in the glTF path (cycles_gltf.py:
    Cycles would filter 8-bit sRGB texels before decoding them)."""
    for mat in bpy.data.materials:
        nt = mat.node_tree
        p = nt.nodes.get("Principled BSDF") if nt else None
        if not p:
            continue
        g = {k: p.inputs[k].default_value for k in ("Metallic", "Specular", "Transmission", "Roughness", "IOR")}
        col = p.inputs["Base Color"]
        color = col.links[0].from_socket if col.is_linked else None
        if color is not None and color.node.type == 'TEX_IMAGE' and color.node.image:
            img = color.node.image
            color.node.image = cg.linear_float_image(img, img.colorspace_settings.name != 'Non-Color')
        if g["Transmission"] == 1 and g["Metallic"] == 0 and g["Roughness"] == 0 and color is None:
            b = nt.nodes.new("ShaderNodeBsdfGlass")
            b.distribution = 'SHARP'
            b.inputs["IOR"].default_value = g["IOR"]
        elif g["Metallic"] == 1 and g["Roughness"] == 0 and color is None:
            b = nt.nodes.new("ShaderNodeBsdfGlossy")
            b.distribution = 'SHARP'
            # Schlick: base + (1 - base) (1 - |n . wo|)^5; Layer Weight's
            # Facing at blend 0.5 is 1 - |n . wo|.
            lw = nt.nodes.new("ShaderNodeLayerWeight")
            lw.inputs["Blend"].default_value = 0.5
            m5 = nt.nodes.new("ShaderNodeMath")
            m5.operation = 'POWER'
            nt.links.new(lw.outputs["Facing"], m5.inputs[0])
            m5.inputs[1].default_value = 5.0
            mix = nt.nodes.new("ShaderNodeMixRGB")
            nt.links.new(m5.outputs[0], mix.inputs["Fac"])
            mix.inputs["Color1"].default_value = col.default_value
            mix.inputs["Color2"].default_value = (1.0, 1.0, 1.0, 1.0)
            color = mix.outputs[0]
        elif g["Metallic"] == 0 and g["Specular"] == 0 and g["Transmission"] == 0:
            b = nt.nodes.new("ShaderNodeBsdfDiffuse")
        else:
            raise RuntimeError("material '%s' is none of the samples' three kinds (%s)" % (mat.name, g))
        if color is not None:
            nt.links.new(color, b.inputs["Color"])
        else:
            b.inputs["Color"].default_value = col.default_value
        nt.links.new(b.outputs[0], nt.nodes["Material Output"].inputs["Surface"])


MODEL = {
    ("sample", "principled"): "Blender's Principled BSDF, as make_samples.py sets it",
    ("sample", "bsdf"): "Diffuse / sharp Glossy / sharp Glass BSDFs and glTF's spot profile (make_samples.py's "
                        "scene as its glTF means it)",
    ("gltf", "gltf"): "glTF metallic-roughness rebuilt from Cycles closures and math nodes (cycles_gltf.py)",
    ("gltf", "principled"): "Blender's glTF importer's Principled BSDFs",
    ("blend", "blend"): "the .blend's own shader node trees, lights and world, as Cycles 3.4 evaluates them",
}


def write_json(path, info):
    with open(path + ".tmp", "w") as f:
        json.dump(info, f, indent=1)
    os.replace(path + ".tmp", path)


def render_to(path):
    bpy.context.scene.render.filepath = path
    t0 = time.time()
    bpy.ops.render.render(write_still=True)
    return time.time() - t0


def half_seed(seed, k):
    """Cycles' seed of half k of --seed `seed`. Consecutive seeds give
    correlated pixel sampling in Cycles 3.4 (measured on ring, 48 px: seeds 10
    and 11 differ by 30 % less than unrelated seeds), which would make the
    halves' noise estimate too small, so each half's seed is a hash
    (Knuth's multiplicative constant; Cycles takes 0 .. 2^31 - 1)."""
    return ((seed * 2 + k + 1) * 2654435761) % 2147483647


def average_exr(a, b, out):
    """out = (a + b) / 2, float EXR with the scene's output settings."""
    import numpy
    ia, ib = bpy.data.images.load(a), bpy.data.images.load(b)
    n = len(ia.pixels)
    pa, pb = numpy.empty(n, numpy.float32), numpy.empty(n, numpy.float32)
    ia.pixels.foreach_get(pa)
    ib.pixels.foreach_get(pb)
    w, h = ia.size
    m = bpy.data.images.new("average", w, h, alpha=True, float_buffer=True)
    names = m.colorspace_settings.bl_rna.properties["name"].enum_items.keys()
    m.colorspace_settings.name = "Linear" if "Linear" in names else "Linear Rec.709"  # Blender 3.x / 4.x
    m.pixels.foreach_set(0.5 * (pa + pb))
    m.save_render(out, scene=bpy.context.scene)  # EXR: linear values as they are


def main(argv):
    ap = argparse.ArgumentParser(prog="run_cycles.py")
    src = ap.add_mutually_exclusive_group(required=True)
    src.add_argument("--scene", help="a sample of exporters/blender/make_samples.py")
    src.add_argument("--gltf", help="a .gltf or .glb file, through Blender's importer")
    src.add_argument("--blend", help="a .blend file: its scene as the artist set it up")
    ap.add_argument("--info", help="with --gltf: `photonbridge info --json` of the file (camera, units, origin)")
    ap.add_argument("--camera", help="with --gltf: the camera photonbridge renders (default: its first)")
    ap.add_argument("--materials", choices=["principled", "bsdf", "gltf", "blend"],
                    help="material model (see the module comment)")
    ap.add_argument("--out", required=True)
    ap.add_argument("--width", type=int, default=0, help="image width (height from the aspect)")
    ap.add_argument("--height", type=int, default=0)
    ap.add_argument("--samples", type=int, default=256)
    ap.add_argument("--threads", type=int, default=0, help="0: all cores")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--bounces", type=int, default=64, help="max bounces (0: direct light only)")
    ap.add_argument("--halves", action="store_true", help="two independent halves and their average")
    args = ap.parse_args(argv)
    source = "sample" if args.scene else ("blend" if args.blend else "gltf")
    materials = args.materials or {"sample": "principled", "gltf": "gltf", "blend": "blend"}[source]
    if (source, materials) not in MODEL:
        ap.error("--materials %s does not apply to --%s" % (materials, source if source != "sample" else "scene"))
    out = os.path.abspath(args.out)
    info = {"renderer": "cycles", "blender": bpy.app.version_string, "source": source,
            "scene": args.scene or os.path.abspath(args.gltf or args.blend), "materials": materials,
            "material_model": MODEL[(source, materials)], "notes": []}
    cg = load_module("pb_cycles_gltf", os.path.join(HERE, "cycles_gltf.py"))
    tmpdirs = []
    sc = bpy.context.scene
    r = sc.render
    if source == "sample":
        samples = load_samples_module()
        if args.scene not in samples.SCENES:
            print("run_cycles: unknown scene '%s' (have: %s)" % (args.scene, ", ".join(samples.SCENES)),
                  file=sys.stderr)
            return 2
        tmpdirs = samples.SCENES[args.scene]() or []
        sc = bpy.context.scene
        r = sc.render
        # Static renders show the rest pose, which make_samples exports as frame 0.
        sc.frame_set(0)
        if materials == "bsdf":
            simple_bsdfs(cg)
            cg.convert_lights()
        if args.width:
            aspect = r.resolution_y / r.resolution_x
            r.resolution_x = args.width
            r.resolution_y = args.height or max(1, round(args.width * aspect))
    elif source == "blend":
        # The scene as the artist left it: its materials, lights, world and
        # active camera; only the render settings below are validation's.
        try:
            bpy.ops.wm.open_mainfile(filepath=os.path.abspath(args.blend), load_ui=False)
        except RuntimeError as e:
            info["error"] = "Blender cannot open %s: %s" % (args.blend, cg.one_line(e))
            write_json(out + ".json", info)
            print("run_cycles: error: %s" % info["error"], file=sys.stderr)
            return 1
        sc = bpy.context.scene
        r = sc.render
        if sc.camera is None:
            info["error"] = "%s: the scene '%s' has no active camera" % (args.blend, sc.name)
            write_json(out + ".json", info)
            print("run_cycles: error: %s" % info["error"], file=sys.stderr)
            return 1
        r.use_border = False
        if args.width:
            aspect = (r.resolution_y * r.pixel_aspect_y) / (r.resolution_x * r.pixel_aspect_x)
            r.resolution_x = args.width
            r.resolution_y = args.height or max(1, round(args.width * aspect))
        info["camera"] = sc.camera.name
        info["notes"].append("Cycles renders the .blend's own materials, lights and world; validation's render "
                             "settings replace its own (bounces, 1-px box filter, no denoising, clamping, "
                             "light threshold or caustic blur)")
    else:
        if not args.info:
            ap.error("--gltf needs --info (photonbridge info --json of the file)")
        with open(args.info) as f:
            pbinfo = json.load(f)
        bpy.ops.wm.read_factory_settings(use_empty=True)
        sc = bpy.context.scene
        r = sc.render
        try:
            cam, notes = cg.setup(os.path.abspath(args.gltf), pbinfo, materials, args.camera)
        except Exception as e:  # ImportFailed, or a bug: either way one line in the report
            if not isinstance(e, cg.ImportFailed):
                traceback.print_exc()
            info["error"] = str(e) if isinstance(e, cg.ImportFailed) else \
                "Cycles glTF path: %s: %s (a bug; traceback in the log)" % (type(e).__name__, cg.one_line(e))
            write_json(out + ".json", info)
            print("run_cycles: error: %s: %s" % (args.gltf, info["error"]), file=sys.stderr)
            return 1
        info["notes"] += notes
        info["camera"] = cam.get("name")
        r.resolution_x, r.resolution_y = cg.image_size(cam, args.width, args.height)
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    if source != "blend":
        sc.world = None  # glTF has no environment: black, as in the reference
    configure(sc, out, args.samples, args.threads, args.seed, args.bounces)
    if args.halves:
        half = max(1, args.samples // 2)
        sc.cycles.samples = half
        parts = [out + ".a.exr", out + ".b.exr"]
        dt = 0.0
        for k, p in enumerate(parts):
            sc.cycles.seed = half_seed(args.seed, k)
            dt += render_to(p)
        average_exr(parts[0], parts[1], out)
        info["halves"] = [os.path.basename(p) for p in parts]
        info["half_seeds"] = [half_seed(args.seed, k) for k in (0, 1)]
        info["samples"] = 2 * half
    else:
        dt = render_to(out)
        info["samples"] = args.samples
    for d in tmpdirs:
        for fn in os.listdir(d):
            os.remove(os.path.join(d, fn))
        os.rmdir(d)
    info.update({"width": r.resolution_x, "height": r.resolution_y, "seed": args.seed, "bounces": args.bounces,
                 "pixel_filter": "box 1 px", "render_s": round(dt, 3)})
    write_json(out + ".json", info)
    print("run_cycles: %s %dx%d %d spp in %.3f s" % (out, r.resolution_x, r.resolution_y, info["samples"], dt))
    return 0


def run_jobs(path):
    """--jobs FILE: a JSON list of argument lists, each run as one
    invocation in this Blender process (tests render many scenes without
    paying Blender's start-up for each). Status 1 when any job failed."""
    with open(path) as f:
        jobs = json.load(f)
    return 1 if sum(main(argv) != 0 for argv in jobs) else 0


if __name__ == "__main__":
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    rc = run_jobs(argv[1]) if argv[:1] == ["--jobs"] and len(argv) == 2 else main(argv)
    if rc:
        sys.exit(rc)
