/* The scene model's own operations (the glTF loader is load.c). */
#include "core/srgb.h"
#include "core/half.h"
#include "scene/scene.h"

#include "scene/anim.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

float pb_blender_input_max(const pb_blender_material *b, pb_blender_input i) {
  return b->input_tex[i].tex >= 0 ? fmaxf(b->input[i], 1.0f) : b->input[i];
}
float pb_blender_input_min(const pb_blender_material *b, pb_blender_input i) {
  return b->input_tex[i].tex >= 0 ? fminf(b->input[i], 0.0f) : b->input[i];
}

int pb_material_has_normal_map(const pb_material *m) {
  return m->normal_tex >= 0 || (m->blender.model != PB_MODEL_GLTF && m->blender.coat_normal_tex >= 0);
}

int pb_material_may_be_singular(const pb_material *m) {
  const pb_blender_material *b = &m->blender;
  if (b->model == PB_MODEL_GLTF) {
    if (m->transmission > 0.0f) return 1;
    int smooth = m->roughness < PB_SPECULAR_ROUGHNESS || m->metallic_roughness_tex >= 0;
    float spec = m->specular * fmaxf(m->specular_color[0], fmaxf(m->specular_color[1], m->specular_color[2]));
    return smooth && (m->metallic > 0.0f || spec > 0.0f);
  }
  if (b->mix_with && b->mix_singular) return 1; /* a Mix Shader's second shader */
  if (b->model != PB_MODEL_PRINCIPLED) return 0;
  /* Cycles' singular test alpha_x alpha_y <= 1e-7 with alpha = r^2 (the
   * anisotropic stretch keeps the product): r <= 1e-7^(1/4). */
  const float r_singular = 0.0178f;
  int rough_low = pb_blender_input_min(b, PB_IN_ROUGHNESS) <= r_singular;
  int layer = pb_blender_input_max(b, PB_IN_SPECULAR) > 0.0f || pb_blender_input_max(b, PB_IN_METALLIC) > 0.0f ||
              pb_blender_input_max(b, PB_IN_TRANSMISSION) > 0.0f;
  int coat = pb_blender_input_max(b, PB_IN_CLEARCOAT) > 0.0f && pb_blender_input_min(b, PB_IN_CLEARCOAT_ROUGHNESS) <= r_singular;
  return (rough_low && layer) || coat;
}

pb_bsdf_kind pb_material_kind(const pb_material *m) {
  const pb_blender_material *b = &m->blender;
  if (b->model == PB_MODEL_PRINCIPLED) {
    int singular = pb_material_may_be_singular(m);
    float metal = b->input[PB_IN_METALLIC], glass = b->input[PB_IN_TRANSMISSION] * (1.0f - metal);
    if (glass > 0.5f) return singular ? PB_BSDF_GLASS : PB_BSDF_GLOSSY;
    if (metal > 0.5f) return singular ? PB_BSDF_MIRROR : PB_BSDF_GLOSSY;
    return b->input[PB_IN_SPECULAR] > 0.0f || b->input[PB_IN_CLEARCOAT] > 0.0f ? PB_BSDF_GLOSSY : PB_BSDF_DIFFUSE;
  }
  if (b->model != PB_MODEL_GLTF) return PB_BSDF_DIFFUSE;
  if (m->transmission > 0.5f)
    return m->roughness < PB_SPECULAR_ROUGHNESS ? PB_BSDF_GLASS : PB_BSDF_GLOSSY;
  if (m->metallic > 0.5f)
    return m->roughness < PB_SPECULAR_ROUGHNESS ? PB_BSDF_MIRROR : PB_BSDF_GLOSSY;
  /* A dielectric: its specular layer, if any, makes it glossy. */
  float spec = m->specular * fmaxf(m->specular_color[0],
                                   fmaxf(m->specular_color[1], m->specular_color[2]));
  return spec > 0.0f ? PB_BSDF_GLOSSY : PB_BSDF_DIFFUSE;
}

