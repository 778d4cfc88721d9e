/* materials[i].extensions.PHOTONBRIDGE_blender -> pb_material (see
 * blender_material.h and exporters/blender/PHOTONBRIDGE_blender.md).
 *
 * Defaults are Blender 3.4's, measured on this machine's Blender 3.4.1 (a new
 * material's Principled BSDF and fresh Diffuse/Emission nodes): Base Color
 * 0.8, Metallic 0, Specular 0.5, Specular Tint 0, Roughness 0.5,
 * Anisotropic 0, Sheen 0, Sheen Tint 0.5, Clearcoat 0, Clearcoat Roughness
 * 0.03, IOR 1.45, Transmission 0, Transmission Roughness 0, Emission black,
 * Emission Strength 1, Alpha 1, Subsurface 0, distribution GGX (not
 * Multiscatter GGX: bpy reports 'GGX' for both), Diffuse BSDF colour 0.8 and
 * roughness 0, Emission colour 1 and strength 1.
 *
 * Ranges are the sockets' hard ranges as bpy reports them (the 0..1 factors;
 * colours >= 0), except where Blender's range would let light be negative
 * (Emission Strength, an IOR below 0): those are refused. */
#include "scene/blender_material.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#define EXT "extensions.PHOTONBRIDGE_blender"

typedef struct reader {
  const pb_blender_material_io *io;
  int index;
  const char *at; /* "" or "mix.shader." (the second shader of a Mix Shader) */
} reader;

