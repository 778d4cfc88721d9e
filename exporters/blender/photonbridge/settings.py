"""The photonbridge render settings (Scene.photonbridge) and their command
line: every setting is one option of `photonbridge render` and nothing
else (cli_args), so what Blender renders is what the CLI renders with the
same options. The settings, their ranges and defaults come from
photonbridge's settings table (settings_table.py, generated from the
binary's own: `photonbridge settings --python`): the ones an artist sets
have properties with Blender's wording here (PROPERTY_SETTING), every other
one of the table gets a property under its own name (TABLE_PROPERTIES,
the Advanced panels). The defaults are the CLI's (tests/blender/bl_ui.py compares
them with `photonbridge render --help-all`), but for F12's quality
(FINAL_RENDER: a bare `photonbridge render` refines photon maps to its
default noise threshold, F12 a final render of 16 progressive maps at 16
samples, limited to Blender's Max Bounces as Cycles is, and to the Noise
Threshold when that is on); the add-on's own settings (the viewport's samples,
the picture's refresh, the animation mode) are listed in ADDON_ONLY.

The property names are stored in .blend files: a rename needs a migration,
so new wording goes into the names shown (name=) and the tooltips."""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty

from . import devices
from .settings_table import BY_ID, SETTINGS

# Settings with no `photonbridge render` default to follow: the add-on's own.
ADDON_ONLY = ("viewport_samples", "preview_interval", "blender_bounces", "animation_sequence", "device_menu",
              "use_noise_threshold", "use_viewport_noise_threshold", "viewport_noise_threshold")
# F12 renders a final picture where the CLI's bare defaults are a preview:
# these differ from the CLI's on purpose (the .blend samples are measured
# against Cycles at these).
FINAL_RENDER = {"spp": 16, "iterations": 16, "progressive": True, "blender_bounces": True, "noise_threshold": 0.02}

# The properties with the artist's names and the settings they set (the
# table's id); Limit Bounces sets max_bounces from Cycles' Max Bounces.
PROPERTY_SETTING = {"spp": "spp", "noise_threshold": "noise_threshold", "time_limit": "time_limit",
                    "filter_passes": "atrous_iterations", "photons": "photons", "iterations": "iterations",
                    "progressive": "progressive", "first_bounce": "first_bounce", "tracer": "tracer",
                    "image_maps": "image_maps", "image_map_resolution": "image_map_resolution",
                    "estimator": "estimator", "photon_bounces": "photon_bounces",
                    "specular_depth": "max_specular_depth", "caustic_filter": "smoothing_caustic"}
# Every other setting the table offers Blender: a property of its own name.
TABLE_PROPERTIES = tuple(t["id"] for t in SETTINGS if "blender" in t["surfaces"] and t["id"] != "max_bounces"
                         and t["id"] not in PROPERTY_SETTING.values())
# Their labels (the rest: the id in words).
LABELS = {"glossy_path_roughness": "Glossy Path Roughness", "direct_only": "Direct Light Only",
          "r_max": "Footprint Clamp", "alpha": "Progressive Alpha", "knn_k": "Nearest Photons",
          "vsch_radius": "Cluster Photon Radius", "vsch_directional": "Directional Clusters",
          "splat_ntile": "Splat Density", "splat_lmax": "Splat Full-Size Length",
          "splat_smax": "Splat Stretch", "splat_tile": "Splat Tile", "leaf_size": "BVH Leaf Size",
          "bandwidth_c0": "Variable Bandwidth", "upsample_levels": "Up-sampling Levels",
          "no_shading_correction": "No Shading Correction", "atrous_clip": "Filter Detail Clip"}


def table_range(setting, **kw):
    """min, max and default of a property from the table's row (the
    property's own keywords win): an "automatic" default outside the
    option's range (0 where the option starts at 1) widens min to it."""
    t = BY_ID[setting]
    out = {}
    if t["kind"] == "choice":
        out["default"] = t["default"]
    elif t["kind"] == "bool":
        out["default"] = t["default"]
    else:
        out["default"] = t["default"]
        if t["min"] is not None:
            out["min"] = min(t["min"], t["default"])
            out["max"] = t["max"]
    out.update(kw)
    return out


def _words(setting):
    return LABELS.get(setting, setting.replace("_", " ").title())