int pb_material_is_emissive(const pb_material *m) {
  return m->emissive[0] > 0 || m->emissive[1] > 0 || m->emissive[2] > 0;
}

static const char *const feature_names[] = {
    "specular paths", "transmission", "glossy", "textures",
    "emissive triangles", "animation", "alpha", "normal maps",
    "vertex colours", "skinning", "morph targets", "unlit", "absorbing media",
    "soft lights", "world light", "Blender materials", "multiscatter GGX", "holdout",
    "anisotropy"};

const char *pb_material_model_name(pb_material_model m) {
  switch (m) {
  case PB_MODEL_PRINCIPLED: return "principled";
  case PB_MODEL_DIFFUSE: return "diffuse";
  case PB_MODEL_EMISSION: return "emission";
  case PB_MODEL_HOLDOUT: return "holdout";
  default: return "gltf";
  }
}

const char *pb_blender_model_name(const pb_blender_material *b) {
  if (b->node == PB_NODE_METALLIC) return "metallic";
  if (b->node == PB_NODE_SHEEN || b->node == PB_NODE_VELVET) return "sheen";
  if (b->node == PB_NODE_GLOSSY) return "glossy";
  if (b->node == PB_NODE_GLASS) return "glass";
  if (b->node == PB_NODE_REFRACTION) return "refraction";
  if (b->model == PB_MODEL_PRINCIPLED && b->principled_v2) return "principled2";
  return pb_material_model_name(b->model);
}

/* What the GPU's set-up makes (common/principled.glsl pb_blender_setup,
 * pb2_setup, pb2_node) and the reference's (ref/principled.c): a kind
 * wherever its weight could pass the cutoff somewhere, so that no closure
 * the shader would make is compiled out and two mixed shaders that could
 * both make one kind are told apart. */
const char *const pb_blender_closure_names[PB_BLENDER_CL_BITS] = {
    "diffuse", "sheen", "specular", "reflection", "refraction", "coat", "multiscatter_walk", "principled_v1", "mix"};

uint32_t pb_blender_closures(const pb_material *m) {
  const pb_blender_material *b = &m->blender;
  uint32_t mix = b->mix_with ? PB_BLENDER_CL_MIX : 0;
  switch (b->model) {
  case PB_MODEL_DIFFUSE: return PB_BLENDER_CL_DIFFUSE | mix;
  case PB_MODEL_PRINCIPLED: break;
  default: return 0; /* glTF's model (its own code), Emission, Holdout */
  }
  uint32_t c = 0;
  if (!b->principled_v2) {
    c = PB_BLENDER_CL_V1 | PB_BLENDER_CL_DIFFUSE | PB_BLENDER_CL_SPECULAR;
    if (pb_blender_input_max(b, PB_IN_SHEEN) > 0) c |= PB_BLENDER_CL_SHEEN;
    if (pb_blender_input_max(b, PB_IN_TRANSMISSION) > 0) c |= PB_BLENDER_CL_REFLECTION | PB_BLENDER_CL_REFRACTION;
    if (pb_blender_input_max(b, PB_IN_CLEARCOAT) > 0) c |= PB_BLENDER_CL_COAT;
    if (b->distribution == PB_DISTRIBUTION_MULTI_GGX) c |= PB_BLENDER_CL_MULTI_WALK;
    return c | mix;
  }
  switch (b->node) {
  case PB_NODE_GLOSSY: return PB_BLENDER_CL_REFLECTION | mix;
  /* Blender 3.x's Glass (separable G: Cycles 3.4's two closures) */
  case PB_NODE_GLASS: return (b->g2_correlated ? 0 : PB_BLENDER_CL_REFLECTION) | PB_BLENDER_CL_REFRACTION | mix;
  case PB_NODE_REFRACTION: return PB_BLENDER_CL_REFRACTION | mix;
  case PB_NODE_VELVET: return PB_BLENDER_CL_SHEEN | mix;
  /* the v2 metal alone (Metallic 1: no layer under it) */
  case PB_NODE_METALLIC: return PB_BLENDER_CL_REFLECTION | mix;
  /* the v2 sheen alone (black base, Specular IOR Level 0) */
  case PB_NODE_SHEEN: return PB_BLENDER_CL_SHEEN | mix;
  default: break; /* the Principled BSDF */
  }
  c = PB_BLENDER_CL_DIFFUSE | PB_BLENDER_CL_SPECULAR;
  if (pb_blender_input_max(b, PB_IN_SHEEN_WEIGHT) > 0) c |= PB_BLENDER_CL_SHEEN;
  if (pb_blender_input_max(b, PB_IN_COAT_WEIGHT) > 0) c |= PB_BLENDER_CL_COAT;
  if (pb_blender_input_max(b, PB_IN_METALLIC) > 0) c |= PB_BLENDER_CL_REFLECTION;
  if (pb_blender_input_max(b, PB_IN_TRANSMISSION) > 0) c |= PB_BLENDER_CL_REFRACTION;
  return c | mix;
}

