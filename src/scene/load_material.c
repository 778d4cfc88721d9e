/* glTF materials -> pb_material: factors checked first (check_material),
 * then converted, with KHR_materials_unlit / _volume and the
 * PHOTONBRIDGE_blender material (blender_material.c); glTF's or Blender's
 * default material for primitives without one. Part of the loader
 * (load_internal.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/blender_material.h"
#include "scene/load_internal.h"

static float clamp01(double v) { return (float)(v < 0 ? 0 : (v > 1 ? 1 : v)); }

static pb_result check_factor(loader *L, int i, const char *field, double v, double lo, double hi) {
  if (!isfinite(v) || v < lo || v > hi)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: materials[%d].%s: %g is outside [%g, %g]", L->path, i, field, v, lo, hi);
  return PB_OK;
}

/* The PHOTONBRIDGE_blender material reader's way to textures (glTF
 * textureInfos, through the same load_texture_ref as glTF's own: uv set and
 * KHR_texture_transform included) and warnings (blender_material.h). */
static pb_result blender_texture(void *user, const pb_gltf_texture_ref *ref, int srgb, const char *where, int32_t *out) {
  return load_texture_ref(user, ref, srgb, where, out);
}
static pb_result blender_warn(void *user, const char *line) { return load_warn(user, "%s", line); }
/* A Mix Shader's second shader: after the glTF materials (load.c counted them). */
static pb_result blender_add_material(void *user, const pb_material *m, uint32_t *index) {
  loader *L = user;
  if (L->mix_count >= L->mix_capacity)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: more Mix Shaders than materials with a mix", L->path);
  *index = (uint32_t)L->doc->material_count + L->mix_count++;
  L->s->materials[*index] = *m;
  return PB_OK;
}

/* KHR_materials_unlit and KHR_materials_volume (scene.h, pb_material). */
static pb_result material_extensions(loader *L, int i, const pb_gltf_material *g, pb_material *m) {
  pb_result r = PB_OK;
  if (g->unlit) {
    /* The extension's shading is the base colour alone: every other lobe
     * and the emission are ignored (KHR_materials_unlit, "Overview"). */
    m->unlit = 1;
    m->metallic = 0;
    m->specular = 0;
    m->transmission = 0;
    memset(m->emissive, 0, sizeof m->emissive);
  }
  if (!g->has_volume) return PB_OK;
  const char *vw = "extensions.KHR_materials_volume";
  char w[96];
  snprintf(w, sizeof w, "%s.thicknessFactor", vw);
  if ((r = check_factor(L, i, w, g->thickness, 0, 1e30)) != PB_OK) return r;
  if (g->attenuation_distance != 0 && !(g->attenuation_distance > 0 && isfinite(g->attenuation_distance)))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: materials[%d].%s.attenuationDistance: %g is not positive", L->path, i, vw,
                   g->attenuation_distance);
  for (int k = 0; k < 3 && r == PB_OK; ++k) {
    snprintf(w, sizeof w, "%s.attenuationColor[%d]", vw, k);
    r = check_factor(L, i, w, g->attenuation_color[k], 0, 1);
  }
  if (r != PB_OK) return r;
  /* Thin-walled (thickness 0) and an absent distance (infinite) mean no
   * absorption (KHR_materials_volume). A colour of 0 would absorb
   * everything at once: it is held at 1e-6 (sigma_a d = 13.8 at d = the
   * attenuation distance), so paths stay finite. */
  if (g->thickness > 0 && g->attenuation_distance > 0)
    for (int k = 0; k < 3; ++k)
      m->attenuation[k] = (float)(-log(fmax(g->attenuation_color[k], 1e-6)) / g->attenuation_distance);
  if (m->transmission <= 0 &&
      (m->attenuation[0] > 0 || m->attenuation[1] > 0 || m->attenuation[2] > 0) &&
      (r = load_warn(L, "materials[%d].%s: no transmission, so no light enters the volume", i, vw)) != PB_OK)
    return r;
  return PB_OK;
}

/* materials[i]'s factors and enums, before anything is converted: every
 * factor finite and in its range, the ior 0 or at least 1, a known
 * alphaMode (KHR_materials_volume's are checked with the extension). */