def _table_property(t):
    """A property for table row t: its range, default and help (the
    option's, with the option named)."""
    desc = "%s (--%s)" % (t["help"][:1].upper() + t["help"][1:], t["cli"])
    if t["kind"] in ("u32", "f64") and t["min"] is not None and not t["min"] <= t["default"] <= t["max"]:
        desc += ". %g: the renderer's own choice" % t["default"]
    if t["kind"] == "bool":
        return BoolProperty(name=_words(t["id"]), description=desc, default=t["default"])
    if t["kind"] == "choice":
        return EnumProperty(name=_words(t["id"]), description=desc, default=t["default"],
                            items=[(c, c, c) for c in t["choices"]])
    kw = table_range(t["id"])
    if t["kind"] == "u32":
        return IntProperty(name=_words(t["id"]), description=desc, **kw)
    if "max" not in kw:
        kw.update(min=0.0, max=1e9)
    return FloatProperty(name=_words(t["id"]), description=desc, precision=3, **kw)


def setting_value(s, setting):
    """The value of a table setting on the settings s, in the table's terms."""
    if setting == "max_bounces":  # Limit Bounces: Cycles' Max Bounces B is B + 1 events
        return cycles_max_bounces(s.id_data) + 1 if s.blender_bounces else 0
    for prop, sid in PROPERTY_SETTING.items():
        if sid == setting:
            return getattr(s, prop)
    return getattr(s, setting)


def is_automatic(setting, value):
    """The value means "the renderer's own choice": the table's default
    where it lies outside the option's range (0 for an option from 1)."""
    t = BY_ID[setting]
    return t["kind"] in ("u32", "f64") and t["min"] is not None and not (t["min"] <= value <= t["max"])