const char *pb_feature_name(uint32_t bit) {
  for (unsigned i = 0; i < sizeof feature_names / sizeof *feature_names; ++i)
    if (bit == (1u << i)) return feature_names[i];
  return "unknown";
}

pb_result pb_scene_warn(pb_scene *s, const char *fmt, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  char **w = realloc(s->warnings, (s->warning_count + 1) * sizeof *w);
  if (!w) return PB_ERR_NOMEM;
  s->warnings = w;
  if (!(w[s->warning_count] = strdup(buf))) return PB_ERR_NOMEM;
  s->warning_count++;
  return PB_OK;
}

void pb_scene_update_bounds(pb_scene *s) {
  for (int k = 0; k < 3; ++k) {
    s->bounds_min[k] = INFINITY;
    s->bounds_max[k] = -INFINITY;
  }
  /* Bounds of referenced vertices only. */
  for (uint32_t t = 0; t < s->triangle_count; ++t)
    for (int v = 0; v < 3; ++v) {
      const float *p = s->positions[s->triangles[t][v]];
      for (int k = 0; k < 3; ++k) {
        s->bounds_min[k] = fminf(s->bounds_min[k], p[k]);
        s->bounds_max[k] = fmaxf(s->bounds_max[k], p[k]);
      }
    }
  if (s->triangle_count == 0)
    for (int k = 0; k < 3; ++k) s->bounds_min[k] = s->bounds_max[k] = 0;
}

