/* The pipeline's switches for a scene; see scene_plan.h. */
#include "render/scene/scene_plan.h"

#include <string.h>

#include "core/json.h"
#include "shared/pb_gpu.h"


/* The GPU's closure bits are the scene's closure kinds (scene.h
 * pb_blender_closures). */
_Static_assert(PB_CLOSURES_DIFFUSE == PB_BLENDER_CL_DIFFUSE && PB_CLOSURES_SHEEN == PB_BLENDER_CL_SHEEN &&
                   PB_CLOSURES_SPECULAR == PB_BLENDER_CL_SPECULAR &&
                   PB_CLOSURES_GLASS_REFL == PB_BLENDER_CL_REFLECTION &&
                   PB_CLOSURES_GLASS_REFR == PB_BLENDER_CL_REFRACTION && PB_CLOSURES_CLEARCOAT == PB_BLENDER_CL_COAT &&
                   PB_CLOSURES_MULTI_WALK == PB_BLENDER_CL_MULTI_WALK && PB_CLOSURES_V1 == PB_BLENDER_CL_V1 &&
                   PB_CLOSURES_MIX == PB_BLENDER_CL_MIX,
               "PB_CLOSURES_* and PB_BLENDER_CL_*");

void pb_render_plan_of(const pb_scene *s, int direct_only, pb_render_plan *out) {
  memset(out, 0, sizeof *out);
  uint32_t f = s->features;
  out->eye_chains = (f & PB_FEATURE_SPECULAR) != 0;
  out->emitter_sampling = (f & PB_FEATURE_EMISSIVE) != 0;
  out->unlit = (f & PB_FEATURE_UNLIT) != 0;
  out->vertex_colors = s->colors != NULL;
  out->media = (f & PB_FEATURE_VOLUME) != 0 && (f & PB_FEATURE_TRANSMISSION) != 0;
  out->textures = (f & PB_FEATURE_TEXTURES) != 0;
  out->vertex_normals = s->normals != NULL;
  out->photons = !direct_only && (s->light_count > 0 || s->world.present || (f & PB_FEATURE_EMISSIVE) != 0);
  out->caustic_photons = out->photons && (f & PB_FEATURE_SPECULAR) != 0;
  out->refraction = out->caustic_photons && (f & PB_FEATURE_TRANSMISSION) != 0;
  out->normal_maps = (f & PB_FEATURE_NORMAL_MAPS) != 0 && s->tangents != NULL && s->uvs != NULL;
  out->blender_materials = (f & PB_FEATURE_BLENDER) != 0;
  out->multi_ggx = (f & PB_FEATURE_MULTI_GGX) != 0;
  /* Only the Blender models render Alpha (Cycles' transparency); glTF's
   * alpha modes are not rendered by either renderer. */
  out->alpha = (f & PB_FEATURE_ALPHA) != 0 && out->blender_materials;
  for (uint32_t i = 0; i < s->material_count && out->blender_materials; ++i) {
    out->principled2 |= s->materials[i].blender.model == PB_MODEL_PRINCIPLED && s->materials[i].blender.principled_v2;
    out->closures |= pb_blender_closures(&s->materials[i]);
  }
  out->soft_lights = (f & PB_FEATURE_SOFT_LIGHTS) != 0;
  out->world = s->world.present;
  out->world_map = s->world.present && s->world.env != NULL;
}

void pb_render_plan_json(struct pb_json *j, const char *key, const pb_render_plan *p) {
  pb_json_begin_object(j, key);
  pb_json_bool(j, "photons", p->photons);
  pb_json_bool(j, "caustic_photons", p->caustic_photons);
  pb_json_bool(j, "photon_refraction", p->refraction);
  pb_json_bool(j, "specular_eye_paths", p->eye_chains);
  pb_json_bool(j, "emitter_sampling", p->emitter_sampling);
  pb_json_bool(j, "unlit", p->unlit);
  pb_json_bool(j, "vertex_colors", p->vertex_colors);
  pb_json_bool(j, "absorbing_media", p->media);
  pb_json_bool(j, "textures", p->textures);
  pb_json_bool(j, "normal_maps", p->normal_maps);
  pb_json_bool(j, "blender_materials", p->blender_materials);
  pb_json_bool(j, "multiscatter_ggx", p->multi_ggx);
  pb_json_begin_array(j, "blender_closures");
  for (unsigned k = 0; k < PB_BLENDER_CL_BITS; ++k)
    if (p->closures >> k & 1u) pb_json_string(j, NULL, pb_blender_closure_names[k]);
  pb_json_end_array(j);
  pb_json_bool(j, "transparent_shadows", p->alpha);
  pb_json_bool(j, "shading_normal_correction", p->normal_maps && p->photons);
  pb_json_bool(j, "soft_lights", p->soft_lights);
  pb_json_bool(j, "world_light", p->world);
  pb_json_bool(j, "world_map", p->world_map);
  pb_json_end_object(j);
}
