"""The photonbridge render settings (Scene.photonbridge) and their command
line: every setting is one option of `photonbridge render` and nothing
else (cli_args), so what Blender renders is what the CLI renders with the
same options. The defaults are the CLI's (tests/blender/bl_ui.py compares
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

# Settings with no `photonbridge render` default to follow: the add-on's own.
ADDON_ONLY = ("viewport_samples", "preview_interval", "blender_bounces", "animation_sequence", "device_menu",
              "use_noise_threshold")
# F12 renders a final picture where the CLI's bare defaults are a preview:
# these differ from the CLI's on purpose (the .blend samples are measured
# against Cycles at these).
FINAL_RENDER = {"spp": 16, "iterations": 16, "progressive": True, "blender_bounces": True, "noise_threshold": 0.02}

# --smoothing-caustic's default (src/render: PB_PHOTON_SMOOTHING_CAUSTIC_DEFAULT)
CAUSTIC_FILTER_DEFAULT = 1.0


class PhotonbridgeSettings(bpy.types.PropertyGroup):
    # ---- Sampling ---------------------------------------------------------------
    spp: IntProperty(
        name="Samples", description="Camera samples per pixel for the final render. 1 takes each pixel's "
        "centre; more smooth the edges and the noise. At least one sample is taken per photon map (--spp)",
        default=FINAL_RENDER["spp"], min=1, max=1 << 20)
    use_noise_threshold: BoolProperty(
        name="Noise Threshold", description="Stop refining once the render's own estimate of its noise is "
        "below the Noise Threshold; Maps is then the most it renders (--noise-threshold)", default=False)
    noise_threshold: FloatProperty(
        name="Noise Threshold", description="The noise the render refines down to: the RMS error of the "
        "displayed picture it estimates from its independent photon maps, white being 1 (0.01: 40 dB "
        "PSNR, 0.02: 34 dB, 0.03: 30 dB). Lower: less noise, longer render (--noise-threshold)",
        default=FINAL_RENDER["noise_threshold"], min=0.001, max=0.5, soft_max=0.1, precision=3)
    viewport_samples: IntProperty(
        name="Viewport Samples", description="Passes the Rendered viewport refines before it rests; "
        "0: it never rests", default=1024, min=0, max=1 << 24)
    time_limit: FloatProperty(
        name="Time Limit", description="Stop starting new photon maps after this long; the picture averages "
        "the maps finished by then. 0: no limit (--time-limit)",
        default=0.0, min=0.0, max=1e6, unit='TIME_ABSOLUTE', subtype='TIME_ABSOLUTE')
    filter_passes: IntProperty(
        name="Filter Passes", description="Smooth the indirect light with this many edge-preserving filter "
        "passes (denoising); 0: off (--atrous-iterations)", default=0, min=0, max=12)
    seed: IntProperty(
        name="Seed", description="Seed of the random numbers: another value gives another noise pattern "
        "(--seed)", default=0, min=0)
    # ---- Photons (Sampling > Advanced) ------------------------------------------------
    photons: IntProperty(
        name="Photons per Map", description="Light paths traced from the lights for each photon map. More: "
        "finer indirect light and caustics, more memory (--photons)",
        default=262144, min=1, max=1 << 26)
    iterations: IntProperty(
        name="Maps", description="Photon maps traced one after the other and averaged; the picture refines "
        "after each one. More maps: less noise and blotches, longer render (--iterations)",
        default=FINAL_RENDER["iterations"], min=1, max=65536)
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
        "scene (--image-maps)", default=8, min=1, max=15)
    image_map_resolution: IntProperty(
        name="Map Resolution", description="Pixels per side of each cube map face (--image-map-resolution)",
        default=128, min=8, max=1024)
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
        "or unbounded (--photon-bounces)", default=0, min=0, max=255)
    specular_depth: IntProperty(
        name="Mirror and Glass", description="Mirror and glass surfaces followed from the camera; 0: from "
        "Max Bounces, or ended at random after the 8th (--max-specular-depth)", default=0, min=0, max=64)
    caustic_filter: FloatProperty(
        name="Filter Caustics", description="How far each caustic photon (light focused by mirrors and "
        "glass) spreads: above 1 blurs caustics (smoother, less noisy), below 1 sharpens them (noisier) "
        "(--smoothing-caustic)", default=CAUSTIC_FILTER_DEFAULT, min=0.01, max=100.0, soft_max=8.0)
    # ---- Performance --------------------------------------------------------------------
    device: IntProperty(
        name="Device Number", description="Vulkan device number (photonbridge info --devices); -1: the "
        "default choice, a discrete GPU first (--device). Set through the Device menu",
        default=-1, min=-1, max=64)
    device_menu: EnumProperty(
        name="Device", description="The GPU (Vulkan device) that renders (--device)",
        items=devices.enum_items, get=devices.enum_get, set=devices.enum_set)
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
    --frames, which renders every frame fully (no time limit). serve: for
    `photonbridge serve` (the viewport), which takes no --estimator."""
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
    if abs(s.caustic_filter - CAUSTIC_FILTER_DEFAULT) > 1e-6:
        args += ["--smoothing-caustic", "%g" % s.caustic_filter]
    if s.estimator != "lbvh" and not serve:
        args += ["--estimator", s.estimator]
    if s.time_limit > 0 and not sequence:
        args += ["--time-limit", "%g" % s.time_limit]
    if s.use_noise_threshold and not sequence and not serve:
        args += ["--noise-threshold", "%g" % s.noise_threshold]
    if s.progressive:
        args.append("--progressive")
    if s.filter_passes:
        args += ["--atrous-iterations", str(s.filter_passes)]
    if s.device >= 0:
        args += ["--device", str(s.device)]
    return args


classes = (PhotonbridgeSettings,)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.Scene.photonbridge = PointerProperty(type=PhotonbridgeSettings)


def unregister():
    del bpy.types.Scene.photonbridge
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