void pb_scene_finalize(pb_scene *s) {
  pb_scene_update_bounds(s);

  uint32_t f = 0;
  uint8_t *used = calloc(s->material_count ? s->material_count : 1, 1);
  for (uint32_t t = 0; t < s->triangle_count && used; ++t)
    used[s->triangle_material[t]] = 1;
  /* a Mix Shader's second shader is used where its first is */
  for (uint32_t i = 0; i < s->material_count && used; ++i) {
    uint32_t w = s->materials[i].blender.mix_with;
    if (used[i] && s->materials[i].blender.model != PB_MODEL_GLTF && w > 0 && w <= s->material_count) used[w - 1] = 1;
  }
  for (uint32_t i = 0; i < s->material_count; ++i) {
    if (used && !used[i]) continue;
    const pb_material *m = &s->materials[i];
    const pb_blender_material *b = &m->blender;
    pb_bsdf_kind k = pb_material_kind(m);
    if (b->model == PB_MODEL_GLTF) {
      if (k == PB_BSDF_MIRROR || k == PB_BSDF_GLASS) f |= PB_FEATURE_SPECULAR;
      if (m->transmission > 0) f |= PB_FEATURE_TRANSMISSION;
      if (k == PB_BSDF_GLOSSY) f |= PB_FEATURE_GLOSSY;
      if (m->alpha_mode != PB_ALPHA_OPAQUE) f |= PB_FEATURE_ALPHA;
    } else {
      f |= PB_FEATURE_BLENDER;
      if (b->model == PB_MODEL_HOLDOUT) f |= PB_FEATURE_HOLDOUT;
    }
    if (b->model == PB_MODEL_PRINCIPLED) {
      if (pb_material_may_be_singular(m)) f |= PB_FEATURE_SPECULAR;
      if (pb_blender_input_max(b, PB_IN_TRANSMISSION) > 0.0f && pb_blender_input_min(b, PB_IN_METALLIC) < 1.0f)
        f |= PB_FEATURE_TRANSMISSION;
      if (k == PB_BSDF_GLOSSY || pb_blender_input_max(b, PB_IN_SPECULAR) > 0.0f || pb_blender_input_max(b, PB_IN_METALLIC) > 0.0f ||
          pb_blender_input_max(b, PB_IN_CLEARCOAT) > 0.0f)
        f |= PB_FEATURE_GLOSSY;
      if (b->distribution == PB_DISTRIBUTION_MULTI_GGX) f |= PB_FEATURE_MULTI_GGX;
      /* (the Glossy BSDF's Anisotropy is -1..1) */
      if (pb_blender_input_max(b, PB_IN_ANISOTROPIC) > 0.0f || pb_blender_input_min(b, PB_IN_ANISOTROPIC) < 0.0f)
        f |= PB_FEATURE_ANISOTROPY;
      if (pb_blender_input_min(b, PB_IN_ALPHA) < 1.0f) f |= PB_FEATURE_ALPHA;
      for (int in = 0; in < PB_IN_COUNT; ++in)
        if (b->input_tex[in].tex >= 0) f |= PB_FEATURE_TEXTURES;
      if (b->subsurface_color_tex >= 0) f |= PB_FEATURE_TEXTURES;
    }
    if (b->model == PB_MODEL_DIFFUSE && b->input_tex[PB_IN_ROUGHNESS].tex >= 0) f |= PB_FEATURE_TEXTURES;
    if (m->base_color_tex >= 0 || m->emissive_tex >= 0 ||
        m->metallic_roughness_tex >= 0)
      f |= PB_FEATURE_TEXTURES;
    if (pb_material_has_normal_map(m)) f |= PB_FEATURE_NORMAL_MAPS;
    if (pb_material_is_emissive(m)) f |= PB_FEATURE_EMISSIVE;
    if (m->unlit) f |= PB_FEATURE_UNLIT;
    if (m->attenuation[0] > 0 || m->attenuation[1] > 0 || m->attenuation[2] > 0) f |= PB_FEATURE_VOLUME;
  }
  free(used);
  if (s->anim) f |= PB_FEATURE_ANIMATION;
  if (s->colors) f |= PB_FEATURE_VERTEX_COLORS;
  if (s->skinned_vertex_count) f |= PB_FEATURE_SKINNING;
  if (s->morphed_vertex_count) f |= PB_FEATURE_MORPH_TARGETS;
  for (uint32_t i = 0; i < s->light_count; ++i)
    if (!pb_light_is_delta(&s->lights[i])) f |= PB_FEATURE_SOFT_LIGHTS;
  if (s->world.present) f |= PB_FEATURE_WORLD;
  s->features = f;
}

int pb_scene_find_camera(const pb_scene *s, const char *name) {
  if (s->camera_count == 0) return PB_CAMERA_ABSENT;
  if (!name) return 0;
  size_t digits = strspn(name, "0123456789");
  if (name[0] && !name[digits]) {
    if (digits > 9) return PB_CAMERA_ABSENT; /* beyond any uint32 camera count we hold */
    unsigned long i = strtoul(name, NULL, 10);
    return i < s->camera_count ? (int)i : PB_CAMERA_ABSENT;
  }
  int found = PB_CAMERA_ABSENT;
  for (uint32_t i = 0; i < s->camera_count; ++i)
    if (strcmp(s->cameras[i].name, name) == 0) {
      if (found >= 0) return PB_CAMERA_AMBIGUOUS;
      found = (int)i;
    }
  return found;
}

