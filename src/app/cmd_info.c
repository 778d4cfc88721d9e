/* photonbridge info SCENE: what the loader made of a scene, in the units the
 * renderers use. Human-readable on stdout; --json for tools. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "color/color.h"
#include "app/color_opts.h"
#include "core/json.h"
#include "render/estimate/estimator.h"
#include "render/scene/scene_plan.h"
#include "render/photon/tracer.h"
#include "scene/camera.h"

/* A Blender material's microfacet distribution: as info prints it, and as
 * the extension spells it. */
static const char *distribution_label(pb_distribution d) {
  return d == PB_DISTRIBUTION_MULTI_GGX ? "Multiscatter GGX" : d == PB_DISTRIBUTION_BECKMANN ? "Beckmann" : "GGX";
}
static const char *distribution_name(pb_distribution d) {
  return d == PB_DISTRIBUTION_MULTI_GGX ? "MULTI_GGX" : d == PB_DISTRIBUTION_BECKMANN ? "BECKMANN" : "GGX";
}

static const char *const bsdf_names[] = {"diffuse", "glossy", "mirror", "glass"};

/* The view PNG previews of this scene go through by default (`render --png`
 * and `reference --png`: the scene's own colour management where it has
 * one, else the config's default, which `display` and `validate`'s pictures
 * use): one line, or why there is none. */
static void default_view(const pb_scene *s, char *buf, size_t size) {
  pb_color *c = NULL;
  const pb_color_opts co = PB_COLOR_OPTS_INIT;
  if (pb_color_opts_open_scene(&co, s, &c) == PB_OK) {
    pb_color_describe(c, buf, size);
  } else {
    snprintf(buf, size, "unavailable: %s", pb_error_message());
    pb_error_clear();
  }
  pb_color_destroy(c);
}
static const char *const camera_fit_names[] = {"vertical", "horizontal", "larger"};
static const char *const camera_panorama_names[] = {"none", "equirectangular", "fisheye equidistant",
                                                   "fisheye equisolid", "mirror ball"};

