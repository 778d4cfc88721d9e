"""The photonbridge panels (Render Properties: Sampling with Render,
Viewport and Advanced (the photon maps), Light Paths with Max Bounces and
Caustics, Film, Performance), laid out as Cycles' are, and the standard
Blender panels the engine shows: every panel that lists the generic
'BLENDER_RENDER' engine (dimensions, output, colour management, camera,
light cone, ...) plus the EEVEE panels whose settings the writer reads
(light power and radius, material surface and settings, world surface).
Cycles' own panels stay hidden; the one Cycles setting the engine reads
(Max Bounces) is drawn in photonbridge's Light Paths panel."""
import textwrap

import bpy

from . import devices, settings

ENGINE = "PHOTONBRIDGE"

# EEVEE panels that show what photonbridge reads; generic panels that
# duplicate them or show what it ignores are left out. Names of every
# Blender from 3.4 on: a name this Blender lacks is skipped (3.4's
# EEVEE_MATERIAL_PT_settings became EEVEE_NEXT_MATERIAL_PT_settings in 4.2;
# EEVEE's engine id is BLENDER_EEVEE_NEXT in 4.2-4.5, BLENDER_EEVEE again in 5.0).
EXTRA_PANELS = ("DATA_PT_EEVEE_light", "DATA_PT_EEVEE_light_distance", "EEVEE_MATERIAL_PT_context_material",
                "EEVEE_MATERIAL_PT_surface", "EEVEE_MATERIAL_PT_settings", "EEVEE_NEXT_MATERIAL_PT_settings",
                "EEVEE_WORLD_PT_surface")
SKIP_PANELS = ("DATA_PT_light", "DATA_PT_area", "DATA_PT_falloff_curve", "DATA_PT_preview", "MATERIAL_PT_preview")


def compat_panels():
    """The standard panels the engine is added to."""
    out = []
    for name in dir(bpy.types):
        t = getattr(bpy.types, name)
        ce = getattr(t, "COMPAT_ENGINES", None)
        if not isinstance(ce, set) or name in SKIP_PANELS or name.startswith("DATA_PT_lightprobe"):
            continue
        if 'BLENDER_RENDER' in ce or name in EXTRA_PANELS:
            out.append(t)
    return out


class PhotonbridgePanel:
    """Render Properties panels of the engine, laid out as Cycles' are."""
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def split_layout(self):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        return layout


class PHOTONBRIDGE_PT_sampling(PhotonbridgePanel, bpy.types.Panel):
    bl_label = "Sampling"

    def draw(self, context):
        pass


class PHOTONBRIDGE_PT_sampling_render(PhotonbridgePanel, bpy.types.Panel):
    bl_label = "Render"
    bl_parent_id = "PHOTONBRIDGE_PT_sampling"

    def draw(self, context):
        s = context.scene.photonbridge
        layout = self.split_layout()
        row = layout.row(align=True)  # Cycles' Noise Threshold: a switch and its value
        row.prop(s, "use_noise_threshold", text="")
        sub = row.row()
        sub.active = s.use_noise_threshold
        sub.prop(s, "noise_threshold")
        col = layout.column(align=True)
        col.prop(s, "spp", text="Samples")
        col.prop(s, "time_limit")
        col = self.layout.column()
        col.prop(s, "filter_passes")


class PHOTONBRIDGE_PT_sampling_viewport(PhotonbridgePanel, bpy.types.Panel):
    bl_label = "Viewport"
    bl_parent_id = "PHOTONBRIDGE_PT_sampling"

    def draw(self, context):
        s = context.scene.photonbridge
        layout = self.split_layout()
        row = layout.row(align=True)
        row.prop(s, "use_viewport_noise_threshold", text="")
        sub = row.row()
        sub.active = s.use_viewport_noise_threshold
        sub.prop(s, "viewport_noise_threshold", text="Noise Threshold")
        layout.prop(s, "viewport_samples", text="Samples")


class PHOTONBRIDGE_PT_sampling_advanced(PhotonbridgePanel, bpy.types.Panel):
    """The photon maps: photonbridge's own knobs, closed by default."""
    bl_label = "Advanced"
    bl_parent_id = "PHOTONBRIDGE_PT_sampling"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        s = context.scene.photonbridge
        layout = self.split_layout()
        col = layout.column(align=True)
        col.prop(s, "photons")
        col.prop(s, "iterations")
        col = layout.column()
        col.prop(s, "progressive")
        col.prop(s, "first_bounce")
        col.prop(s, "tracer")
        if s.tracer == "images":
            sub = col.column(align=True)
            sub.prop(s, "image_maps")
            sub.prop(s, "image_map_resolution")
        col.prop(s, "estimator")
        layout.column().prop(s, "seed")