int pb_camera_clip_sees(const pb_scene *s, const pb_camera *c, float depth[2]) {
  float lo = INFINITY, hi = -INFINITY;
  for (uint32_t i = 0; s->positions && i < s->vertex_count; ++i) {
    const float *p = s->positions[i];
    float d = (p[0] - c->position[0]) * c->forward[0] + (p[1] - c->position[1]) * c->forward[1] +
              (p[2] - c->position[2]) * c->forward[2];
    if (d < lo) lo = d;
    if (d > hi) hi = d;
  }
  if (depth) {
    depth[0] = lo;
    depth[1] = hi;
  }
  if (c->panorama != PB_CAMERA_PANO_NONE || !(lo <= hi)) return 1;
  if (hi < c->znear) return 0;
  if (c->zfar > 0.0f && lo > c->zfar) return 0;
  return 1;
}

void pb_camera_image_size(const pb_camera *c, uint32_t want_w, uint32_t want_h,
                          uint32_t *w, uint32_t *h) {
  float aspect = c && c->aspect > 0 ? c->aspect : 4.0f / 3.0f;
  if (want_w && want_h) {
    *w = want_w;
    *h = want_h;
  } else if (want_w) {
    *w = want_w;
    *h = (uint32_t)fmaxf(1.0f, roundf((float)want_w / aspect));
  } else if (want_h) {
    *h = want_h;
    *w = (uint32_t)fmaxf(1.0f, roundf((float)want_h * aspect));
  } else {
    *w = 640;
    *h = (uint32_t)fmaxf(1.0f, roundf(640.0f / aspect));
  }
}

static int wrap_coord(int i, int n, pb_wrap w) {
  switch (w) {
  case PB_WRAP_CLAMP:
    return i < 0 ? 0 : (i >= n ? n - 1 : i);
  case PB_WRAP_MIRROR: {
    int p = 2 * n;
    int m = ((i % p) + p) % p;
    return m < n ? m : p - 1 - m;
  }
  default:
    return ((i % n) + n) % n;
  }
}

static void texel(const pb_texture *t, int x, int y, float out[4]) {
  if (t->rgbah) {
    const uint16_t *h = t->rgbah + ((size_t)y * t->width + (size_t)x) * 4;
    for (int c = 0; c < 4; ++c) out[c] = pb_half_to_float(h[c]);
    return;
  }
  const uint8_t *p = t->rgba8 + ((size_t)y * t->width + (size_t)x) * 4;
  for (int c = 0; c < 4; ++c) {
    float v = (float)p[c] * (1.0f / 255.0f);
    out[c] = (t->srgb && c < 3) ? pb_srgb_to_linear(v) : v;
  }
}

void pb_texture_mean(const pb_texture *t, float out[4]) {
  double acc[4] = {0, 0, 0, 0};
  for (uint32_t y = 0; y < t->height; ++y)
    for (uint32_t x = 0; x < t->width; ++x) {
      float c[4];
      texel(t, (int)x, (int)y, c);
      for (int k = 0; k < 4; ++k) acc[k] += c[k];
    }
  double n = (double)t->width * t->height;
  for (int k = 0; k < 4; ++k) out[k] = n > 0 ? (float)(acc[k] / n) : 0.0f;
}

void pb_texture_sample(const pb_texture *t, float u, float v, float out[4]) {
  if (!isfinite(u)) u = 0;
  if (!isfinite(v)) v = 0;
  /* Keep coordinates in a range where float->int is defined. */
  u = fmodf(u, 65536.0f);
  v = fmodf(v, 65536.0f);
  int W = (int)t->width, H = (int)t->height;
  float fx = u * (float)W - 0.5f, fy = v * (float)H - 0.5f;
  if (t->nearest) {
    int x = wrap_coord((int)floorf(fx + 0.5f), W, t->wrap_s);
    int y = wrap_coord((int)floorf(fy + 0.5f), H, t->wrap_t);
    texel(t, x, y, out);
    return;
  }
  float x0f = floorf(fx), y0f = floorf(fy);
  float ax = fx - x0f, ay = fy - y0f;
  int x0 = (int)x0f, y0 = (int)y0f;
  int xa = wrap_coord(x0, W, t->wrap_s), xb = wrap_coord(x0 + 1, W, t->wrap_s);
  int ya = wrap_coord(y0, H, t->wrap_t), yb = wrap_coord(y0 + 1, H, t->wrap_t);
  float a[4], b[4], c[4], d[4];
  texel(t, xa, ya, a);
  texel(t, xb, ya, b);
  texel(t, xa, yb, c);
  texel(t, xb, yb, d);
  for (int k = 0; k < 4; ++k)
    out[k] = (a[k] * (1 - ax) + b[k] * ax) * (1 - ay) +
             (c[k] * (1 - ax) + d[k] * ax) * ay;
}