class PhotonbridgeSettings(bpy.types.PropertyGroup):
    # ---- Sampling ---------------------------------------------------------------
    spp: IntProperty(
        name="Samples", description="Camera samples per pixel for the final render. 1 takes each pixel's "
        "centre; more smooth the edges and the noise. At least one sample is taken per photon map (--spp)",
        **table_range("spp", default=FINAL_RENDER["spp"]))
    use_noise_threshold: BoolProperty(
        name="Noise Threshold", description="Stop refining once the render's own estimate of its noise is "
        "below the Noise Threshold; Maps is then the most it renders (--noise-threshold)", default=False)
    noise_threshold: FloatProperty(
        name="Noise Threshold", description="The noise the render refines down to: the RMS error of the "
        "displayed picture it estimates from its independent photon maps, white being 1 (0.01: 40 dB "
        "PSNR, 0.02: 34 dB, 0.03: 30 dB). Lower: less noise, longer render (--noise-threshold)",
        **table_range("noise_threshold", default=FINAL_RENDER["noise_threshold"], min=0.001), soft_max=0.1,
        precision=3)
    viewport_samples: IntProperty(
        name="Viewport Samples", description="Passes the Rendered viewport refines before it rests; "
        "0: it never rests", default=1024, min=0, max=1 << 24)
    use_viewport_noise_threshold: BoolProperty(
        name="Viewport Noise Threshold", description="The Rendered viewport rests once its own estimate of "
        "its noise is below the Viewport Noise Threshold (or after Viewport Samples passes)", default=False)
    viewport_noise_threshold: FloatProperty(
        name="Viewport Noise Threshold", description="The noise the Rendered viewport refines down to: the "
        "RMS error of the displayed picture, white being 1, estimated from its passes (0.05: 26 dB PSNR, "
        "0.02: 34 dB)", **table_range("noise_threshold", default=0.05, min=0.001), soft_max=0.2, precision=3)
    time_limit: FloatProperty(
        name="Time Limit", description="Stop starting new photon maps after this long; the picture averages "
        "the maps finished by then. 0: no limit (--time-limit)",
        **table_range("time_limit"), unit='TIME_ABSOLUTE', subtype='TIME_ABSOLUTE')
    filter_passes: IntProperty(
        name="Filter Passes", description="Smooth the indirect light with this many edge-preserving filter "
        "passes (denoising); 0: off (--atrous-iterations)", **table_range("atrous_iterations"))
    seed: IntProperty(
        name="Seed", description="Seed of the random numbers: another value gives another noise pattern "
        "(--seed)", default=0, min=0)
    # ---- Photons (Sampling > Advanced) ------------------------------------------------
    photons: IntProperty(
        name="Photons per Map", description="Light paths traced from the lights for each photon map. More: "
        "finer indirect light and caustics, more memory (--photons)",
        **table_range("photons", default=262144))
    iterations: IntProperty(
        name="Maps", description="Photon maps traced one after the other and averaged; the picture refines "
        "after each one. More maps: less noise and blotches, longer render (--iterations)",
        **table_range("iterations", default=FINAL_RENDER["iterations"], min=1))
    progressive: BoolProperty(
        name="Progressive", description="Each photon map gathers over a smaller area than the one before, so "
        "that many maps (or a time limit) keep getting sharper instead of only less noisy (--progressive)",
        default=FINAL_RENDER["progressive"])
    first_bounce: EnumProperty(
        name="First Bounce", description="How photons leaving a light find the first surface they hit "
        "(--first-bounce)",
        items=[("auto", "Auto", "Shadow maps for lights that light mostly empty space (open scenes), traced "
                "for the others"),
               ("traced", "Traced", "Traced from the light: exact"),
               ("rsm", "Shadow Maps", "Picked from the lights' shadow maps where they reflect the most light: "
                "faster in open scenes, may miss geometry thinner than a shadow-map pixel")],
        default="traced")
    tracer: EnumProperty(
        name="Photon Tracer", description="How photons find what they hit after the first bounce (--tracer)",
        items=[("bvh", "BVH", "Exact hits against the scene's geometry"),
               ("images", "Environment Maps", "Looked up in a few cube maps of the scene instead: nothing to "
                "rebuild when objects move, but approximate; what no map sees is missed")],
        default="bvh")
    image_maps: IntProperty(
        name="Environment Maps", description="How many cube maps the Environment Maps tracer places in the "
        "scene (--image-maps)", **table_range("image_maps", default=8))
    image_map_resolution: IntProperty(
        name="Map Resolution", description="Pixels per side of each cube map face (--image-map-resolution)",
        **table_range("image_map_resolution", default=128))
    estimator: EnumProperty(
        name="Estimator", description="How the light of the photons near a point is added up (final render "
        "only; the viewport uses BVH Footprints) (--estimator)",
        items=[("lbvh", "BVH Footprints", "Each photon lights the area around it; exact and the default"),
               ("knn", "Nearest Photons", "The nearest photons of each point, as classic photon mapping"),
               ("splat", "Screen Splats", "Photons splatted in screen space: fast, approximate"),
               ("vsch", "Clustered", "Photons gathered over clusters of the visible points: fast, approximate"),
               ("auto", "Auto", "Chosen per scene and device")],
        default="lbvh")
    # ---- Light Paths ------------------------------------------------------------------
    blender_bounces: BoolProperty(
        name="Limit Bounces", description="Limit light paths to Max Bounces, as Cycles does "
        "(--max-bounces); off: paths end at random when they have little light left (unbounded), "
        "the CLI's default", default=FINAL_RENDER["blender_bounces"])
    photon_bounces: IntProperty(
        name="Photon Bounces", description="Bounces kept along each photon's path; 0: from Max Bounces, "
        "or unbounded (--photon-bounces)", **table_range("photon_bounces"))
    specular_depth: IntProperty(
        name="Mirror and Glass", description="Mirror and glass surfaces followed from the camera; 0: from "
        "Max Bounces, or ended at random after the 8th (--max-specular-depth)", **table_range("max_specular_depth"))
    caustic_filter: FloatProperty(
        name="Filter Caustics", description="How far each caustic photon (light focused by mirrors and "
        "glass) spreads: above 1 blurs caustics (smoother, less noisy), below 1 sharpens them (noisier) "
        "(--smoothing-caustic)", default=1.0, min=0.01, max=100.0, soft_max=8.0)
    # ---- Performance --------------------------------------------------------------------
    device: IntProperty(
        name="Device Number", description="Vulkan device number (photonbridge info --devices); -1: the "
        "default choice, a discrete GPU first (--device). Set through the Device menu",
        default=-1, min=-1, max=64)
    device_menu: EnumProperty(
        name="Device", description="The GPU (Vulkan device) that renders (--device)",
        items=devices.enum_items, get=devices.enum_get, set=devices.enum_set)
    traversal: EnumProperty(
        name="Ray Tracing", description="How rays find surfaces (--traversal)",
        items=[("auto", "Auto", "The GPU's ray-tracing hardware (Vulkan ray queries: NVIDIA RTX, AMD RDNA 2 and "
                "later, Intel Arc) where the device has it, else photonbridge's own BVH (also on a CPU device)"),
               ("bvh", "BVH", "photonbridge's own BVH on every device (the same pictures)"),
               ("ray-query", "Ray Queries", "The device's ray queries; the render fails on a device without")],
        default="auto")
    preview_interval: FloatProperty(
        name="Refresh", description="Seconds between updates of the picture while the render refines",
        default=2.0, min=0.0, max=600.0, unit='TIME_ABSOLUTE', subtype='TIME_ABSOLUTE')
    animation_sequence: BoolProperty(
        name="Animation as Sequence",
        description="For animation renders: render the whole frame range in one go, each frame reusing "
        "the light of the frames before (less flicker), and hand Blender the frames one by one (--frames)",
        default=False)