class PHOTONBRIDGE_PT_sampling_algorithm(PhotonbridgePanel, bpy.types.Panel):
    """Every other setting of photonbridge's settings table
    (settings.TABLE_PROPERTIES), under its heading; one that does nothing
    with the current choices (the nearest photons' count with BVH
    Footprints) is greyed out."""
    bl_label = "Algorithm"
    bl_parent_id = "PHOTONBRIDGE_PT_sampling_advanced"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        s = context.scene.photonbridge
        layout = self.split_layout()
        group = None
        col = layout.column()
        for sid in settings.TABLE_PROPERTIES:
            g = settings.BY_ID[sid]["group"]
            if g != group:
                layout.label(text=g)
                col = layout.column()
                group = g
            row = col.row()
            row.active = settings.needs_met(s, sid)
            row.prop(s, sid)


class PHOTONBRIDGE_PT_light_paths(PhotonbridgePanel, bpy.types.Panel):
    bl_label = "Light Paths"

    def draw(self, context):
        pass


class PHOTONBRIDGE_PT_light_paths_max_bounces(PhotonbridgePanel, bpy.types.Panel):
    bl_label = "Max Bounces"
    bl_parent_id = "PHOTONBRIDGE_PT_light_paths"

    def draw_header(self, context):
        self.layout.prop(context.scene.photonbridge, "blender_bounces", text="")

    def draw(self, context):
        scene = context.scene
        s = scene.photonbridge
        layout = self.split_layout()
        col = layout.column(align=True)
        cycles = getattr(scene, "cycles", None)
        if cycles is not None and hasattr(cycles, "max_bounces"):
            # Cycles' own property: the same Max Bounces in both engines.
            row = col.row()
            row.active = s.blender_bounces
            row.prop(cycles, "max_bounces", text="Total")
        else:
            row = col.row()
            row.active = s.blender_bounces
            row.label(text="Total: %d (the Cycles add-on is off)" % settings.cycles_max_bounces(scene))
        col = layout.column(align=True)
        col.prop(s, "photon_bounces")
        col.prop(s, "specular_depth")


class PHOTONBRIDGE_PT_light_paths_caustics(PhotonbridgePanel, bpy.types.Panel):
    bl_label = "Caustics"
    bl_parent_id = "PHOTONBRIDGE_PT_light_paths"

    def draw(self, context):
        s = context.scene.photonbridge
        layout = self.split_layout()
        layout.prop(s, "caustic_filter")
        col = layout.column(align=True)
        col.label(text="Reflective and refractive caustics are always on:", icon='INFO')
        col.label(text="the photon maps carry them", icon='BLANK1')


class PHOTONBRIDGE_PT_film(PhotonbridgePanel, bpy.types.Panel):
    bl_label = "Film"

    def draw(self, context):
        scene = context.scene
        layout = self.split_layout()
        # Colour management's exposure: applied by Blender to the
        # scene-linear result, as it is to Cycles' (the render itself is
        # not scaled).
        layout.prop(scene.view_settings, "exposure")
        layout.prop(scene.render, "film_transparent", text="Transparent")


class PHOTONBRIDGE_PT_performance(PhotonbridgePanel, bpy.types.Panel):
    bl_label = "Performance"

    def draw(self, context):
        scene = context.scene
        s = scene.photonbridge
        layout = self.split_layout()
        row = layout.row(align=True)
        row.prop(s, "device_menu")
        row.operator("photonbridge.refresh_devices", text="", icon='FILE_REFRESH')
        error = devices.listing(context)["error"]
        if error:
            col = layout.column(align=True)
            col.alert = True
            for i, line in enumerate(textwrap.wrap(error, 60)[:4]):
                col.label(text=line, icon='ERROR' if i == 0 else 'BLANK1')
        layout.prop(s, "traversal")
        layout.prop(s, "preview_interval")
        layout.prop(scene.render, "preview_pixel_size", text="Viewport Pixel Size")
        layout.prop(s, "animation_sequence")


classes = (PHOTONBRIDGE_PT_sampling, PHOTONBRIDGE_PT_sampling_render, PHOTONBRIDGE_PT_sampling_viewport,
           PHOTONBRIDGE_PT_sampling_advanced, PHOTONBRIDGE_PT_sampling_algorithm, PHOTONBRIDGE_PT_light_paths, PHOTONBRIDGE_PT_light_paths_max_bounces,
           PHOTONBRIDGE_PT_light_paths_caustics, PHOTONBRIDGE_PT_film, PHOTONBRIDGE_PT_performance)
_added = []


def register():
    for c in classes:
        bpy.utils.register_class(c)
    for p in compat_panels():
        if ENGINE not in p.COMPAT_ENGINES:
            p.COMPAT_ENGINES.add(ENGINE)
            _added.append(p)


def unregister():
    for p in _added:
        p.COMPAT_ENGINES.discard(ENGINE)
    _added.clear()
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