void pb_texture_uv(const pb_texture *t, const float uv0[2], const float uv1[2], float out[2]) {
  static const float zero[2] = {0, 0};
  const float *uv = t->texcoord == 1 ? (uv1 ? uv1 : zero) : uv0;
  if (!t->uv_transformed) {
    out[0] = uv[0], out[1] = uv[1];
    return;
  }
  const float *m = t->uv_xform;
  out[0] = m[0] * uv[0] + m[1] * uv[1] + m[2];
  out[1] = m[3] * uv[0] + m[4] * uv[1] + m[5];
}

void pb_texture_lookup(const pb_texture *t, const float uv0[2], const float uv1[2], float out[4]) {
  float uv[2];
  pb_texture_uv(t, uv0, uv1, uv);
  pb_texture_sample(t, uv[0], uv[1], out);
}

static int has_tex(const pb_scene *s, int32_t t) { return t >= 0 && (uint32_t)t < s->texture_count; }
static float clamp01f(float x) { return x < 0 ? 0 : x > 1 ? 1 : x; }

void pb_material_base_color(const pb_scene *s, const pb_material *m, const float uv0[2], const float uv1[2],
                            const float color[4], float out[4]) {
  float t[4] = {1, 1, 1, 1};
  if (has_tex(s, m->base_color_tex)) pb_texture_lookup(&s->textures[m->base_color_tex], uv0, uv1, t);
  for (int k = 0; k < 4; ++k) out[k] = clamp01f(m->base_color[k] * t[k] * (color ? color[k] : 1.0f));
}

void pb_material_metal_rough(const pb_scene *s, const pb_material *m, const float uv0[2], const float uv1[2],
                             float *metallic, float *roughness) {
  *metallic = m->metallic;
  *roughness = m->roughness;
  if (!has_tex(s, m->metallic_roughness_tex)) return;
  float t[4];
  pb_texture_lookup(&s->textures[m->metallic_roughness_tex], uv0, uv1, t);
  *roughness *= t[1];
  *metallic *= t[2];
}

void pb_material_emission(const pb_scene *s, const pb_material *m, const float uv0[2], const float uv1[2],
                          const float color[4], float out[3]) {
  if (m->unlit) {
    float b[4];
    pb_material_base_color(s, m, uv0, uv1, color, b);
    memcpy(out, b, 3 * sizeof *out);
    return;
  }
  float t[4] = {1, 1, 1, 1};
  if (pb_material_is_emissive(m) && has_tex(s, m->emissive_tex)) pb_texture_lookup(&s->textures[m->emissive_tex], uv0, uv1, t);
  for (int k = 0; k < 3; ++k) out[k] = m->emissive[k] * t[k];
}

void pb_scene_destroy(pb_scene *s) {
  if (!s) return;
  free(s->path);
  free(s->positions);
  free(s->normals);
  free(s->uvs);
  free(s->uvs1);
  free(s->colors);
  free(s->tangents);
  free(s->triangles);
  free(s->triangle_material);
  free(s->materials);
  for (uint32_t i = 0; i < s->texture_count; ++i) free(s->textures[i].rgba8), free(s->textures[i].rgbah);
  free(s->textures);
  free(s->lights);
  free(s->cameras);
  free(s->world.env);
  for (uint32_t i = 0; i < s->warning_count; ++i) free(s->warnings[i]);
  free(s->warnings);
  pb_scene_anim_destroy(s->anim);
  memset(s, 0, sizeof *s);
}
