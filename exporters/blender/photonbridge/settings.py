"""The photonbridge render settings (Scene.photonbridge) and their command
line: every setting is one option of `photonbridge render` and nothing
else (cli_args), so what Blender renders is what the CLI renders with the
same options."""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty


class PhotonbridgeSettings(bpy.types.PropertyGroup):
    photons: IntProperty(
        name="Photons", description="Photon paths traced per photon map (--photons)",
        default=262144, min=1, max=1 << 26)
    iterations: IntProperty(
        name="Maps", description="Independent photon maps averaged; the picture refines after each one "
        "(--iterations)", default=16, min=1, max=65536)
    spp: IntProperty(
        name="Samples", description="Camera samples per pixel, at least one per map (--spp)",
        default=16, min=1, max=1 << 20)
    time_limit: FloatProperty(
        name="Time Limit", description="Start no photon map after this many seconds; 0: none (--time-limit)",
        default=0.0, min=0.0, max=1e6, unit='TIME_ABSOLUTE', subtype='TIME_ABSOLUTE')
    progressive: BoolProperty(
        name="Progressive", description="Shrink the photon footprints between maps, so more maps converge "
        "(--progressive)", default=True)
    first_bounce: EnumProperty(
        name="First Bounce", description="How photons find their first hit (--first-bounce)",
        items=[("auto", "Auto", "Shadow maps for the lights whose map covers under half of their light "
                "(open scenes), traced for the others"),
               ("traced", "Traced", "Traced from the light"),
               ("rsm", "Shadow Maps", "Sampled from reflective shadow maps by reflected power")],
        default="traced")
    tracer: EnumProperty(
        name="Photon Tracer", description="How photons find their hits (--tracer)",
        items=[("bvh", "BVH", "Exact hits in the scene's bounding volume hierarchy"),
               ("images", "Environment Maps", "Searched in cube environment maps of the scene (seed 003): no "
                "hierarchy to update when objects move, approximate; what no map sees is missed")],
        default="bvh")
    image_maps: IntProperty(
        name="Maps", description="Environment maps of the Environment Maps tracer (--image-maps)",
        default=8, min=1, max=15)
    image_map_resolution: IntProperty(
        name="Map Resolution", description="Texels per cube-face side of each environment map "
        "(--image-map-resolution)", default=128, min=8, max=1024)
    blender_bounces: BoolProperty(
        name="Blender's Bounces", description="Limit paths to Light Paths > Max Bounces, as Cycles does "
        "(--max-bounces, Max Bounces + 1 scattering events); off: unbounded, paths end by Russian roulette",
        default=True)
    photon_bounces: IntProperty(
        name="Bounces", description="Bounces stored per photon path; 0: from Max Bounces, or unbounded "
        "(--photon-bounces)", default=0, min=0, max=255)
    specular_depth: IntProperty(
        name="Mirror Depth", description="Mirror and glass interactions followed from the camera; 0: from Max "
        "Bounces, or Russian roulette (--max-specular-depth)", default=0, min=0, max=64)
    filter_passes: IntProperty(
        name="Filter Passes", description="Edge-avoiding A-Trous passes over the indirect light; 0: off "
        "(--atrous-iterations)", default=0, min=0, max=12)
    device: IntProperty(
        name="Device", description="Vulkan device (photonbridge info --devices); -1: the default choice "
        "(a discrete GPU first) (--device)", default=-1, min=-1, max=64)
    seed: IntProperty(
        name="Seed", description="Random seed (--seed)", default=0, min=0)
    animation_sequence: BoolProperty(
        name="Animation as Sequence",
        description="For animation renders: render the whole frame range as one photonbridge sequence "
        "(--frames, temporal filtering across frames) and hand Blender the frames one by one",
        default=False)
    preview_interval: FloatProperty(
        name="Refresh", description="Seconds between picture refreshes while the render refines "
        "(--preview-interval)", default=2.0, min=0.0, max=600.0)


def cli_args(s, sequence=False):
    """`photonbridge render` options of the settings `s` (the frame size,
    crop, files and progress options are the engine's). sequence: for
    --frames, which renders every frame fully (no time limit)."""
    args = ["--photons", str(s.photons), "--iterations", str(s.iterations), "--spp", str(max(s.spp, 1)),
            "--first-bounce", s.first_bounce, "--tracer", s.tracer, "--seed", str(s.seed)]
    if s.tracer == "images":
        args += ["--image-maps", str(s.image_maps), "--image-map-resolution", str(s.image_map_resolution)]
    if s.blender_bounces:
        # Cycles counts the direct light's bounce as 0: Max Bounces B is B + 1
        # scattering events, photonbridge's --max-bounces.
        cycles = getattr(s.id_data, "cycles", None)
        args += ["--max-bounces", str(int(getattr(cycles, "max_bounces", 12)) + 1)]
    if s.photon_bounces:
        args += ["--photon-bounces", str(s.photon_bounces)]
    if s.specular_depth:
        args += ["--max-specular-depth", str(s.specular_depth)]
    if s.time_limit > 0 and not sequence:
        args += ["--time-limit", "%g" % s.time_limit]
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