static pb_result bad(const reader *R, const char *member, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static pb_result bad(const reader *R, const char *member, const char *fmt, ...) {
  char why[256];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(why, sizeof why, fmt, ap);
  va_end(ap);
  return pb_fail(PB_ERR_SCENE_INVALID, "%s: materials[%d]." EXT ".%s%s: %s", R->io->path, R->index, R->at, member, why);
}

static pb_result warn(const reader *R, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static pb_result warn(const reader *R, const char *fmt, ...) {
  char line[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  return R->io->warn(R->io->user, line);
}

/* Joins "prefix.key" into buf for messages. */
static const char *member(char *buf, size_t n, const char *prefix, const char *key) {
  if (snprintf(buf, n, "%s%s%s", prefix ? prefix : "", prefix && prefix[0] ? "." : "", key) < 0) buf[0] = '\0';
  return buf; /* a longer name is cut at n - 1 characters: a message, not a key */
}

static pb_result number_in(const reader *R, const char *path, const pb_gltf_value *v, double lo, double hi,
                           float *out) {
  if (v->type != PB_GLTF_NUMBER) return bad(R, path, "%s, expected a number", pb_gltf_value_type_name(v));
  double x = v->number;
  if (isnan(x)) return bad(R, path, "NaN");
  if (!isfinite(x) || fabs(x) > FLT_MAX) return bad(R, path, "%g is not a finite float", x);
  if (x < lo || x > hi) return bad(R, path, "%g is outside [%g, %g]", x, lo, hi);
  *out = (float)x;
  return PB_OK;
}

/* Optional number member: *out keeps its default when absent. */
static pb_result opt_number(const reader *R, const pb_gltf_value *obj, const char *prefix, const char *key, double lo,
                            double hi, float *out) {
  const pb_gltf_value *v = pb_gltf_value_get(obj, key);
  if (!v) return PB_OK;
  char path[128];
  return number_in(R, member(path, sizeof path, prefix, key), v, lo, hi, out);
}

/* Optional colour: an array of 3 (RGB) or 4 (RGBA; alpha ignored, as Cycles
 * ignores a colour socket's alpha) numbers, each >= 0. */
static pb_result opt_color(const reader *R, const pb_gltf_value *obj, const char *prefix, const char *key,
                           float out[3]) {
  const pb_gltf_value *v = pb_gltf_value_get(obj, key);
  if (!v) return PB_OK;
  char path[128], el[160];
  member(path, sizeof path, prefix, key);
  if (v->type != PB_GLTF_ARRAY) return bad(R, path, "%s, expected an array of 3 or 4 numbers", pb_gltf_value_type_name(v));
  if (v->count != 3 && v->count != 4) return bad(R, path, "%zu elements, expected 3 or 4", v->count);
  for (size_t k = 0; k < v->count; ++k) {
    float x = 0;
    snprintf(el, sizeof el, "%s[%zu]", path, k);
    pb_result r = number_in(R, el, &v->items[k], 0.0, FLT_MAX, &x);
    if (r != PB_OK) return r;
    if (k < 3) out[k] = x;
  }
  return PB_OK;
}

/* Optional string member that must be one of names[0..n): *out its index. */
static pb_result opt_enum(const reader *R, const pb_gltf_value *obj, const char *prefix, const char *key,
                          const char *const *names, int n, int *out) {
  const pb_gltf_value *v = pb_gltf_value_get(obj, key);
  if (!v) return PB_OK;
  char path[128], list[256] = "";
  member(path, sizeof path, prefix, key);
  for (int i = 0; i < n; ++i) {
    if (v->type == PB_GLTF_STRING && strcmp(v->string, names[i]) == 0) {
      *out = i;
      return PB_OK;
    }
    size_t l = strlen(list);
    snprintf(list + l, sizeof list - l, "%s%s", i ? (i + 1 == n ? " or " : ", ") : "", names[i]);
  }
  if (v->type != PB_GLTF_STRING) return bad(R, path, "%s, expected a string (%s)", pb_gltf_value_type_name(v), list);
  return bad(R, path, "'%s' is not %s", v->string, list);
}

static pb_result opt_object(const reader *R, const pb_gltf_value *obj, const char *key, const pb_gltf_value **out) {
  const pb_gltf_value *v = pb_gltf_value_get(obj, key);
  *out = v;
  if (v && v->type != PB_GLTF_OBJECT) return bad(R, key, "%s, expected an object", pb_gltf_value_type_name(v));
  return PB_OK;
}

/* ---- texture links ------------------------------------------------------- */

enum { CH_R = 0, CH_G, CH_B, CH_A, CH_RGB };
/* Where a texture entry goes. */
typedef enum target_kind { T_NONE = 0, T_COLOR, T_INPUT, T_NORMAL, T_COAT_NORMAL } target_kind;
typedef struct target {
  const char *name;
  target_kind kind;
  int input;      /* T_INPUT: pb_blender_input; T_COLOR: which colour */
} target;
enum { COLOR_BASE = 0, COLOR_SUBSURFACE, COLOR_EMISSION, COLOR_SPECULAR_TINT, COLOR_COAT_TINT, COLOR_SHEEN_TINT };

static const target principled_targets[] = {
    {"baseColor", T_COLOR, COLOR_BASE},
    {"subsurfaceColor", T_COLOR, COLOR_SUBSURFACE},
    {"emission", T_COLOR, COLOR_EMISSION},
    {"normal", T_NORMAL, 0},
    {"clearcoatNormal", T_COAT_NORMAL, 0},
    {"metallic", T_INPUT, PB_IN_METALLIC},
    {"specular", T_INPUT, PB_IN_SPECULAR},
    {"specularTint", T_INPUT, PB_IN_SPECULAR_TINT},
    {"roughness", T_INPUT, PB_IN_ROUGHNESS},
    {"anisotropic", T_INPUT, PB_IN_ANISOTROPIC},
    {"anisotropicRotation", T_INPUT, PB_IN_ANISOTROPIC_ROTATION},
    {"sheen", T_INPUT, PB_IN_SHEEN},
    {"sheenTint", T_INPUT, PB_IN_SHEEN_TINT},
    {"clearcoat", T_INPUT, PB_IN_CLEARCOAT},
    {"clearcoatRoughness", T_INPUT, PB_IN_CLEARCOAT_ROUGHNESS},
    {"ior", T_INPUT, PB_IN_IOR},
    {"transmission", T_INPUT, PB_IN_TRANSMISSION},
    {"transmissionRoughness", T_INPUT, PB_IN_TRANSMISSION_ROUGHNESS},
    {"alpha", T_INPUT, PB_IN_ALPHA},
    {"subsurface", T_INPUT, PB_IN_SUBSURFACE},
    {NULL, T_NONE, 0}};
/* Principled v2 (model "principled2"). */
static const target principled2_targets[] = {
    {"baseColor", T_COLOR, COLOR_BASE},
    {"emissionColor", T_COLOR, COLOR_EMISSION},
    {"specularTint", T_COLOR, COLOR_SPECULAR_TINT},
    {"coatTint", T_COLOR, COLOR_COAT_TINT},
    {"sheenTint", T_COLOR, COLOR_SHEEN_TINT},
    {"normal", T_NORMAL, 0},
    {"coatNormal", T_COAT_NORMAL, 0},
    {"metallic", T_INPUT, PB_IN_METALLIC},
    {"roughness", T_INPUT, PB_IN_ROUGHNESS},
    {"ior", T_INPUT, PB_IN_IOR},
    {"alpha", T_INPUT, PB_IN_ALPHA},
    {"diffuseRoughness", T_INPUT, PB_IN_DIFFUSE_ROUGHNESS},
    {"subsurfaceWeight", T_INPUT, PB_IN_SUBSURFACE},
    {"subsurfaceScale", T_INPUT, PB_IN_SUBSURFACE_SCALE},
    {"subsurfaceIor", T_INPUT, PB_IN_SUBSURFACE_IOR},
    {"subsurfaceAnisotropy", T_INPUT, PB_IN_SUBSURFACE_ANISOTROPY},
    {"specularIorLevel", T_INPUT, PB_IN_SPECULAR_IOR_LEVEL},
    {"anisotropic", T_INPUT, PB_IN_ANISOTROPIC},
    {"anisotropicRotation", T_INPUT, PB_IN_ANISOTROPIC_ROTATION},
    {"transmissionWeight", T_INPUT, PB_IN_TRANSMISSION},
    {"coatWeight", T_INPUT, PB_IN_COAT_WEIGHT},
    {"coatRoughness", T_INPUT, PB_IN_COAT_ROUGHNESS},
    {"coatIor", T_INPUT, PB_IN_COAT_IOR},
    {"sheenWeight", T_INPUT, PB_IN_SHEEN_WEIGHT},
    {"sheenRoughness", T_INPUT, PB_IN_SHEEN_ROUGHNESS},
    {"emissionStrength", T_INPUT, PB_IN_EMISSION_STRENGTH},
    {"thinFilmThickness", T_INPUT, PB_IN_THIN_FILM_THICKNESS},
    {"thinFilmIor", T_INPUT, PB_IN_THIN_FILM_IOR},
    {NULL, T_NONE, 0}};
/* The Diffuse BSDF's and Emission shader's Color input is `baseColor` and
 * `emission` in `textures` (the contract; what the writer writes). */
static const target diffuse_targets[] = {
    {"baseColor", T_COLOR, COLOR_BASE}, {"roughness", T_INPUT, PB_IN_ROUGHNESS}, {"normal", T_NORMAL, 0}, {NULL, T_NONE, 0}};
/* The Glossy, Glass and Refraction BSDFs: Color is `baseColor`, as the
 * Diffuse BSDF's. */
static const target glossy_targets[] = {{"baseColor", T_COLOR, COLOR_BASE},
                                        {"roughness", T_INPUT, PB_IN_ROUGHNESS},
                                        {"anisotropy", T_INPUT, PB_IN_ANISOTROPIC},
                                        {"rotation", T_INPUT, PB_IN_ANISOTROPIC_ROTATION},
                                        {"normal", T_NORMAL, 0},
                                        {NULL, T_NONE, 0}};
static const target glass_targets[] = {{"baseColor", T_COLOR, COLOR_BASE},
                                       {"roughness", T_INPUT, PB_IN_ROUGHNESS},
                                       {"ior", T_INPUT, PB_IN_IOR},
                                       {"normal", T_NORMAL, 0},
                                       {NULL, T_NONE, 0}};
static const target emission_targets[] = {{"emission", T_COLOR, COLOR_EMISSION}, {NULL, T_NONE, 0}};

/* An optional integer member in [0, 2^31 - 1]; *out keeps its default when
 * absent. */
static pb_result opt_index(const reader *R, const pb_gltf_value *obj, const char *prefix, const char *key,
                           int32_t *out) {
  const pb_gltf_value *v = pb_gltf_value_get(obj, key);
  if (!v) return PB_OK;
  char path[192];
  member(path, sizeof path, prefix, key);
  if (v->type != PB_GLTF_NUMBER || !v->is_integer || v->number < 0 || v->number > INT32_MAX)
    return bad(R, path, "%s is not an integer from 0 to 2^31-1",
               v->type == PB_GLTF_NUMBER ? "the number" : pb_gltf_value_type_name(v));
  *out = (int32_t)v->number;
  return PB_OK;
}

/* An optional array member of 2 finite numbers. */
static pb_result opt_pair(const reader *R, const pb_gltf_value *obj, const char *prefix, const char *key,
                          double out[2]) {
  const pb_gltf_value *v = pb_gltf_value_get(obj, key);
  if (!v) return PB_OK;
  char path[192], el[208];
  member(path, sizeof path, prefix, key);
  if (v->type != PB_GLTF_ARRAY || v->count != 2)
    return bad(R, path, "%s, expected an array of 2 numbers", v->type == PB_GLTF_ARRAY ? "an array of another length"
                                                                                    : pb_gltf_value_type_name(v));
  for (int k = 0; k < 2; ++k) {
    float x = 0;
    snprintf(el, sizeof el, "%s[%d]", path, k);
    pb_result r = number_in(R, el, &v->items[k], -FLT_MAX, FLT_MAX, &x);
    if (r != PB_OK) return r;
    out[k] = x;
  }
  return PB_OK;
}

/* A texture entry as the glTF textureInfo it is (the contract): index,
 * texCoord and extensions.KHR_texture_transform, for the loader's texture
 * path (load_texture.c, load_texture_ref: uv sets 0 and 1, the transform). */
static pb_result texture_info(const reader *R, const char *path, const pb_gltf_value *e, const pb_gltf_value *iv,
                              pb_gltf_texture_ref *ref) {
  memset(ref, 0, sizeof *ref);
  ref->index = (int32_t)iv->number;
  ref->scale = 1.0;
  ref->transform.scale[0] = ref->transform.scale[1] = 1.0;
  ref->transform.texcoord = -1;
  pb_result r = opt_index(R, e, path, "texCoord", &ref->texcoord);
  if (r != PB_OK) return r;
  const pb_gltf_value *ex = pb_gltf_value_get(e, "extensions");
  char sub[192];
  snprintf(sub, sizeof sub, "%s.extensions", path);
  if (ex && ex->type != PB_GLTF_OBJECT) return bad(R, sub, "%s, expected an object", pb_gltf_value_type_name(ex));
  const pb_gltf_value *x = pb_gltf_value_get(ex, "KHR_texture_transform");
  if (!x) return PB_OK;
  snprintf(sub, sizeof sub, "%s.extensions.KHR_texture_transform", path);
  if (x->type != PB_GLTF_OBJECT) return bad(R, sub, "%s, expected an object", pb_gltf_value_type_name(x));
  pb_gltf_texture_transform *t = &ref->transform;
  t->present = 1;
  float rot = 0;
  if ((r = opt_pair(R, x, sub, "offset", t->offset)) != PB_OK) return r;
  if ((r = opt_pair(R, x, sub, "scale", t->scale)) != PB_OK) return r;
  if ((r = opt_number(R, x, sub, "rotation", -FLT_MAX, FLT_MAX, &rot)) != PB_OK) return r;
  t->rotation = rot;
  return opt_index(R, x, sub, "texCoord", &t->texcoord);
}

static pb_result read_texture(const reader *R, const char *name, const pb_gltf_value *e, const target *t,
                              pb_material *m) {
  char path[128], sub[256];
  snprintf(path, sizeof path, "textures.%s", name);
  if (e->type != PB_GLTF_OBJECT) return bad(R, path, "%s, expected an object (a glTF textureInfo)", pb_gltf_value_type_name(e));
  const pb_gltf_value *iv = pb_gltf_value_get(e, "index");
  snprintf(sub, sizeof sub, "%s.index", path);
  if (!iv) return bad(R, sub, "missing (required)");
  if (iv->type != PB_GLTF_NUMBER || !iv->is_integer || iv->number < 0 || iv->number > INT32_MAX)
    return bad(R, sub, "%s is not a texture index (an integer from 0 to 2^31-1)",
               iv->type == PB_GLTF_NUMBER ? "the number" : pb_gltf_value_type_name(iv));
  pb_gltf_texture_ref ref;
  pb_result r = texture_info(R, path, e, iv, &ref);
  if (r != PB_OK) return r;
  static const char *const channels[] = {"R", "G", "B", "A", "RGB"};
  int ch = CH_RGB;
  if ((r = opt_enum(R, e, path, "channel", channels, 5, &ch)) != PB_OK) return r;
  /* Colour sockets: sRGB texels unless the image is data (Non-Color;
   * Linear and Raw images hold linear values too). */
  static const char *const spaces[] = {"sRGB", "Non-Color", "Linear", "Raw"};
  int space = 0;
  if ((r = opt_enum(R, e, path, "colorSpace", spaces, 4, &space)) != PB_OK) return r;
  float strength = 1.0f;
  if ((r = opt_number(R, e, path, "strength", 0.0, FLT_MAX, &strength)) != PB_OK) return r;
  int srgb = t->kind == T_COLOR && space == 0;
  int32_t tex = PB_NO_TEXTURE;
  snprintf(sub, sizeof sub, "materials[%d]." EXT ".%s%s", R->index, R->at, path);
  if ((r = R->io->texture(R->io->user, &ref, srgb, sub, &tex)) != PB_OK) return r;
  pb_blender_material *b = &m->blender;
  switch (t->kind) {
  case T_COLOR:
    if (ch != CH_RGB)
      return bad(R, path, "channel %s on a colour input (only RGB)", channels[ch]);
    if (t->input == COLOR_BASE) m->base_color_tex = tex;
    else if (t->input == COLOR_SUBSURFACE) b->subsurface_color_tex = tex;
    else if (t->input == COLOR_SPECULAR_TINT) b->specular_tint_tex = tex;
    else if (t->input == COLOR_COAT_TINT) b->coat_tint_tex = tex;
    else if (t->input == COLOR_SHEEN_TINT) b->sheen_tint_tex = tex;
    else m->emissive_tex = tex;
    break;
  case T_NORMAL:
    m->normal_tex = tex;
    b->normal_strength = strength;
    break;
  case T_COAT_NORMAL:
    b->coat_normal_tex = tex;
    b->coat_normal_strength = strength;
    break;
  case T_INPUT:
    b->input_tex[t->input].tex = tex;
    /* A colour output on a float socket: Cycles' colour-to-float is the
     * luminance (svm_node_convert, linear_rgb_to_gray). */
    b->input_tex[t->input].channel = (uint32_t)ch;
    break;
  default:
    break;
  }
  return PB_OK;
}

static pb_result read_textures(const reader *R, const pb_gltf_value *ext, const target *targets, pb_material *m) {
  const pb_gltf_value *tx;
  pb_result r = opt_object(R, ext, "textures", &tx);
  if (r != PB_OK || !tx) return r;
  for (size_t i = 0; i < tx->count; ++i) {
    const target *t = targets;
    while (t->name && strcmp(t->name, tx->keys[i]) != 0) t++;
    if (!t->name) {
      r = warn(R, "materials[%d]." EXT ".%stextures.%s: not an input this model reads a texture for; its constant is used",
               R->index, R->at, tx->keys[i]);
    } else {
      r = read_texture(R, tx->keys[i], &tx->items[i], t, m);
    }
    if (r != PB_OK) return r;
  }
  return PB_OK;
}

/* ---- models -------------------------------------------------------------- */

typedef struct input_spec {
  const char *name;
  int input;
  float dflt, lo, hi;
} input_spec;

static const input_spec principled_inputs[] = {
    {"metallic", PB_IN_METALLIC, 0.0f, 0.0f, 1.0f},
    {"specular", PB_IN_SPECULAR, 0.5f, 0.0f, 1.0f},
    {"specularTint", PB_IN_SPECULAR_TINT, 0.0f, 0.0f, 1.0f},
    {"roughness", PB_IN_ROUGHNESS, 0.5f, 0.0f, 1.0f},
    {"anisotropic", PB_IN_ANISOTROPIC, 0.0f, 0.0f, 1.0f},
    {"anisotropicRotation", PB_IN_ANISOTROPIC_ROTATION, 0.0f, 0.0f, 1.0f},
    {"sheen", PB_IN_SHEEN, 0.0f, 0.0f, 1.0f},
    {"sheenTint", PB_IN_SHEEN_TINT, 0.5f, 0.0f, 1.0f},
    {"clearcoat", PB_IN_CLEARCOAT, 0.0f, 0.0f, 1.0f},
    {"clearcoatRoughness", PB_IN_CLEARCOAT_ROUGHNESS, 0.03f, 0.0f, 1.0f},
    {"ior", PB_IN_IOR, 1.45f, 0.0f, FLT_MAX},
    {"transmission", PB_IN_TRANSMISSION, 0.0f, 0.0f, 1.0f},
    {"transmissionRoughness", PB_IN_TRANSMISSION_ROUGHNESS, 0.0f, 0.0f, 1.0f},
    {"alpha", PB_IN_ALPHA, 1.0f, 0.0f, 1.0f},
    {"subsurface", PB_IN_SUBSURFACE, 0.0f, 0.0f, 1.0f},
};

static pb_result read_principled(const reader *R, const pb_gltf_value *ext, pb_material *m) {
  pb_blender_material *b = &m->blender;
  const pb_gltf_value *p;
  pb_result r = opt_object(R, ext, "principled", &p);
  if (r != PB_OK) return r;
  float base[3] = {0.8f, 0.8f, 0.8f}, ss[3] = {0.8f, 0.8f, 0.8f}, em[3] = {0.0f, 0.0f, 0.0f}, strength = 1.0f;
  float radius[3] = {1.0f, 0.2f, 0.1f};
  int dist = 0, ssm = 0;
  static const char *const dists[] = {"GGX", "MULTI_GGX"};
  /* Blender 3.4's names; RANDOM_WALK_SKIN, 4.x's name for 3.4's RANDOM_WALK,
   * is read as it. */
  static const char *const ss_methods[] = {"RANDOM_WALK", "RANDOM_WALK_FIXED_RADIUS", "BURLEY", "RANDOM_WALK_SKIN"};
  if (p) {
    for (size_t i = 0; i < sizeof principled_inputs / sizeof *principled_inputs && r == PB_OK; ++i) {
      const input_spec *in = &principled_inputs[i];
      r = opt_number(R, p, "principled", in->name, in->lo, in->hi, &b->input[in->input]);
    }
    if (r == PB_OK) r = opt_color(R, p, "principled", "baseColor", base);
    if (r == PB_OK) r = opt_color(R, p, "principled", "subsurfaceColor", ss);
    if (r == PB_OK) r = opt_color(R, p, "principled", "emission", em);
    if (r == PB_OK) r = opt_number(R, p, "principled", "emissionStrength", 0.0, FLT_MAX, &strength);
    for (int k = 0; k < 3 && r == PB_OK; ++k) {
      const pb_gltf_value *rv = pb_gltf_value_get(p, "subsurfaceRadius");
      if (!rv) break;
      if (rv->type != PB_GLTF_ARRAY || rv->count != 3) {
        r = bad(R, "principled.subsurfaceRadius", "expected an array of 3 numbers");
        break;
      }
      char el[64];
      snprintf(el, sizeof el, "principled.subsurfaceRadius[%d]", k);
      r = number_in(R, el, &rv->items[k], -FLT_MAX, FLT_MAX, &radius[k]);
    }
    if (r == PB_OK) r = opt_enum(R, p, "principled", "distribution", dists, 2, &dist);
    if (r == PB_OK) r = opt_enum(R, p, "principled", "subsurfaceMethod", ss_methods, 4, &ssm);
    if (r != PB_OK) return r;
  }
  b->distribution = dist ? PB_DISTRIBUTION_MULTI_GGX : PB_DISTRIBUTION_GGX;
  b->subsurface_method = ssm == 1 ? PB_SUBSURFACE_RANDOM_WALK_FIXED_RADIUS
                         : ssm == 2 ? PB_SUBSURFACE_BURLEY
                                    : PB_SUBSURFACE_RANDOM_WALK_SKIN;
  memcpy(b->subsurface_radius, radius, sizeof radius);
  memcpy(b->subsurface_color, ss, sizeof ss);
  for (int k = 0; k < 3; ++k) {
    m->base_color[k] = base[k];
    m->emissive[k] = em[k] * strength;
  }
  if ((r = read_textures(R, ext, principled_targets, m)) != PB_OK) return r;
  /* A texture replaces its socket's constant, so the colour factor of an
   * emission texture is the strength alone. */
  if (m->emissive_tex >= 0) m->emissive[0] = m->emissive[1] = m->emissive[2] = strength;
  m->base_color[3] = b->input[PB_IN_ALPHA];
  m->metallic = b->input[PB_IN_METALLIC];
  m->roughness = b->input[PB_IN_ROUGHNESS];
  m->transmission = b->input[PB_IN_TRANSMISSION];
  m->ior = b->input[PB_IN_IOR] >= 1.0f ? b->input[PB_IN_IOR] : 1.0f;
  if (b->distribution == PB_DISTRIBUTION_MULTI_GGX &&
      (b->input[PB_IN_TRANSMISSION] > 0.0f || b->input_tex[PB_IN_TRANSMISSION].tex >= 0) &&
      (b->input[PB_IN_ROUGHNESS] > 0.05f || b->input_tex[PB_IN_ROUGHNESS].tex >= 0) &&
      (r = warn(R, "materials[%d]." EXT ".principled.distribution: MULTI_GGX glass (roughness above 0.05) is rendered "
                   "with the single-scatter GGX glass closures", R->index)) != PB_OK)
    return r;
  if ((b->input[PB_IN_SUBSURFACE] > 0.0f || b->input_tex[PB_IN_SUBSURFACE].tex >= 0) &&
      (r = warn(R, "materials[%d]." EXT ".principled.subsurface: %g: approximated as diffuse with the subsurface-mixed "
                   "colour (no subsurface scattering)", R->index, b->input[PB_IN_SUBSURFACE])) != PB_OK)
    return r;
  return PB_OK;
}

/* Principled v2 (Blender 4.0+). Ranges: Blender 4.5's soft-and-hard socket
 * ranges where light stays non-negative (the 0..1 factors; IORs >= 0, the
 * coat's and thin film's >= 1 as Cycles clamps them; colours >= 0);
 * Subsurface Anisotropy -1..1 (5.2's range, a superset of 4.x's 0..1). */
static const input_spec principled2_inputs[] = {
    {"metallic", PB_IN_METALLIC, 0.0f, 0.0f, 1.0f},
    {"roughness", PB_IN_ROUGHNESS, 0.5f, 0.0f, 1.0f},
    {"ior", PB_IN_IOR, 1.5f, 0.0f, 1000.0f},
    {"alpha", PB_IN_ALPHA, 1.0f, 0.0f, 1.0f},
    {"diffuseRoughness", PB_IN_DIFFUSE_ROUGHNESS, 0.0f, 0.0f, 1.0f},
    {"subsurfaceWeight", PB_IN_SUBSURFACE, 0.0f, 0.0f, 1.0f},
    {"subsurfaceScale", PB_IN_SUBSURFACE_SCALE, 0.05f, 0.0f, FLT_MAX},
    {"subsurfaceIor", PB_IN_SUBSURFACE_IOR, 1.4f, 1.01f, 3.8f},
    {"subsurfaceAnisotropy", PB_IN_SUBSURFACE_ANISOTROPY, 0.0f, -1.0f, 1.0f},
    {"specularIorLevel", PB_IN_SPECULAR_IOR_LEVEL, 0.5f, 0.0f, FLT_MAX},
    {"anisotropic", PB_IN_ANISOTROPIC, 0.0f, 0.0f, 1.0f},
    {"anisotropicRotation", PB_IN_ANISOTROPIC_ROTATION, 0.0f, 0.0f, 1.0f},
    {"transmissionWeight", PB_IN_TRANSMISSION, 0.0f, 0.0f, 1.0f},
    {"coatWeight", PB_IN_COAT_WEIGHT, 0.0f, 0.0f, 1.0f},
    {"coatRoughness", PB_IN_COAT_ROUGHNESS, 0.03f, 0.0f, 1.0f},
    {"coatIor", PB_IN_COAT_IOR, 1.5f, 1.0f, 4.0f},
    {"sheenWeight", PB_IN_SHEEN_WEIGHT, 0.0f, 0.0f, 1.0f},
    {"sheenRoughness", PB_IN_SHEEN_ROUGHNESS, 0.5f, 0.0f, 1.0f},
    {"emissionStrength", PB_IN_EMISSION_STRENGTH, 0.0f, 0.0f, FLT_MAX},
    {"thinFilmThickness", PB_IN_THIN_FILM_THICKNESS, 0.0f, 0.0f, 100000.0f},
    {"thinFilmIor", PB_IN_THIN_FILM_IOR, 1.33f, 1.0f, 1000.0f},
};

/* F0 of a dielectric of relative IOR eta at normal incidence. */
static float f0_of_ior(float eta) {
  float r = (eta - 1.0f) / (eta + 1.0f);
  return r * r;
}

/* The glTF members and the v1 slots of a principled2 material from its
 * input[]. */
static void principled2_v1_slots(pb_material *m) {
  pb_blender_material *b = &m->blender;
  m->base_color[3] = b->input[PB_IN_ALPHA];
  m->metallic = b->input[PB_IN_METALLIC];
  m->roughness = b->input[PB_IN_ROUGHNESS];
  m->transmission = b->input[PB_IN_TRANSMISSION];
  m->ior = b->input[PB_IN_IOR] >= 1.0f ? b->input[PB_IN_IOR] : 1.0f;
  /* The v1 slots: Blender 3.4's nearest inputs, for code that renders the
   * v1 closures (dielectric F0 = 0.08 Specular; Clearcoat is 4 x Coat, as
   * Blender 4.0's versioning divides it by 4). */
  float ior = b->input[PB_IN_IOR], f0 = f0_of_ior(ior >= 1.0f ? ior : 1.0f / fmaxf(ior, 1e-3f));
  b->input[PB_IN_SPECULAR] = fminf(f0 * 2.0f * b->input[PB_IN_SPECULAR_IOR_LEVEL] / 0.08f, 12.5f);
  b->input[PB_IN_SPECULAR_TINT] = 0.0f;
  b->input[PB_IN_SHEEN] = b->input[PB_IN_SHEEN_WEIGHT];
  b->input[PB_IN_SHEEN_TINT] = 0.0f;
  b->input[PB_IN_CLEARCOAT] = fminf(4.0f * b->input[PB_IN_COAT_WEIGHT], 1.0f);
  b->input[PB_IN_CLEARCOAT_ROUGHNESS] = b->input[PB_IN_COAT_ROUGHNESS];
  b->input[PB_IN_TRANSMISSION_ROUGHNESS] = b->input[PB_IN_ROUGHNESS];
}

static pb_result read_principled2(const reader *R, const pb_gltf_value *ext, pb_material *m) {
  pb_blender_material *b = &m->blender;
  const pb_gltf_value *p;
  pb_result r = opt_object(R, ext, "principled2", &p);
  if (r != PB_OK) return r;
  float base[3] = {0.8f, 0.8f, 0.8f}, em[3] = {1.0f, 1.0f, 1.0f};
  int dist = 1, ssm = 1;
  static const char *const dists[] = {"GGX", "MULTI_GGX"};
  static const char *const ss_methods[] = {"RANDOM_WALK_SKIN", "RANDOM_WALK_FIXED_RADIUS", "BURLEY"};
  if (p) {
    for (size_t i = 0; i < sizeof principled2_inputs / sizeof *principled2_inputs && r == PB_OK; ++i) {
      const input_spec *in = &principled2_inputs[i];
      r = opt_number(R, p, "principled2", in->name, in->lo, in->hi, &b->input[in->input]);
    }
    if (r == PB_OK) r = opt_color(R, p, "principled2", "baseColor", base);
    if (r == PB_OK) r = opt_color(R, p, "principled2", "emissionColor", em);
    if (r == PB_OK) r = opt_color(R, p, "principled2", "specularTint", b->specular_tint);
    if (r == PB_OK) r = opt_color(R, p, "principled2", "coatTint", b->coat_tint);
    if (r == PB_OK) r = opt_color(R, p, "principled2", "sheenTint", b->sheen_tint);
    const pb_gltf_value *rv = pb_gltf_value_get(p, "subsurfaceRadius");
    if (r == PB_OK && rv) {
      if (rv->type != PB_GLTF_ARRAY || rv->count != 3)
        return bad(R, "principled2.subsurfaceRadius", "%s, expected an array of 3 numbers",
                   rv->type == PB_GLTF_ARRAY ? "an array of another length" : pb_gltf_value_type_name(rv));
      for (int k = 0; k < 3 && r == PB_OK; ++k) {
        char el[64];
        snprintf(el, sizeof el, "principled2.subsurfaceRadius[%d]", k);
        r = number_in(R, el, &rv->items[k], 0.0, FLT_MAX, &b->subsurface_radius[k]);
      }
    }
    if (r == PB_OK) r = opt_enum(R, p, "principled2", "distribution", dists, 2, &dist);
    if (r == PB_OK) r = opt_enum(R, p, "principled2", "subsurfaceMethod", ss_methods, 3, &ssm);
    if (r != PB_OK) return r;
  }
  b->distribution = dist ? PB_DISTRIBUTION_MULTI_GGX : PB_DISTRIBUTION_GGX;
  b->subsurface_method = ssm == 1 ? PB_SUBSURFACE_RANDOM_WALK_FIXED_RADIUS
                         : ssm == 2 ? PB_SUBSURFACE_BURLEY
                                    : PB_SUBSURFACE_RANDOM_WALK_SKIN;
  float strength = b->input[PB_IN_EMISSION_STRENGTH];
  for (int k = 0; k < 3; ++k) {
    m->base_color[k] = b->subsurface_color[k] = base[k];
    m->emissive[k] = em[k] * strength;
  }
  if ((r = read_textures(R, ext, principled2_targets, m)) != PB_OK) return r;
  if (m->emissive_tex >= 0) m->emissive[0] = m->emissive[1] = m->emissive[2] = strength;
  b->subsurface_color_tex = m->base_color_tex;
  if (b->input_tex[PB_IN_EMISSION_STRENGTH].tex >= 0 &&
      (r = warn(R, "materials[%d]." EXT ".textures.emissionStrength: an Emission Strength texture is not rendered; "
                   "the strength %g is used", R->index, strength)) != PB_OK)
    return r;
  principled2_v1_slots(m);
  if ((b->input[PB_IN_SUBSURFACE] > 0.0f || b->input_tex[PB_IN_SUBSURFACE].tex >= 0) &&
      (r = warn(R, "materials[%d]." EXT ".principled2.subsurfaceWeight: %g: approximated as diffuse (no subsurface "
                   "scattering)", R->index, b->input[PB_IN_SUBSURFACE])) != PB_OK)
    return r;
  return PB_OK;
}

/* Cycles 4.5 src/kernel/closure/bsdf_util.h fresnel_conductor: the
 * unpolarised reflectance of a conductor of complex IOR n + ik. */
static float fresnel_conductor1(float cosi, float eta, float k) {
  float cosi2 = cosi * cosi, tmp_f = eta * eta + k * k, tmp = tmp_f * cosi2;
  float rparl2 = (tmp - 2.0f * eta * cosi + 1.0f) / (tmp + 2.0f * eta * cosi + 1.0f);
  float rperp2 = (tmp_f - 2.0f * eta * cosi + cosi2) / (tmp_f + 2.0f * eta * cosi + cosi2);
  return 0.5f * (rparl2 + rperp2);
}

/* The Metallic BSDF (Blender 4.3+; model "metallic", Fresnel type F82 or
 * PHYSICAL_CONDUCTOR).
 * Cycles 4.5 src/kernel/svm/closure.h, CLOSURE_BSDF_F82_CONDUCTOR: a
 * microfacet closure of weight 1, F0 = saturate(Base Color), F82 tint =
 * saturate(Edge Tint) (bsdf_microfacet_setup_fresnel_f82_tint), alpha = r^2
 * stretched by sqrt(1 - 0.9 anisotropy), the tangent rotated by Rotation x
 * 2 pi: the very closure of the Principled v2 metal lobe (Metallic 1, Specular
 * Tint = Edge Tint), which is how both renderers render it. PHYSICAL_CONDUCTOR
 * (CLOSURE_BSDF_PHYSICAL_CONDUCTOR) is the same closure with
 * bsdf_microfacet_setup_fresnel_conductor's Fresnel of n = max(IOR, 0), k =
 * max(Extinction, 0): the metal lobe with pb_blender_material.conductor.
 * Distribution GGX, Multiscatter GGX (compensated) or Beckmann
 * (bsdf_microfacet_beckmann_setup: Beckmann's D and Lambda, uncompensated). */
static pb_result read_metallic(const reader *R, const pb_gltf_value *ext, pb_material *m) {
  pb_blender_material *b = &m->blender;
  const pb_gltf_value *p;
  pb_result r = opt_object(R, ext, "metallic", &p);
  if (r != PB_OK) return r;
  float base[3] = {0.617f, 0.577f, 0.540f}, tint[3] = {0.695f, 0.726f, 0.770f};
  float n[3] = {2.757f, 2.513f, 2.231f}, k[3] = {3.867f, 3.404f, 3.009f};
  float rough = 0.5f, aniso = 0.0f, rot = 0.0f;
  int dist = 1, fresnel = 0;
  static const char *const dists[] = {"GGX", "MULTI_GGX", "BECKMANN"};
  static const char *const fresnels[] = {"F82", "PHYSICAL_CONDUCTOR"};
  if (p) {
    if ((r = opt_color(R, p, "metallic", "baseColor", base)) != PB_OK ||
        (r = opt_color(R, p, "metallic", "edgeTint", tint)) != PB_OK ||
        (r = opt_number(R, p, "metallic", "roughness", 0.0, 1.0, &rough)) != PB_OK ||
        (r = opt_number(R, p, "metallic", "anisotropy", 0.0, 1.0, &aniso)) != PB_OK ||
        (r = opt_number(R, p, "metallic", "rotation", 0.0, 1.0, &rot)) != PB_OK ||
        (r = opt_enum(R, p, "metallic", "distribution", dists, 3, &dist)) != PB_OK ||
        (r = opt_enum(R, p, "metallic", "fresnelType", fresnels, 2, &fresnel)) != PB_OK ||
        (r = opt_color(R, p, "metallic", "ior", n)) != PB_OK ||
        (r = opt_color(R, p, "metallic", "extinction", k)) != PB_OK)
      return r;
  }
  b->distribution = dist == 2 ? PB_DISTRIBUTION_BECKMANN : dist ? PB_DISTRIBUTION_MULTI_GGX : PB_DISTRIBUTION_GGX;
  b->input[PB_IN_METALLIC] = 1.0f;
  b->input[PB_IN_ROUGHNESS] = rough;
  b->input[PB_IN_ANISOTROPIC] = aniso;
  b->input[PB_IN_ANISOTROPIC_ROTATION] = rot;
  for (int c = 0; c < 3; ++c) {
    m->base_color[c] = b->subsurface_color[c] = fminf(base[c], 1.0f);
    b->specular_tint[c] = fminf(tint[c], 1.0f);
  }
  if (fresnel == 1) {
    b->conductor = 1;
    for (int c = 0; c < 3; ++c) {
      b->input[PB_IN_CONDUCTOR_N_R + c] = n[c];
      b->specular_tint[c] = k[c];
      m->base_color[c] = b->subsurface_color[c] = fminf(fmaxf(fresnel_conductor1(1.0f, n[c], k[c]), 0.0f), 1.0f);
    }
  }
  b->node = PB_NODE_METALLIC;
  principled2_v1_slots(m);
  return PB_OK;
}

/* The Sheen BSDF (Blender 4.0+; model "sheen", distribution Microfiber).
 * Cycles 4.5 src/kernel/svm/closure.h, CLOSURE_BSDF_SHEEN_ID: bsdf_sheen_setup
 * (closure/bsdf_sheen.h, the LTC microfiber sheen) of weight Color and
 * roughness saturate(Roughness): the Principled v2 sheen lobe over nothing
 * (Sheen Weight 1, Sheen Tint = Color, black base, Specular IOR Level 0). */
static pb_result read_sheen(const reader *R, const pb_gltf_value *ext, pb_material *m) {
  pb_blender_material *b = &m->blender;
  const pb_gltf_value *p;
  pb_result r = opt_object(R, ext, "sheen", &p);
  if (r != PB_OK) return r;
  float color[3] = {0.8f, 0.8f, 0.8f}, rough = 0.5f;
  int dist = 0;
  static const char *const dists[] = {"MICROFIBER", "ASHIKHMIN"};
  if (p && ((r = opt_color(R, p, "sheen", "color", color)) != PB_OK ||
            (r = opt_number(R, p, "sheen", "roughness", 0.0, 1.0, &rough)) != PB_OK ||
            (r = opt_enum(R, p, "sheen", "distribution", dists, 2, &dist)) != PB_OK))
    return r;
  if (dist == 1) {
    /* Ashikhmin (CLOSURE_BSDF_ASHIKHMIN_VELVET_ID, the Velvet BSDF of 3.x,
     * whose Sigma is the Roughness): a closure of its own, weight Color. */
    b->input[PB_IN_SPECULAR_IOR_LEVEL] = 0.0f;
    b->input[PB_IN_ROUGHNESS] = rough;
    for (int k = 0; k < 3; ++k) m->base_color[k] = b->subsurface_color[k] = color[k];
    b->node = PB_NODE_VELVET;
    principled2_v1_slots(m);
    return PB_OK;
  }
  b->input[PB_IN_SPECULAR_IOR_LEVEL] = 0.0f;
  b->input[PB_IN_SHEEN_WEIGHT] = 1.0f;
  b->input[PB_IN_SHEEN_ROUGHNESS] = rough;
  for (int k = 0; k < 3; ++k) {
    m->base_color[k] = b->subsurface_color[k] = 0.0f;
    b->sheen_tint[k] = color[k];
  }
  b->node = PB_NODE_SHEEN;
  principled2_v1_slots(m);
  return PB_OK;
}

/* The Glossy BSDF (model "glossy"), and the Glass and Refraction BSDFs
 * (models "glass", "refraction"), as Blender 4.x computes them (Cycles 4.5
 * src/kernel/svm/closure.h, CLOSURE_BSDF_MICROFACET_GGX_ID and _MULTI_GGX_ID,
 * _GGX_GLASS_ID and _MULTI_GGX_GLASS_ID, _GGX_REFRACTION_ID):
 * - Glossy: a GGX reflection of weight Color with no Fresnel, alpha = r^2
 *   (r = saturate(Roughness)) stretched by Anisotropy a in -0.99..0.99
 *   (a >= 0: alpha_x = alpha (1 - a), alpha_y = alpha / (1 - a); a < 0:
 *   alpha_x = alpha / (1 + a), alpha_y = alpha (1 + a)), the tangent turned
 *   by Rotation x 2 pi; Multiscatter GGX: Turquin energy compensation with
 *   the Fresnel average Color (bsdf_microfacet_setup_fresnel_constant);
 * - Glass: a GGX glass whose reflection and transmission are both tinted
 *   by Color, on the real dielectric Fresnel curve of IOR (generalized
 *   Schlick with F0 = F0(IOR), F90 = 1 and a negative exponent); Multiscatter
 *   GGX: the glass tables' compensation with the transmission tint;
 * - Refraction: a GGX refraction of weight Color with no Fresnel (all but
 *   total internal reflection is transmitted), never compensated.
 * Beckmann (each node's third distribution; never compensated): the same
 * closures with Beckmann's D and Walter et al.'s rational Smith Lambda
 * (bsdf_aniso_D, bsdf_lambda_from_sqr_alpha_tan_n).
 * The writer writes these models from Blender 4.0 on; an Ashikhmin-Shirley
 * Glossy comes as GGX with the writer's warning. */
static pb_result read_bsdf_node(const reader *R, const pb_gltf_value *ext, pb_material *m, pb_blender_node node) {
  pb_blender_material *b = &m->blender;
  const char *name = node == PB_NODE_GLOSSY ? "glossy" : node == PB_NODE_GLASS ? "glass" : "refraction";
  const pb_gltf_value *p;
  pb_result r = opt_object(R, ext, name, &p);
  if (r != PB_OK) return r;
  float color[3] = {0.8f, 0.8f, 0.8f};
  float rough = node == PB_NODE_GLOSSY ? 0.5f : 0.0f, ior = 1.5f, aniso = 0.0f, rot = 0.0f;
  /* Blender's own node defaults: Multiscatter GGX for Glossy and Glass,
   * GGX for Refraction (which has no Multiscatter form). */
  int dist = node == PB_NODE_REFRACTION ? 0 : 1;
  static const char *const dists[] = {"GGX", "MULTI_GGX", "BECKMANN"};
  static const char *const refraction_dists[] = {"GGX", "BECKMANN"};
  if (p) {
    if ((r = opt_color(R, p, name, "color", color)) != PB_OK ||
        (r = opt_number(R, p, name, "roughness", 0.0, 1.0, &rough)) != PB_OK)
      return r;
    if (node == PB_NODE_REFRACTION) {
      if ((r = opt_enum(R, p, name, "distribution", refraction_dists, 2, &dist)) != PB_OK) return r;
      if (dist == 1) dist = 2;
    } else if ((r = opt_enum(R, p, name, "distribution", dists, 3, &dist)) != PB_OK) {
      return r;
    }
    if (node == PB_NODE_GLOSSY &&
        ((r = opt_number(R, p, name, "anisotropy", -1.0, 1.0, &aniso)) != PB_OK ||
         (r = opt_number(R, p, name, "rotation", 0.0, 1.0, &rot)) != PB_OK))
      return r;
    if (node != PB_NODE_GLOSSY && (r = opt_number(R, p, name, "ior", 0.0, 1000.0, &ior)) != PB_OK) return r;
  }
  b->distribution = dist == 2 ? PB_DISTRIBUTION_BECKMANN : dist ? PB_DISTRIBUTION_MULTI_GGX : PB_DISTRIBUTION_GGX;
  b->input[PB_IN_SPECULAR_IOR_LEVEL] = 0.0f;
  b->input[PB_IN_ROUGHNESS] = rough;
  if (node == PB_NODE_GLOSSY) {
    b->input[PB_IN_METALLIC] = 1.0f;
    b->input[PB_IN_ANISOTROPIC] = aniso;
    b->input[PB_IN_ANISOTROPIC_ROTATION] = rot;
  } else {
    b->input[PB_IN_TRANSMISSION] = 1.0f;
    b->input[PB_IN_IOR] = ior;
  }
  for (int k = 0; k < 3; ++k) m->base_color[k] = b->subsurface_color[k] = color[k];
  b->node = node;
  if ((r = read_textures(R, ext, node == PB_NODE_GLOSSY ? glossy_targets : glass_targets, m)) != PB_OK) return r;
  b->subsurface_color_tex = m->base_color_tex;
  principled2_v1_slots(m);
  return PB_OK;
}

static pb_result read_diffuse(const reader *R, const pb_gltf_value *ext, pb_material *m) {
  const pb_gltf_value *d;
  pb_result r = opt_object(R, ext, "diffuse", &d);
  if (r != PB_OK) return r;
  float color[3] = {0.8f, 0.8f, 0.8f};
  m->blender.input[PB_IN_ROUGHNESS] = 0.0f;
  if (d && ((r = opt_color(R, d, "diffuse", "color", color)) != PB_OK ||
            (r = opt_number(R, d, "diffuse", "roughness", 0.0, 1.0, &m->blender.input[PB_IN_ROUGHNESS])) != PB_OK))
    return r;
  for (int k = 0; k < 3; ++k) m->base_color[k] = color[k];
  m->roughness = m->blender.input[PB_IN_ROUGHNESS];
  return read_textures(R, ext, diffuse_targets, m);
}

static pb_result read_emission(const reader *R, const pb_gltf_value *ext, pb_material *m) {
  const pb_gltf_value *e;
  pb_result r = opt_object(R, ext, "emission", &e);
  if (r != PB_OK) return r;
  float color[3] = {1.0f, 1.0f, 1.0f}, strength = 1.0f;
  if (e && ((r = opt_color(R, e, "emission", "color", color)) != PB_OK ||
            (r = opt_number(R, e, "emission", "strength", 0.0, FLT_MAX, &strength)) != PB_OK))
    return r;
  for (int k = 0; k < 3; ++k) m->emissive[k] = color[k] * strength;
  if ((r = read_textures(R, ext, emission_targets, m)) != PB_OK) return r;
  if (m->emissive_tex >= 0) m->emissive[0] = m->emissive[1] = m->emissive[2] = strength;
  return PB_OK;
}

void pb_blender_material_defaults_v2(pb_material *m) {
  pb_blender_material_defaults(m, PB_MODEL_PRINCIPLED);
  pb_blender_material *b = &m->blender;
  b->principled_v2 = 1;
  for (int i = 0; i < PB_IN_COUNT; ++i) b->input[i] = 0.0f;
  for (size_t i = 0; i < sizeof principled2_inputs / sizeof *principled2_inputs; ++i)
    b->input[principled2_inputs[i].input] = principled2_inputs[i].dflt;
  for (int k = 0; k < 3; ++k) {
    m->base_color[k] = b->subsurface_color[k] = 0.8f;
    b->specular_tint[k] = b->coat_tint[k] = b->sheen_tint[k] = 1.0f;
  }
  b->distribution = PB_DISTRIBUTION_MULTI_GGX;
  b->subsurface_method = PB_SUBSURFACE_RANDOM_WALK_FIXED_RADIUS;
  b->input[PB_IN_SPECULAR] = 0.5f; /* the v1 approximation of level 0.5 at IOR 1.5 */
  b->input[PB_IN_CLEARCOAT_ROUGHNESS] = b->input[PB_IN_COAT_ROUGHNESS];
  b->input[PB_IN_TRANSMISSION_ROUGHNESS] = b->input[PB_IN_ROUGHNESS];
  m->roughness = b->input[PB_IN_ROUGHNESS];
  m->ior = b->input[PB_IN_IOR];
}

void pb_blender_material_defaults(pb_material *m, pb_material_model model) {
  /* The extension replaces the plain glTF form: start from nothing. */
  pb_blender_material *b = &m->blender;
  memset(b, 0, sizeof *b);
  for (int k = 0; k < 4; ++k) m->base_color[k] = k == 3 ? 1.0f : 0.0f;
  for (int k = 0; k < 3; ++k) m->emissive[k] = 0.0f;
  m->metallic = m->roughness = m->transmission = 0.0f;
  m->ior = 1.5f;
  m->base_color_tex = m->metallic_roughness_tex = m->emissive_tex = m->normal_tex = PB_NO_TEXTURE;
  m->normal_scale = 1.0f;
  m->alpha_mode = PB_ALPHA_OPAQUE;
  m->double_sided = 1; /* Cycles' emission leaves both sides of a face */
  m->unlit = 0;        /* glTF extensions of the plain form do not apply */
  memset(m->attenuation, 0, sizeof m->attenuation);
  b->model = model;
  b->subsurface_color_tex = PB_NO_TEXTURE;
  b->normal_strength = 1.0f;
  b->specular_tint_tex = b->coat_tint_tex = b->sheen_tint_tex = b->coat_normal_tex = PB_NO_TEXTURE;
  b->coat_normal_strength = 1.0f;
  b->subsurface_radius[0] = 1.0f, b->subsurface_radius[1] = 0.2f, b->subsurface_radius[2] = 0.1f;
  for (int i = 0; i < PB_IN_COUNT; ++i) b->input_tex[i].tex = PB_NO_TEXTURE;
  switch (model) {
  case PB_MODEL_PRINCIPLED:
    for (size_t i = 0; i < sizeof principled_inputs / sizeof *principled_inputs; ++i)
      b->input[principled_inputs[i].input] = principled_inputs[i].dflt;
    for (int k = 0; k < 3; ++k) m->base_color[k] = b->subsurface_color[k] = 0.8f;
    m->roughness = b->input[PB_IN_ROUGHNESS];
    m->ior = b->input[PB_IN_IOR];
    break;
  case PB_MODEL_DIFFUSE:
    for (int k = 0; k < 3; ++k) m->base_color[k] = 0.8f;
    break;
  case PB_MODEL_EMISSION:
    for (int k = 0; k < 3; ++k) m->emissive[k] = 1.0f;
    break;
  default:
    break;
  }
}

/* The model and its inputs (a material's, or a Mix Shader's second shader's). */
static pb_result read_model(reader R, const pb_gltf_value *ext, pb_material *m) {
  const pb_blender_material_io *io = R.io;
  int index = R.index;
  if (ext->type != PB_GLTF_OBJECT)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: materials[%d]." EXT ": %s, expected an object", io->path, index,
                   pb_gltf_value_type_name(ext));
  /* Index 0..3: pb_material_model from PB_MODEL_PRINCIPLED; 4: Principled
   * v2; 5..9: the Metallic, Sheen, Glossy, Glass and Refraction BSDFs
   * (rendered by the v2 code). */
  static const char *const models[] = {"principled", "diffuse", "emission", "holdout", "principled2",
                                        "metallic", "sheen", "glossy", "glass", "refraction"};
  int model = -1;
  pb_result r = opt_enum(&R, ext, "", "model", models, 10, &model);
  if (r != PB_OK) return r;
  if (model < 0)
    return bad(&R, "model", "missing (required: principled, principled2, metallic, sheen, glossy, glass, refraction, "
                            "diffuse, emission or holdout)");

  pb_blender_material *b = &m->blender;
  int v2 = model >= 4;
  if (v2) {
    pb_blender_material_defaults_v2(m);
  } else {
    pb_blender_material_defaults(m, (pb_material_model)(PB_MODEL_PRINCIPLED + model));
  }
  switch (b->model) {
  case PB_MODEL_PRINCIPLED:
    r = model == 5   ? read_metallic(&R, ext, m)
        : model == 6 ? read_sheen(&R, ext, m)
        : model == 7 ? read_bsdf_node(&R, ext, m, PB_NODE_GLOSSY)
        : model == 8 ? read_bsdf_node(&R, ext, m, PB_NODE_GLASS)
        : model == 9 ? read_bsdf_node(&R, ext, m, PB_NODE_REFRACTION)
        : v2         ? read_principled2(&R, ext, m)
                     : read_principled(&R, ext, m);
    break;
  case PB_MODEL_DIFFUSE: r = read_diffuse(&R, ext, m); break;
  case PB_MODEL_EMISSION: r = read_emission(&R, ext, m); break;
  default: break; /* holdout: nothing to read */
  }
  if (r != PB_OK) return r;
  /* Cycles 3.5 made Smith masking-shadowing height-correlated for every GGX
   * lobe; the root's "blender" (bpy.app.version_string, "4.5.1 LTS") says
   * which Blender wrote the file. */
  const pb_gltf_value *ver = io->root && io->root->type == PB_GLTF_OBJECT ? pb_gltf_value_get(io->root, "blender") : NULL;
  if (ver) {
    int major = 0, minor = 0;
    if (ver->type != PB_GLTF_STRING || sscanf(ver->string, "%d.%d", &major, &minor) != 2)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensions.PHOTONBRIDGE_blender.blender: %s, expected Blender's version "
                     "string (\"4.5.1\")", io->path, ver->type == PB_GLTF_STRING ? "not a version" : pb_gltf_value_type_name(ver));
    b->g2_correlated = major > 3 || (major == 3 && minor >= 5);
    b->normal_map_cycles4 = major >= 4;
    b->bump_model = major > 4 || (major == 4 && minor >= 5) ? PB_BUMP_CONTY : PB_BUMP_CHIANG;
    b->oren_nayar_ms = major > 4 || (major == 4 && minor >= 3);
  } else {
    b->g2_correlated = b->normal_map_cycles4 = b->principled_v2; /* principled2 is Blender 4.0+ */
    b->bump_model = PB_BUMP_CHIANG;
    b->oren_nayar_ms = 0;
  }
  /* Diffuse Roughness exists from 4.3, so a v2 material that has it is 4.3+. */
  if (b->principled_v2) b->oren_nayar_ms = 1;
  /* "bumpMapCorrection": false (Blender 4.2+ Material > Settings). */
  const pb_gltf_value *bmc = pb_gltf_value_get(ext, "bumpMapCorrection");
  if (bmc) {
    if (bmc->type != PB_GLTF_BOOL)
      return bad(&R, "bumpMapCorrection", "%s, expected true or false", pb_gltf_value_type_name(bmc));
    if (!bmc->boolean) b->bump_model = PB_BUMP_NONE;
  }

  /* "vertexColor": the input a Color Attribute node drives, its colour the
   * primitive's COLOR_0 (the writer puts the attribute there). */
  const pb_gltf_value *vc = pb_gltf_value_get(ext, "vertexColor");
  if (vc) {
    const char *want = b->node == PB_NODE_GLOSSY || b->node == PB_NODE_GLASS || b->node == PB_NODE_REFRACTION ? "color"
                       : b->node != PB_NODE_PRINCIPLED ? NULL
                       : b->model == PB_MODEL_PRINCIPLED ? "baseColor" : b->model == PB_MODEL_DIFFUSE ? "color" : NULL;
    if (vc->type != PB_GLTF_STRING)
      return bad(&R, "vertexColor", "%s, expected the name of the input a Color Attribute drives",
                 pb_gltf_value_type_name(vc));
    if (!want || strcmp(vc->string, want) != 0)
      return bad(&R, "vertexColor", "'%s': a colour attribute drives no such input of the %s model%s%s%s",
                 vc->string, models[model], want ? " (only '" : "", want ? want : "", want ? "')" : " (none)");
    b->base_from_vertex_color = 1;
  }

  /* Viewport settings Cycles does not use (EEVEE's blend mode, clip
   * threshold, backface culling): checked, not used. Cycles renders Alpha
   * as fractional transparency whatever the blend mode. */
  static const char *const blends[] = {"OPAQUE", "CLIP", "HASHED", "BLEND"};
  int blend = 0;
  float threshold = 0.5f;
  if ((r = opt_enum(&R, ext, "", "blendMethod", blends, 4, &blend)) != PB_OK) return r;
  if ((r = opt_number(&R, ext, "", "alphaThreshold", 0.0, 1.0, &threshold)) != PB_OK) return r;
  const pb_gltf_value *cull = pb_gltf_value_get(ext, "backfaceCulling");
  if (cull && cull->type != PB_GLTF_BOOL)
    return bad(&R, "backfaceCulling", "%s, expected true or false", pb_gltf_value_type_name(cull));
  const pb_gltf_value *w = pb_gltf_value_get(ext, "warnings");
  if (w) {
    if (w->type != PB_GLTF_ARRAY) return bad(&R, "warnings", "%s, expected an array of strings", pb_gltf_value_type_name(w));
    for (size_t i = 0; i < w->count; ++i) {
      if (w->items[i].type != PB_GLTF_STRING) {
        char path[64];
        snprintf(path, sizeof path, "warnings[%zu]", i);
        return bad(&R, path, "%s, expected a string", pb_gltf_value_type_name(&w->items[i]));
      }
      if ((r = warn(&R, "materials[%d] (%s): the Blender writer says: %s", index, m->name, w->items[i].string)) != PB_OK)
        return r;
    }
  }
  return PB_OK;
}

/* "mix": a Mix Shader of m's shader (weight 1 - fac) and "shader" (weight
 * fac), Cycles' svm_node_mix_closure; its factor as svm/fresnel.h computes
 * the Fresnel and Layer Weight nodes. */
static const target mix_targets[] = {{"fac", T_INPUT, PB_IN_MIX_FAC}, {NULL, T_NONE, 0}};

static int emits(const pb_material *m) {
  return m->emissive_tex >= 0 || m->emissive[0] > 0.0f || m->emissive[1] > 0.0f || m->emissive[2] > 0.0f;
}
static int clear(const pb_material *m) {
  return m->blender.model == PB_MODEL_PRINCIPLED && pb_blender_input_min(&m->blender, PB_IN_ALPHA) < 1.0f;
}

static pb_result read_mix(const reader *R, const pb_gltf_value *ext, pb_material *m) {
  const pb_gltf_value *mx, *sh;
  pb_result r = opt_object(R, ext, "mix", &mx);
  if (r != PB_OK || !mx) return r;
  pb_blender_material *b = &m->blender;
  if (!R->io->add_material)
    return warn(R, "materials[%d]." EXT ".mix: a Mix Shader is not read here; its first shader is rendered", R->index);
  if (b->model != PB_MODEL_PRINCIPLED && b->model != PB_MODEL_DIFFUSE)
    return bad(R, "mix", "the %s model cannot be mixed (only BSDFs)", pb_blender_model_name(b));
  static const char *const kinds[] = {"value", "fresnel", "layerFresnel", "layerFacing", "add"};
  int kind = 0;
  if ((r = opt_enum(R, mx, "mix", "facFrom", kinds, 5, &kind)) != PB_OK) return r;
  /* Fac 0..1; the Fresnel's IOR 0..1000; the Layer Weight's Blend 0..1
   * (the sockets' ranges). */
  /* An Add Shader has no factor (both weigh 1). */
  const char *key = kind == 0 ? "fac" : kind == 1 ? "ior" : "blend";
  float v = kind == 1 ? 1.5f : 0.5f;
  if (kind != PB_MIX_FAC_ADD) {
    if (!pb_gltf_value_get(mx, key)) {
      char path[32];
      snprintf(path, sizeof path, "mix.%s", key);
      return bad(R, path, "missing (required with facFrom '%s')", kinds[kind]);
    }
    if ((r = opt_number(R, mx, "mix", key, 0.0, kind == 1 ? 1000.0 : 1.0, &v)) != PB_OK) return r;
  }
  b->mix_fac = (pb_mix_fac)kind;
  b->input[PB_IN_MIX_FAC] = v;
  b->input_tex[PB_IN_MIX_FAC].tex = PB_NO_TEXTURE;
  reader RM = *R;
  RM.at = "mix.";
  if ((r = read_textures(&RM, mx, kind == 0 ? mix_targets : mix_targets + 1, m)) != PB_OK) return r;
  if ((r = opt_object(R, mx, "shader", &sh)) != PB_OK) return r;
  if (!sh) return bad(R, "mix.shader", "missing (required: the Mix Shader's second shader)");
  if (pb_gltf_value_get(sh, "mix")) return bad(R, "mix.shader.mix", "a Mix Shader inside a Mix Shader is not read");
  if (emits(m) || clear(m))
    return bad(R, "mix", "the first shader %s; a mixed shader is opaque and emits nothing here",
               emits(m) ? "emits" : "is transparent");
  pb_material second;
  memset(&second, 0, sizeof second);
  snprintf(second.name, sizeof second.name, "%.*s (mix)", (int)sizeof second.name - 7, m->name);
  reader RS = *R;
  RS.at = "mix.shader.";
  if ((r = read_model(RS, sh, &second)) != PB_OK) return r;
  const pb_blender_material *sb = &second.blender;
  if (sb->model != PB_MODEL_PRINCIPLED && sb->model != PB_MODEL_DIFFUSE)
    return bad(R, "mix.shader.model", "'%s' cannot be mixed (only BSDFs)", pb_blender_model_name(sb));
  if (emits(&second) || clear(&second))
    return bad(R, "mix.shader", "the second shader %s; a mixed shader is opaque and emits nothing here",
               emits(&second) ? "emits" : "is transparent");
  if (second.normal_tex >= 0 || sb->coat_normal_tex >= 0) {
    if ((r = warn(R, "materials[%d]." EXT ".mix.shader.textures: the second shader's normal map is not rendered; "
                     "it takes the first shader's normal", R->index)) != PB_OK)
      return r;
    second.normal_tex = second.blender.coat_normal_tex = PB_NO_TEXTURE;
  }
  uint32_t shared = pb_blender_closures(m) & pb_blender_closures(&second) & PB_BLENDER_CL_SLOTS;
  if (shared) {
    int k = 0;
    while (!(shared >> k & 1u)) ++k;
    return warn(R, "materials[%d]." EXT ".mix: both shaders can make a %s closure, which is not rendered mixed; "
                   "only the first shader is rendered", R->index, pb_blender_closure_names[k]);
  }
  uint32_t at = 0;
  if ((r = R->io->add_material(R->io->user, &second, &at)) != PB_OK) return r;
  b->mix_with = at + 1;
  b->mix_singular = pb_material_may_be_singular(&second);
  return PB_OK;
}

pb_result pb_blender_material_read(const pb_blender_material_io *io, int index, const pb_gltf_value *ext,
                                   pb_material *m) {
  reader R = {io, index, ""};
  pb_result r = read_model(R, ext, m);
  return r != PB_OK ? r : read_mix(&R, ext, m);
}

int pb_blender_needs_tangent(const pb_material *m) {
  const pb_blender_material *b = &m->blender;
  return b->model == PB_MODEL_PRINCIPLED && m->normal_tex < 0 &&
         (b->input[PB_IN_ANISOTROPIC] != 0.0f || b->input_tex[PB_IN_ANISOTROPIC].tex >= 0);
}

int pb_blender_radial_tangent(const double pl[3], const double bmin[3], const double bmax[3], const double N[9],
                              float out[3]) {
  /* Blender's texture space: a zero extent counts as 1 (so the division
   * stays finite; BKE_mesh_texspace_calc). glTF x is Blender's x, glTF z is
   * Blender's -y: (g.x - 1/2, g.y - 1/2) = ((x - cx) / sx, -(z - cz) / sz),
   * and Blender's (-(g.y - 1/2), g.x - 1/2, 0) is glTF's
   * ((z - cz) / sz, 0, -(x - cx) / sx). */
  double sx = bmax[0] - bmin[0], sz = bmax[2] - bmin[2];
  if (!(sx > 0.0)) sx = 1.0;
  if (!(sz > 0.0)) sz = 1.0;
  double t[3] = {(pl[2] - 0.5 * (bmin[2] + bmax[2])) / sz, 0.0, -(pl[0] - 0.5 * (bmin[0] + bmax[0])) / sx};
  double w[3], l = 0.0;
  for (int r = 0; r < 3; ++r) {
    w[r] = N[r] * t[0] + N[3 + r] * t[1] + N[6 + r] * t[2];
    l += w[r] * w[r];
  }
  l = sqrt(l);
  if (!(l > 1e-12) || !isfinite(l)) return 0;
  for (int r = 0; r < 3; ++r) out[r] = (float)(w[r] / l);
  return 1;
}