static void print_text(const pb_scene *s) {
  printf("scene      %s\n", s->path);
  printf("generator  %s\n", s->generator[0] ? s->generator : "(none)");
  printf("triangles  %u\nvertices   %u\n", s->triangle_count, s->vertex_count);
  printf("bounds     [%.4g %.4g %.4g] .. [%.4g %.4g %.4g]\n", s->bounds_min[0], s->bounds_min[1], s->bounds_min[2],
         s->bounds_max[0], s->bounds_max[1], s->bounds_max[2]);
  if (s->origin[0] != 0 || s->origin[1] != 0 || s->origin[2] != 0)
    printf("origin     (%.17g %.17g %.17g): far from the world origin, so positions here are relative to it\n",
           s->origin[0], s->origin[1], s->origin[2]);
  printf("cameras    %u\n", s->camera_count);
  for (uint32_t i = 0; i < s->camera_count; ++i) {
    const pb_camera *c = &s->cameras[i];
    uint32_t w, h;
    pb_camera_image_size(c, 0, 0, &w, &h);
    printf("  %-3u %-20s at (%.4g %.4g %.4g) looking (%.3f %.3f %.3f), ", i, c->name, c->position[0],
           c->position[1], c->position[2], c->forward[0], c->forward[1], c->forward[2]);
    if (c->orthographic) printf("orthographic %.4g m", c->ortho_size);
    else printf("%s %.2f deg", c->fit == PB_CAMERA_FIT_VERTICAL ? "yfov" : "fov", c->yfov * 180.0 / M_PI);
    if (c->fit != PB_CAMERA_FIT_VERTICAL) printf(" (%s side)", camera_fit_names[c->fit]);
    if (c->shift[0] != 0 || c->shift[1] != 0) printf(", shift (%.4g %.4g)", c->shift[0], c->shift[1]);
    if (c->panorama) printf(", panoramic %s", camera_panorama_names[c->panorama]);
    if (c->aperture_radius > 0)
      printf(", depth of field (aperture radius %.4g m, focus %.4g m, %s)", c->aperture_radius, c->focus_distance,
             c->aperture_blades >= 3 ? "blades" : "round");
    printf(", aspect %.4g (%ux%u by default%s), clip %.4g..%.4g m%s\n", (double)w / h, w, h,
           c->aspect > 0 ? "" : "; the file gives no aspect ratio", c->znear, c->zfar,
           c->synthesized ? " (default framing, not in the file)" : "");
  }
  /* Each light first in the units the artist typed (Blender's watts for a
   * scene the add-on wrote, glTF's candela or lux otherwise), then the
   * radiometric value photonbridge renders with. */
  printf("lights     %u  (as typed in Blender or glTF, then as rendered: point/spot in W/sr, directional in W/m^2, "
         "area in W/(m^2 sr))\n",
         s->light_count);
  for (uint32_t i = 0; i < s->light_count; ++i) {
    const pb_light *l = &s->lights[i];
    printf("  %-20s %-11s ", l->name, pb_light_kind_name(l->type));
    pb_light_describe(l, s->light_units == PB_LIGHT_UNITS_UNITLESS, stdout);
    printf("\n");
  }
  const pb_world *w = &s->world;
  if (w->present) {
    if (w->env)
      printf("world      map '%s' %ux%u x %.4g, %.4g W/m^2 over the sphere%s\n", w->env_name, w->env_width,
             w->env_height, w->env_scale, (w->integral[0] + w->integral[1] + w->integral[2]) / 3,
             w->hidden_from_camera ? ", hidden from the camera" : "");
    else
      printf("world      L = (%.4g %.4g %.4g) W/(m^2 sr)%s\n", w->color[0], w->color[1], w->color[2],
             w->hidden_from_camera ? ", hidden from the camera" : "");
  } else {
    printf("world      none (black)\n");
  }
  printf("film       %s\n", s->film_opaque ? "opaque (alpha 1)" : "transparent (alpha = coverage)");
  printf("materials  %u\n", s->material_count);
  for (uint32_t i = 0; i < s->material_count; ++i) {
    const pb_material *m = &s->materials[i];
    printf("  %-20s %-7s base (%.3g %.3g %.3g)%s metallic %.3g roughness %.3g", m->name, bsdf_names[pb_material_kind(m)],
           m->base_color[0], m->base_color[1], m->base_color[2], m->base_color_tex >= 0 ? " x texture" : "", m->metallic,
           m->roughness);
    if (m->transmission > 0) printf(" transmission %.3g ior %.3g", m->transmission, m->ior);
    if (pb_material_is_emissive(m)) printf(" emissive (%.3g %.3g %.3g)", m->emissive[0], m->emissive[1], m->emissive[2]);
    if (m->unlit) printf(" unlit (its colour on camera paths, lights nothing)");
    if (m->attenuation[0] > 0 || m->attenuation[1] > 0 || m->attenuation[2] > 0)
      printf(" absorbing medium (%.3g %.3g %.3g)/m", m->attenuation[0], m->attenuation[1], m->attenuation[2]);
    const pb_blender_material *b = &m->blender;
    if (b->node == PB_NODE_METALLIC && b->conductor)
      printf(" [Blender metallic (Metallic BSDF), physical conductor, %s: n (%.3g %.3g %.3g), k (%.3g %.3g %.3g), "
             "anisotropy %.3g]", distribution_label(b->distribution),
             b->input[PB_IN_CONDUCTOR_N_R], b->input[PB_IN_CONDUCTOR_N_G], b->input[PB_IN_CONDUCTOR_N_B],
             b->specular_tint[0], b->specular_tint[1], b->specular_tint[2], b->input[PB_IN_ANISOTROPIC]);
    else if (b->node == PB_NODE_METALLIC)
      printf(" [Blender metallic (Metallic BSDF), F82, %s: edge tint (%.3g %.3g %.3g), anisotropy %.3g]",
             distribution_label(b->distribution), b->specular_tint[0],
             b->specular_tint[1], b->specular_tint[2], b->input[PB_IN_ANISOTROPIC]);
    else if (b->node == PB_NODE_VELVET)
      printf(" [Blender sheen (Sheen BSDF), Ashikhmin: colour (%.3g %.3g %.3g), roughness %.3g]", m->base_color[0],
             m->base_color[1], m->base_color[2], b->input[PB_IN_ROUGHNESS]);
    else if (b->node == PB_NODE_SHEEN)
      printf(" [Blender sheen (Sheen BSDF), Microfiber: colour (%.3g %.3g %.3g), roughness %.3g]", b->sheen_tint[0],
             b->sheen_tint[1], b->sheen_tint[2], b->input[PB_IN_SHEEN_ROUGHNESS]);
    else if (b->node == PB_NODE_GLOSSY)
      printf(" [Blender glossy (Glossy BSDF), %s: roughness %.3g, anisotropy %.3g, rotation %.3g]",
             distribution_label(b->distribution), b->input[PB_IN_ROUGHNESS],
             b->input[PB_IN_ANISOTROPIC], b->input[PB_IN_ANISOTROPIC_ROTATION]);
    else if (b->node == PB_NODE_GLASS || b->node == PB_NODE_REFRACTION)
      printf(" [Blender %s (%s BSDF), %s: roughness %.3g, IOR %.3g]", pb_blender_model_name(b),
             b->node == PB_NODE_GLASS ? "Glass" : "Refraction",
             distribution_label(b->distribution), b->input[PB_IN_ROUGHNESS],
             b->input[PB_IN_IOR]);
    else if (b->model == PB_MODEL_PRINCIPLED && b->principled_v2)
      printf(" [Blender principled v2, %s: specular IOR level %.3g, coat %.3g (roughness %.3g, IOR %.3g), sheen %.3g "
             "(roughness %.3g), anisotropic %.3g, alpha %.3g%s]",
             distribution_label(b->distribution), b->input[PB_IN_SPECULAR_IOR_LEVEL],
             b->input[PB_IN_COAT_WEIGHT], b->input[PB_IN_COAT_ROUGHNESS], b->input[PB_IN_COAT_IOR],
             b->input[PB_IN_SHEEN_WEIGHT], b->input[PB_IN_SHEEN_ROUGHNESS], b->input[PB_IN_ANISOTROPIC],
             b->input[PB_IN_ALPHA], b->input[PB_IN_SUBSURFACE] > 0 ? ", subsurface as diffuse" : "");
    else if (b->model == PB_MODEL_PRINCIPLED)
      printf(" [Blender principled, %s: specular %.3g tint %.3g, sheen %.3g, clearcoat %.3g (roughness %.3g), "
             "anisotropic %.3g, alpha %.3g%s]", distribution_label(b->distribution),
             b->input[PB_IN_SPECULAR], b->input[PB_IN_SPECULAR_TINT], b->input[PB_IN_SHEEN], b->input[PB_IN_CLEARCOAT],
             b->input[PB_IN_CLEARCOAT_ROUGHNESS], b->input[PB_IN_ANISOTROPIC], b->input[PB_IN_ALPHA],
             b->input[PB_IN_SUBSURFACE] > 0 ? ", subsurface as diffuse" : "");
    else if (b->model != PB_MODEL_GLTF)
      printf(" [Blender %s]", pb_material_model_name(b->model));
    if (b->model != PB_MODEL_GLTF && b->mix_with && b->mix_with <= s->material_count) {
      static const char *const facs[] = {"Fac %.3g", "Fresnel (IOR %.3g)", "Layer Weight Fresnel (Blend %.3g)",
                                         "Layer Weight Facing (Blend %.3g)", "1 (Add Shader)"};
      printf(" [%s with '%s', its weight ", b->mix_fac == PB_MIX_FAC_ADD ? "Add Shader" : "Mix Shader",
             s->materials[b->mix_with - 1].name);
      if (b->input_tex[PB_IN_MIX_FAC].tex >= 0) printf("a texture's");
      else printf(facs[b->mix_fac <= PB_MIX_FAC_ADD ? b->mix_fac : 0], b->input[PB_IN_MIX_FAC]);
      printf("]");
    }
    printf("\n");
  }
  printf("textures   %u\n", s->texture_count);
  for (uint32_t i = 0; i < s->texture_count; ++i) {
    const pb_texture *t = &s->textures[i];
    printf("  %-20s %ux%u %s%s", t->name, t->width, t->height, t->srgb ? "sRGB" : "linear",
           t->rgbah ? ", half float" : "");
    if (t->texcoord) printf(", TEXCOORD_%d", t->texcoord);
    if (t->uv_transformed)
      printf(", KHR_texture_transform u' = %.3g u %+.3g v %+.3g, v' = %.3g u %+.3g v %+.3g", t->uv_xform[0], t->uv_xform[1],
             t->uv_xform[2], t->uv_xform[3], t->uv_xform[4], t->uv_xform[5]);
    printf("\n");
  }
  printf("animations %u (%u channels)", s->animation_count, s->animation_channel_count);
  if (s->anim)
    printf(", %.4g to %.4g s (render --frames %d:%d at 24 fps)", s->anim_start, s->anim_end,
           (int)ceil(s->anim_start * 24.0 - 1e-6), (int)floor(s->anim_end * 24.0 + 1e-6));
  printf("\n");
  if (s->skinned_vertex_count || s->morphed_vertex_count)
    printf("deform     skinned vertices %u, morphed vertices %u; %u of them posed again per frame%s\n",
           s->skinned_vertex_count, s->morphed_vertex_count, s->posed_vertex_count,
           s->posed_vertex_count ? " (CPU, pb_scene_set_time)" : " (static: posed once when loaded)");
  printf("features  ");
  if (!s->features) printf(" none (diffuse only)");
  for (uint32_t b = 1; b; b <<= 1)
    if (s->features & b) printf(" [%s]", pb_feature_name(b));
  pb_render_plan pl;
  pb_render_plan_of(s, 0, &pl);
  printf("\npipeline   photon stages %s, caustic photons %s, photon refraction %s, specular eye paths %s, "
         "emissive-triangle sampling %s, textures %s, normal maps %s, unlit %s, vertex colours %s, absorbing media %s, "
         "soft lights %s, world light %s, Blender materials %s, transparent shadows %s (GPU passes compile only what "
         "is on)",
         pl.photons ? "on" : "off (no light, no emissive triangle, no world)",
         pl.caustic_photons ? "on" : "off", pl.refraction ? "on" : "off", pl.eye_chains ? "on" : "off",
         pl.emitter_sampling ? "on" : "off", pl.textures ? "on" : "off",
         pl.normal_maps ? (pl.photons ? "on (+ its correction of the indirect light)" : "on") : "off", pl.unlit ? "on" : "off",
         pl.vertex_colors ? "on" : "off", pl.media ? "on" : "off", pl.soft_lights ? "on" : "off",
         pl.world ? (pl.world_map ? "on (map, importance-sampled)" : "on (constant)") : "off",
         pl.blender_materials ? "on (glossy eye paths)" : "off", pl.alpha ? "on" : "off");
  if (pl.blender_materials) {
    printf("\nclosures  ");
    for (unsigned k = 0; k < PB_BLENDER_CL_BITS; ++k)
      if (pl.closures >> k & 1u) printf(" %s", pb_blender_closure_names[k]);
    printf(" (the Blender materials' closures the GPU passes compile)");
  }
  /* The density estimators (render --estimator; render/estimate/estimator.h): what
   * auto picks for this scene and why, and which are in this binary. */
  pb_estimator_desc ad = {.kind = PB_ESTIMATOR_AUTO};
  printf("\nestimator  auto -> %s (%s); built:", pb_estimator_names[pb_estimator_resolve(s, &ad)],
         pb_estimator_auto_rule);
  for (uint32_t k = 0; k < PB_ESTIMATOR_AUTO; ++k)
    printf(" %s%s", pb_estimator_names[k], pb_estimator_built(k) ? "" : " (not built)");
  /* The photon tracers render --tracer (and view, serve) choose from
   * (render/photon/tracer.h); every one works on every scene. */
  printf("\ntracers   ");
  for (uint32_t k = 0; pb_tracer_names[k]; ++k)
    printf("%s %s%s", k ? "," : "", pb_tracer_names[k],
           k == PB_TRACER_BVH ? " (default: exact hits in the scene BVH)"
                              : " (--image-maps 1..15 cube environment maps, no hierarchy, approximate: "
                                "misses counted)");
  char view[768];
  default_view(s, view, sizeof view);
  printf("\ndisplay    %s (PNG previews; EXR stays scene-linear Rec.709)", view);
  printf("\nwarnings   %u\n", s->warning_count);
  for (uint32_t i = 0; i < s->warning_count; ++i) printf("  %s\n", s->warnings[i]);
}