def cycles_max_bounces(scene):
    """Light Paths > Max Bounces of the scene (Cycles' property; 12, its
    default, when the Cycles add-on is off)."""
    return int(getattr(getattr(scene, "cycles", None), "max_bounces", 12))


def cli_args(s, sequence=False, serve=False):
    """`photonbridge render` options of the settings `s` (the frame size,
    crop, files and progress options are the engine's). sequence: for
    --frames and `photonbridge serve` (the viewport), which render every
    frame fully: no time limit or noise threshold. serve: for `serve`
    (a sequence too)."""
    sequence = sequence or serve
    args = ["--photons", str(s.photons), "--iterations", str(s.iterations), "--spp", str(max(s.spp, 1)),
            "--first-bounce", s.first_bounce, "--tracer", s.tracer, "--seed", str(s.seed)]
    if s.tracer == "images":
        args += ["--image-maps", str(s.image_maps), "--image-map-resolution", str(s.image_map_resolution)]
    if s.blender_bounces:
        # Cycles counts the direct light's bounce as 0: Max Bounces B is B + 1
        # scattering events, photonbridge's --max-bounces.
        args += ["--max-bounces", str(cycles_max_bounces(s.id_data) + 1)]
    if s.photon_bounces:
        args += ["--photon-bounces", str(s.photon_bounces)]
    if s.specular_depth:
        args += ["--max-specular-depth", str(s.specular_depth)]
    if abs(s.caustic_filter - 1.0) > 1e-6:
        args += ["--smoothing-caustic", "%g" % s.caustic_filter]
    if s.estimator != BY_ID["estimator"]["default"]:
        args += ["--estimator", s.estimator]
    if s.time_limit > 0 and not sequence:
        args += ["--time-limit", "%g" % s.time_limit]
    if s.use_noise_threshold and not sequence:
        args += ["--noise-threshold", "%g" % s.noise_threshold]
    if s.progressive:
        args.append("--progressive")
    if s.filter_passes:
        args += ["--atrous-iterations", str(s.filter_passes)]
    args += table_args(s, sequence)
    if s.device >= 0:
        args += ["--device", str(s.device)]
    if s.traversal != "auto":
        args += ["--traversal", s.traversal]
    return args


def needs_met(s, setting):
    """Whether the table's `needs` of a setting holds on s (--knn-k does
    something only with --estimator knn or auto)."""
    n = BY_ID[setting]["needs"]
    if not n:
        return True
    other, names = n.split("=")
    return setting_value(s, other) in names.split(",")


def table_args(s, sequence=False):
    """The options of the TABLE_PROPERTIES that differ from the table's
    default (a sequence takes only those offered to view and serve)."""
    args = []
    for sid in TABLE_PROPERTIES:
        t = BY_ID[sid]
        if (sequence and "live" not in t["surfaces"]) or not needs_met(s, sid):
            continue
        v = getattr(s, sid)
        if t["kind"] == "bool":
            if bool(v) != bool(t["default"]):
                args.append("--" + t["cli"])
        elif t["kind"] == "choice":
            if v != t["default"]:
                args += ["--" + t["cli"], v]
        elif t["kind"] == "u32":
            if int(v) != int(t["default"]):
                args += ["--" + t["cli"], str(int(v))]
        elif abs(float(v) - float(t["default"])) > 1e-6 * max(1.0, abs(float(t["default"]))):
            # a float property holds single precision: 0.15 reads 0.150000006
            args += ["--" + t["cli"], "%.6g" % v]
    return args


def request_settings(s):
    """serve's "settings" request of the settings s: every setting the
    table offers to requests, under its id; a value meaning "automatic"
    (0 for an option from 1) cannot be sent, and is listed in the second
    result instead (a change to or from it restarts serve)."""
    req, automatic = {}, []
    for t in SETTINGS:
        sid = t["id"]
        if "request" not in t["surfaces"] or "blender" not in t["surfaces"]:
            continue
        v = setting_value(s, sid)
        if sid == "spp":
            v = max(int(v), 1)
        if t["kind"] in ("u32", "f64") and is_automatic(sid, v):
            automatic.append(sid)
            continue
        req[sid] = bool(v) if t["kind"] == "bool" else int(v) if t["kind"] == "u32" else \
            v if t["kind"] == "choice" else float("%.6g" % v)  # a float property's single precision
    return req, automatic


classes = (PhotonbridgeSettings,)


def register():
    for sid in TABLE_PROPERTIES:
        PhotonbridgeSettings.__annotations__[sid] = _table_property(BY_ID[sid])
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.Scene.photonbridge = PointerProperty(type=PhotonbridgeSettings)


def unregister():
    del bpy.types.Scene.photonbridge
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
