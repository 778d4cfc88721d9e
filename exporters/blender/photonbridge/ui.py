"""The photonbridge panel (Render Properties) and the standard Blender
panels the engine shows: every panel that lists the generic
'BLENDER_RENDER' engine (dimensions, output, colour management, camera,
light cone, ...) plus the EEVEE panels whose settings the writer reads
(light power and radius, material surface and settings, world surface)."""
import bpy

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


class PHOTONBRIDGE_PT_render(bpy.types.Panel):
    bl_label = "photonbridge"
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        s = context.scene.photonbridge
        col = layout.column()
        col.prop(s, "photons")
        col.prop(s, "iterations")
        col.prop(s, "progressive")
        col.prop(s, "first_bounce")
        col.prop(s, "tracer")
        if s.tracer == "images":
            col.prop(s, "image_maps")
            col.prop(s, "image_map_resolution")
        col.prop(s, "blender_bounces")
        col.prop(s, "photon_bounces")
        col = layout.column()
        col.prop(s, "spp")
        col.prop(s, "specular_depth")
        col.prop(s, "filter_passes")
        col = layout.column()
        col.prop(s, "time_limit")
        col.prop(s, "preview_interval")
        col.prop(s, "device")
        col.prop(s, "seed")
        col.prop(s, "animation_sequence")


classes = (PHOTONBRIDGE_PT_render,)
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