static void vec3(pb_json *j, const char *key, const float *v) {
  pb_json_begin_array(j, key);
  for (int k = 0; k < 3; ++k) pb_json_number(j, NULL, v[k]);
  pb_json_end_array(j);
}

static pb_result write_json(const pb_scene *s, const char *path) {
  pb_json j;
  char *tmp;
  pb_result r = pb_json_open(&j, path, &tmp);
  if (r != PB_OK) return r;
  pb_json_begin_object(&j, NULL);
  pb_json_string(&j, "scene", s->path);
  pb_json_string(&j, "generator", s->generator);
  pb_json_int(&j, "triangles", s->triangle_count);
  pb_json_int(&j, "vertices", s->vertex_count);
  vec3(&j, "bounds_min", s->bounds_min);
  vec3(&j, "bounds_max", s->bounds_max);
  pb_json_begin_array(&j, "origin"); /* world position of the scene's (0,0,0); see scene.h */
  for (int k = 0; k < 3; ++k) pb_json_number(&j, NULL, s->origin[k]);
  pb_json_end_array(&j);
  pb_json_begin_array(&j, "cameras");
  for (uint32_t i = 0; i < s->camera_count; ++i) {
    const pb_camera *c = &s->cameras[i];
    uint32_t w, h;
    pb_camera_image_size(c, 0, 0, &w, &h);
    pb_json_begin_object(&j, NULL);
    pb_json_int(&j, "index", i); /* what --camera N selects */
    pb_json_string(&j, "name", c->name);
    vec3(&j, "position", c->position);
    vec3(&j, "forward", c->forward);
    vec3(&j, "up", c->up);
    pb_json_string(&j, "projection", c->orthographic ? "orthographic" : "perspective");
    pb_json_string(&j, "fit", camera_fit_names[c->fit]);
    pb_json_number(&j, "yfov", c->yfov);
    pb_json_number(&j, "ortho_size", c->ortho_size);
    pb_json_string(&j, "panorama", camera_panorama_names[c->panorama]);
    pb_json_number(&j, "aperture_radius", c->aperture_radius); /* m; 0: no depth of field */
    pb_json_number(&j, "focus_distance", c->focus_distance);
    pb_json_int(&j, "aperture_blades", c->aperture_blades);
    pb_json_begin_array(&j, "shift");
    for (int k = 0; k < 2; ++k) pb_json_number(&j, NULL, c->shift[k]);
    pb_json_end_array(&j);
    pb_json_number(&j, "aspect", c->aspect); /* the file's aspect ratio (or the writer's), 0: none */
    pb_json_number(&j, "default_aspect", (double)w / h); /* of the default image size (what render uses) */
    pb_json_int(&j, "default_width", w);
    pb_json_int(&j, "default_height", h);
    pb_json_number(&j, "znear", c->znear);
    pb_json_number(&j, "zfar", c->zfar);
    /* The view window at the camera's own aspect (4:3 without one), however
     * the file described it (scene/camera.h): width, height (at distance 1,
     * or metres when orthographic) and the centre's offset. */
    double a = c->aspect > 0 ? c->aspect : 4.0 / 3.0, win[4];
    uint32_t wh = 100000, ww = (uint32_t)fmin(4e9, fmax(1.0, round(a * wh)));
    pb_camera_window(c, ww, wh, &win[0], &win[1], &win[2], &win[3]);
    pb_json_begin_array(&j, "window");
    for (int k = 0; k < 4; ++k) pb_json_number(&j, NULL, win[k]);
    pb_json_end_array(&j);
    pb_json_bool(&j, "synthesized", c->synthesized);
    pb_json_end_object(&j);
  }
  pb_json_end_array(&j);
  pb_json_string(&j, "light_units", pb_light_units_names[s->light_units]);
  pb_json_begin_array(&j, "lights");
  for (uint32_t i = 0; i < s->light_count; ++i) {
    const pb_light *l = &s->lights[i];
    pb_json_begin_object(&j, NULL);
    pb_light_write_json(l, &j);
    pb_json_end_object(&j);
  }
  pb_json_end_array(&j);
  pb_json_begin_object(&j, "world");
  pb_json_bool(&j, "present", s->world.present);
  if (s->world.present) {
    vec3(&j, "color", s->world.color);
    if (s->world.env) {
      pb_json_string(&j, "map", s->world.env_name);
      pb_json_int(&j, "map_width", s->world.env_width);
      pb_json_int(&j, "map_height", s->world.env_height);
      pb_json_number(&j, "map_scale", s->world.env_scale);
    }
    vec3(&j, "radiance_integral_w_m2", s->world.integral);
    pb_json_bool(&j, "visible_to_camera", !s->world.hidden_from_camera);
  }
  pb_json_end_object(&j);
  pb_json_bool(&j, "film_opaque", s->film_opaque);
  pb_json_begin_array(&j, "materials");
  for (uint32_t i = 0; i < s->material_count; ++i) {
    const pb_material *m = &s->materials[i];
    pb_json_begin_object(&j, NULL);
    pb_json_string(&j, "name", m->name);
    pb_json_string(&j, "kind", bsdf_names[pb_material_kind(m)]);
    pb_json_string(&j, "model", pb_blender_model_name(&m->blender));
    if (m->blender.model == PB_MODEL_PRINCIPLED)
      pb_json_string(&j, "distribution", distribution_name(m->blender.distribution));
    pb_json_begin_array(&j, "base_color");
    for (int k = 0; k < 4; ++k) pb_json_number(&j, NULL, m->base_color[k]);
    pb_json_end_array(&j);
    pb_json_int(&j, "base_color_texture", m->base_color_tex);
    pb_json_number(&j, "metallic", m->metallic);
    pb_json_number(&j, "roughness", m->roughness);
    pb_json_number(&j, "specular", m->specular);
    vec3(&j, "specular_color", m->specular_color);
    pb_json_number(&j, "transmission", m->transmission);
    pb_json_number(&j, "ior", m->ior);
    vec3(&j, "emissive", m->emissive);
    pb_json_bool(&j, "double_sided", m->double_sided);
    pb_json_bool(&j, "unlit", m->unlit);
    vec3(&j, "attenuation_per_m", m->attenuation);
    pb_json_end_object(&j);
  }
  pb_json_end_array(&j);
  pb_json_begin_array(&j, "textures");
  for (uint32_t i = 0; i < s->texture_count; ++i) {
    pb_json_begin_object(&j, NULL);
    pb_json_string(&j, "name", s->textures[i].name);
    pb_json_int(&j, "width", s->textures[i].width);
    pb_json_int(&j, "height", s->textures[i].height);
    pb_json_bool(&j, "srgb", s->textures[i].srgb);
    pb_json_int(&j, "texcoord", s->textures[i].texcoord);
    if (s->textures[i].uv_transformed) { /* KHR_texture_transform: u' = m0 u + m1 v + m2, v' = m3 u + m4 v + m5 */
      pb_json_begin_array(&j, "uv_transform");
      for (int k = 0; k < 6; ++k) pb_json_number(&j, NULL, s->textures[i].uv_xform[k]);
      pb_json_end_array(&j);
    }
    pb_json_end_object(&j);
  }
  pb_json_end_array(&j);
  pb_json_int(&j, "animations", s->animation_count);
  if (s->anim) {
    pb_json_number(&j, "animation_start_s", s->anim_start);
    pb_json_number(&j, "animation_end_s", s->anim_end);
  }
  pb_json_begin_object(&j, "deform"); /* skins and morph targets, posed on the CPU */
  pb_json_int(&j, "skinned_vertices", s->skinned_vertex_count);
  pb_json_int(&j, "morphed_vertices", s->morphed_vertex_count);
  pb_json_int(&j, "posed_per_frame", s->posed_vertex_count);
  pb_json_end_object(&j);
  pb_json_begin_array(&j, "features");
  for (uint32_t b = 1; b; b <<= 1)
    if (s->features & b) pb_json_string(&j, NULL, pb_feature_name(b));
  pb_json_end_array(&j);
  pb_render_plan pl;
  pb_render_plan_of(s, 0, &pl);
  pb_render_plan_json(&j, "pipeline", &pl); /* what the GPU passes compile in */
  pb_estimator_desc ad = {.kind = PB_ESTIMATOR_AUTO};
  pb_json_begin_object(&j, "estimator"); /* render --estimator */
  pb_json_string(&j, "auto", pb_estimator_names[pb_estimator_resolve(s, &ad)]);
  pb_json_string(&j, "auto_rule", pb_estimator_auto_rule);
  pb_json_begin_array(&j, "built");
  for (uint32_t k = 0; k < PB_ESTIMATOR_AUTO; ++k)
    if (pb_estimator_built(k)) pb_json_string(&j, NULL, pb_estimator_names[k]);
  pb_json_end_array(&j);
  pb_json_end_object(&j);
  pb_json_begin_array(&j, "tracers"); /* render --tracer's choices, the default first */
  for (uint32_t k = 0; pb_tracer_names[k]; ++k) pb_json_string(&j, NULL, pb_tracer_names[k]);
  pb_json_end_array(&j);
  char view[768];
  default_view(s, view, sizeof view);
  pb_json_string(&j, "display_view", view);
  pb_json_begin_array(&j, "warnings");
  for (uint32_t i = 0; i < s->warning_count; ++i) pb_json_string(&j, NULL, s->warnings[i]);
  pb_json_end_array(&j);
  pb_json_end_object(&j);
  return pb_json_close(&j, path, tmp);
}