static pb_result check_material(loader *L, int i, const pb_gltf_material *g) {
  pb_result r = PB_OK;
  static const char *const bc[] = {"pbrMetallicRoughness.baseColorFactor[0]", "pbrMetallicRoughness.baseColorFactor[1]",
                                   "pbrMetallicRoughness.baseColorFactor[2]", "pbrMetallicRoughness.baseColorFactor[3]"};
  for (int k = 0; k < 4 && r == PB_OK; ++k) r = check_factor(L, i, bc[k], g->base_color[k], 0, 1);
  if (r == PB_OK) r = check_factor(L, i, "pbrMetallicRoughness.metallicFactor", g->metallic, 0, 1);
  if (r == PB_OK) r = check_factor(L, i, "pbrMetallicRoughness.roughnessFactor", g->roughness, 0, 1);
  if (r == PB_OK) r = check_factor(L, i, "extensions.KHR_materials_transmission.transmissionFactor", g->transmission, 0, 1);
  if (r == PB_OK) r = check_factor(L, i, "extensions.KHR_materials_ior.ior", g->ior, 0, 10);
  if (r == PB_OK) r = check_factor(L, i, "extensions.KHR_materials_specular.specularFactor", g->specular, 0, 1);
  if (r == PB_OK) r = check_factor(L, i, "extensions.KHR_materials_emissive_strength.emissiveStrength", g->emissive_strength, 0, 1e9);
  for (int k = 0; k < 3 && r == PB_OK; ++k) {
    r = check_factor(L, i, "emissiveFactor", g->emissive[k], 0, 1);
    if (r == PB_OK) r = check_factor(L, i, "extensions.KHR_materials_specular.specularColorFactor", g->specular_color[k], 0, 1e3);
  }
  if (r != PB_OK) return r;
  if (g->has_iridescence) {
    /* KHR_materials_iridescence's schema: a factor in [0, 1], an IOR of at
     * least 1, thicknesses (nm) of at least 0; the upper bounds are the
     * Blender model's (blender_material.c thinFilmIor, thinFilmThickness). */
    static const char *const f[4] = {"iridescenceFactor", "iridescenceIor", "iridescenceThicknessMinimum",
                                     "iridescenceThicknessMaximum"};
    const double v[4] = {g->iridescence, g->iridescence_ior, g->iridescence_thickness_min, g->iridescence_thickness_max};
    static const double lo[4] = {0, 1, 0, 0}, hi[4] = {1, 1000, 100000, 100000};
    char w[96];
    for (int k = 0; k < 4 && r == PB_OK; ++k) {
      snprintf(w, sizeof w, "extensions.KHR_materials_iridescence.%s", f[k]);
      if (isnan(v[k]))
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: materials[%d].%s: not a number", L->path, i, w);
      r = check_factor(L, i, w, v[k], lo[k], hi[k]);
    }
    if (r != PB_OK) return r;
  }
  if (g->ior != 0 && g->ior < 1)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: materials[%d].extensions.KHR_materials_ior.ior: %g is below 1", L->path, i, g->ior);
  if (g->alpha_mode[0] && strcmp(g->alpha_mode, "OPAQUE") != 0 && strcmp(g->alpha_mode, "MASK") != 0 &&
      strcmp(g->alpha_mode, "BLEND") != 0)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: materials[%d].alphaMode: '%s' is not OPAQUE, MASK or BLEND", L->path, i, g->alpha_mode);
  return PB_OK;
}