int pb_cmd_info(int argc, char **argv) {
  const pb_command *cmd = &pb_commands[1];
  pb_core_opts c = {0};
  int devices = 0;
  const pb_opt opts[] = {PB_SCENE_OPTS(&c),
                         {"devices", 0, PB_OPT_FLAG, &devices, NULL,
                          "list the Vulkan devices (the order --device N counts) instead of a scene", NULL, 0, 0, "Device", 0}};
  const size_t n = sizeof opts / sizeof *opts;
  const char *pos[1];
  size_t npos;
  int help;
  pb_result r = pb_cli_parse(cmd, argc, argv, opts, n, pos, 1, &npos, &help);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  if (help) {
    pb_cli_print_help(stdout, help, cmd, opts, n,
                      "Warnings go to stdout as part of the summary. Exit status 0 when the scene loads.");
    return 0;
  }
  if (devices && npos == 0) return pb_cli_exit(cmd, pb_info_devices(&c));
  if (npos != 1) return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "info: expected one SCENE argument (see 'photonbridge info --help')"));
  pb_load_desc desc;
  pb_core_opts_apply(&c, &desc);
  pb_scene s;
  r = pb_scene_load(pos[0], &desc, &s);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  if (c.json) {
    r = write_json(&s, c.json);
    if (r == PB_OK && strcmp(c.json, "-") == 0) {
      pb_scene_destroy(&s);
      return 0;
    }
  }
  if (r == PB_OK && !c.quiet) print_text(&s);
  pb_scene_destroy(&s);
  return pb_cli_exit(cmd, r);
}