pb_result load_material(loader *L, int i, pb_material *m) {
  const pb_gltf_material *g = &L->doc->materials[i];
  char w[128];
  memset(m, 0, sizeof *m);
  load_copy_name(m->name, g->name, "");
  if (!m->name[0]) snprintf(m->name, PB_NAME_MAX, "materials[%d]", i);
  pb_result r = check_material(L, i, g);
  if (r != PB_OK) return r;
  for (int k = 0; k < 4; ++k) m->base_color[k] = (float)g->base_color[k];
  m->metallic = (float)g->metallic;
  m->roughness = (float)g->roughness;
  m->specular = (float)g->specular;
  /* Blender writes Principled "Specular" 0 as specularColorFactor [0,0,0]
   * with specularFactor 1. Read literally, KHR_materials_specular keeps a
   * grazing reflection (F0 = 0 but F90 = specularFactor = 1), which darkens
   * the diffuse base by up to (1 - cos)^5 at grazing view in an
   * energy-conserving BSDF. The scene model's contract (scene.h) is that such
   * a material is purely diffuse, so a layer with zero F0 is dropped whole. */
  if (g->specular_color[0] <= 0 && g->specular_color[1] <= 0 && g->specular_color[2] <= 0) m->specular = 0;
  for (int k = 0; k < 3; ++k) {
    m->specular_color[k] = (float)g->specular_color[k];
    m->emissive[k] = (float)(g->emissive[k] * g->emissive_strength);
  }
  m->transmission = (float)g->transmission;
  /* ior 0 is the spec's "infinite" (a perfect conductor-like dielectric);
   * treat it as a very high index rather than dividing by zero. */
  m->ior = g->ior == 0 ? 1e3f : (float)g->ior;
  m->normal_scale = (float)g->normal_tex.scale;
  m->double_sided = g->double_sided;
  m->alpha_cutoff = clamp01(g->alpha_cutoff);
  if (strcmp(g->alpha_mode, "MASK") == 0) m->alpha_mode = PB_ALPHA_MASK;
  else if (strcmp(g->alpha_mode, "BLEND") == 0) m->alpha_mode = PB_ALPHA_BLEND;
  else m->alpha_mode = PB_ALPHA_OPAQUE; /* "" or "OPAQUE" (check_material) */

  if ((r = material_extensions(L, i, g, m)) != PB_OK) return r;
  /* The plain glTF model has no thin film; a Blender Principled v2
   * material's Thin Film (PHOTONBRIDGE_blender) is rendered. */
  if (!g->blender && g->has_iridescence && g->iridescence > 0 &&
      (r = load_warn(L, "materials[%d].extensions.KHR_materials_iridescence: iridescenceFactor %g: thin-film "
                        "iridescence is not rendered on a plain glTF material", i, g->iridescence)) != PB_OK)
    return r;
  const pb_gltf_texture_ref *refs[4] = {&g->base_color_tex, &g->metallic_roughness_tex, &g->emissive_tex, &g->normal_tex};
  static const char *const names[4] = {"pbrMetallicRoughness.baseColorTexture", "pbrMetallicRoughness.metallicRoughnessTexture",
                                       "emissiveTexture", "normalTexture"};
  static const int srgb[4] = {1, 0, 1, 0};
  int32_t *dst[4] = {&m->base_color_tex, &m->metallic_roughness_tex, &m->emissive_tex, &m->normal_tex};
  for (int k = 0; k < 4; ++k) {
    snprintf(w, sizeof w, "materials[%d].%s", i, names[k]);
    r = load_texture_ref(L, refs[k], srgb[k], w, dst[k]);
    if (r != PB_OK) return r;
  }
  if (g->blender) {
    pb_blender_material_io io = {L->path, L, blender_texture, blender_warn, L->doc->blender, blender_add_material};
    return pb_blender_material_read(&io, i, g->blender, m);
  }
  return PB_OK;
}

/* Whether asset.generator names Blender's own glTF exporter. */
static int from_blender(const pb_scene *s) { return strncmp(s->generator, "Khronos glTF Blender I/O", 24) == 0; }

/* The material of primitives without one. glTF's default (3.9.1: white,
 * metallic 1, roughness 1), or, in a file Blender wrote, what Cycles 3.4
 * shows for an object without material: its default surface, a Diffuse
 * BSDF of colour 0.8 (intern/cycles/scene/shader.cpp, add_default, used by
 * the Blender sync for empty slots; measured here: a plane under a sun of
 * pi W/m^2 gives 0.8000 with no material and with a Diffuse BSDF 0.8, 0.9036
 * with a new Principled material). Its glTF form: baseColorFactor 0.8,
 * metallicFactor 0, KHR_materials_specular specularFactor 0 (no specular
 * layer: Lambertian). */
int32_t load_default_material(loader *L) {
  if (L->default_material < 0) {
    pb_scene *s = L->s;
    pb_material *m = &s->materials[s->material_count];
    memset(m, 0, sizeof *m);
    m->ior = 1.5f;
    m->roughness = 1;
    m->specular_color[0] = m->specular_color[1] = m->specular_color[2] = 1;
    m->base_color_tex = m->metallic_roughness_tex = m->emissive_tex = m->normal_tex = PB_NO_TEXTURE;
    m->base_color[3] = 1;
    if (from_blender(s)) {
      snprintf(m->name, PB_NAME_MAX, "(Blender default surface)");
      m->base_color[0] = m->base_color[1] = m->base_color[2] = 0.8f;
    } else {
      snprintf(m->name, PB_NAME_MAX, "(glTF default)");
      m->base_color[0] = m->base_color[1] = m->base_color[2] = 1;
      m->metallic = 1;
      m->specular = 1;
    }
    L->default_material = (int32_t)s->material_count++;
  }
  return L->default_material;
}

/* Whether any texture of m (a Blender material's input textures included)
 * reads uv set 1. */
int load_reads_uv1(const pb_scene *s, const pb_material *m) {
  int32_t t[4 + 2 + PB_IN_COUNT] = {m->base_color_tex, m->metallic_roughness_tex, m->emissive_tex, m->normal_tex};
  int n = 4;
  if (m->blender.model != PB_MODEL_GLTF) { /* the zeroed struct holds no texture */
    t[n++] = m->blender.subsurface_color_tex;
    t[n++] = m->blender.coat_normal_tex;
    for (int in = 0; in < PB_IN_COUNT; ++in) t[n++] = m->blender.input_tex[in].tex;
  }
  for (int k = 0; k < n; ++k)
    if (t[k] >= 0 && (uint32_t)t[k] < s->texture_count && s->textures[t[k]].texcoord == 1) return 1;
  return 0;
}
