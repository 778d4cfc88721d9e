/* glTF -> pb_scene: every index, offset, stride and count is checked before
 * any data is read, then the node tree is flattened into world-space arrays.
 * Errors are one line "FILE: JSON-PATH: why" (pb_fail). See gltf_doc.h for
 * what the shim has (and has not) checked. */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fs.h"
#include "scene/camera.h"
#include "core/half.h"
#include "image/decode.h"
#include "scene/gltf_doc.h"
#include "scene/tangents.h"
#include "scene/scene.h"

#include "scene/accessor.h"
#include "scene/anim.h"
#include "scene/blender_lights.h"
#include "scene/blender_material.h"
#include "scene/deform.h"
#include "scene/xform.h"

enum {
  MODE_TRIANGLES = 4,
  MODE_TRIANGLE_STRIP = 5,
  MODE_TRIANGLE_FAN = 6,
  MAX_NODE_DEPTH = 1024,
};

static const char *const mode_names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP",
                                         "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};

typedef struct loader {
  const char *path;           /* the file, or the memory load's name: in every message */
  const char *dir;            /* where URIs resolve (gltf_doc.h), NULL: no external files */
  const pb_load_desc *desc;
  pb_gltf_doc *doc;
  pb_scene *s;
  uint32_t vertex_cap, triangle_cap, light_cap, camera_cap, texture_cap;
  int32_t default_material;   /* index in s->materials, -1 until needed */
  int32_t *texture_src;       /* per s->textures: its glTF texture */
  uint8_t **image_cache;      /* decoded RGBA8 per gltf image */
  float **image_cache_f;      /* or RGBA floats (16-bit PNG, HDR, EXR: image/decode.h) */
  uint8_t *image_linear;      /* 1: image_cache_f holds scene-linear values (HDR, EXR) */
  uint32_t *image_w, *image_h;
  uint8_t *node_state;        /* cycle detection: 0 new, 1 on stack, 2 done */
  int32_t *parent;
  struct pb_scene_anim *anim; /* being built (anim.h); moved to s->anim */
  /* TANGENT attributes of normal-mapped primitives, world space, per vertex
   * of s (grown lazily to tan_cap; NULL until the first one); tan_given[v]
   * != 0 where the file gave vertex v one. finish_tangents() hands them to
   * pb_tangents_generate (tangents.c) for the rest. */
  float (*tan)[4];
  uint8_t *tan_given;
  uint32_t tan_cap;
  /* Skins and morph targets (deform.h): moved to the scene's anim when an
   * instance moves, freed after the static pose otherwise. world: every
   * node's world matrix in the file's own pose (with the precision origin),
   * which the static pose of skinned instances needs before visit() has
   * reached their joints. */
  pb_deform deform;
  mat4 *world;
  int need_uv1;               /* some texture reads TEXCOORD_1 */
  uint64_t texels;            /* over every s->textures (texture_ref's budget) */
} loader;

/* ---- growth helpers ---------------------------------------------------- */

static pb_result grow(loader *L, void **p, uint32_t *cap, uint64_t need, size_t elem,
                      const char *what) {
  if (need <= *cap) return PB_OK;
  if (need > UINT32_MAX / 2)
    return pb_fail(PB_ERR_LIMIT, "%s: too many %s (%llu)", L->path, what, (unsigned long long)need);
  uint64_t c = *cap ? *cap : 64;
  while (c < need) c *= 2;
  if (c > SIZE_MAX / elem) /* a 32-bit host: the byte size would wrap */
    return pb_fail(PB_ERR_LIMIT, "%s: too many %s (%llu) for this machine's address space", L->path, what,
                   (unsigned long long)need);
  void *q = realloc(*p, (size_t)c * elem);
  if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for %llu %s", L->path, (unsigned long long)c, what);
  *p = q;
  *cap = (uint32_t)c;
  return PB_OK;
}

static pb_result warn(loader *L, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static pb_result warn(loader *L, const char *fmt, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  if (pb_scene_warn(L->s, "%s", buf) != PB_OK)
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  return PB_OK;
}

static void copy_name(char dst[PB_NAME_MAX], const char *a, const char *b) {
  const char *src = (a && a[0]) ? a : (b ? b : "");
  snprintf(dst, PB_NAME_MAX, "%s", src);
}

/* ---- transforms: scene/xform.h ------------------------------------------ */

static mat4 node_local(const pb_gltf_node *n) {
  if (n->has_matrix) {
    mat4 r;
    memcpy(r.m, n->matrix, sizeof r.m);
    return r;
  }
  return trs_matrix(n->translation, n->rotation, n->scale);
}

/* ---- images and textures ------------------------------------------------- */

static pb_result decode_image(loader *L, int32_t img, const char *where) {
  pb_gltf_doc *d = L->doc;
  if (L->image_cache[img] || L->image_cache_f[img]) return PB_OK;
  const pb_gltf_image *im = &d->images[img];
  uint8_t *file = NULL;
  size_t size = 0;
  const uint8_t *bytes = NULL;
  if (im->buffer_view >= 0) {
    if ((size_t)im->buffer_view >= d->buffer_view_count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: images[%d].bufferView: %d does not exist (%zu bufferViews)",
                     L->path, img, im->buffer_view, d->buffer_view_count);
    const pb_gltf_buffer_view *v = &d->buffer_views[im->buffer_view];
    if (v->buffer < 0 || (size_t)v->buffer >= d->buffer_count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%d].buffer: %d does not exist", L->path,
                     im->buffer_view, v->buffer);
    const pb_gltf_buffer *b = &d->buffers[v->buffer];
    if (v->byte_offset > b->size || v->byte_length > b->size - v->byte_offset)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%d]: offset %llu + length %llu exceeds buffers[%d] (%llu bytes)",
                     L->path, im->buffer_view, (unsigned long long)v->byte_offset,
                     (unsigned long long)v->byte_length, v->buffer, (unsigned long long)b->size);
    bytes = b->data + v->byte_offset;
    size = v->byte_length;
  } else if (im->data) {
    bytes = im->data; /* a data URI, decoded and checked by the shim */
    size = im->data_size;
  } else if (im->uri[0]) {
    char *real = NULL;
    char w[64];
    snprintf(w, sizeof w, "images[%d].uri", img);
    pb_result r = pb_gltf_resolve_uri(L->path, L->dir, im->uri, L->desc->allow_external_files, w, &real);
    if (r != PB_OK) return r;
    r = pb_read_file(real, L->desc->max_file_bytes, &file, &size);
    free(real);
    if (r != PB_OK) {
      pb_error_clear();
      return pb_fail(r, "%s: images[%d].uri: cannot read '%s'", L->path, img, im->uri);
    }
    bytes = file;
  } else {
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: images[%d]: neither uri nor bufferView", L->path, img);
  }
  /* The declared size is checked from the header before any pixel memory
   * is allocated (image/decode.h). */
  const pb_decode_limits lim = {.max_dim = L->desc->max_image_dim, .max_pixels = L->desc->max_image_pixels};
  pb_decoded dec;
  pb_decode_status st;
  if (pb_decode_is_float_image(bytes, size)) {
    /* More than 8 bits a channel: kept as floats (scene.h pb_texture.rgbah). */
    pb_decoded_float df;
    st = pb_decode_image_float(bytes, size, &lim, &df);
    free(file);
    memset(&dec, 0, sizeof dec);
    dec.width = df.width, dec.height = df.height;
    memcpy(dec.why, df.why, sizeof dec.why);
    if (st == PB_DECODE_OK) {
      L->image_cache_f[img] = df.rgba;
      L->image_linear[img] = (uint8_t)df.linear;
      L->image_w[img] = df.width;
      L->image_h[img] = df.height;
      return PB_OK;
    }
  } else {
    st = pb_decode_image_rgba8(bytes, size, &lim, &dec);
    free(file);
  }
  if (st == PB_DECODE_UNKNOWN)
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: images[%d] (used by %s): not a PNG, JPEG, HDR or EXR file", L->path,
                   img, where);
  if (st == PB_DECODE_TOO_LARGE)
    return pb_fail(PB_ERR_LIMIT, "%s: images[%d]: %ux%u is over the image size limit (%u per side, %llu pixels)",
                   L->path, img, dec.width, dec.height, L->desc->max_image_dim,
                   (unsigned long long)L->desc->max_image_pixels);
  if (st == PB_DECODE_NOMEM) return pb_fail(PB_ERR_NOMEM, "%s: images[%d]: out of memory decoding it", L->path, img);
  if (st != PB_DECODE_OK) return pb_fail(PB_ERR_IMAGE, "%s: images[%d]: cannot decode: %s", L->path, img, dec.why);
  L->image_cache[img] = dec.rgba;
  L->image_w[img] = dec.width;
  L->image_h[img] = dec.height;
  return PB_OK;
}

static pb_result wrap_mode(loader *L, int32_t v, int32_t sampler, const char *field, pb_wrap *out) {
  switch (v) {
  case -1: case 10497: *out = PB_WRAP_REPEAT; return PB_OK;
  case 33071: *out = PB_WRAP_CLAMP; return PB_OK;
  case 33648: *out = PB_WRAP_MIRROR; return PB_OK;
  default:
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: samplers[%d].%s: %d is not a glTF wrap mode", L->path, sampler, field, v);
  }
}

/* Resolves a material's texture reference to an index in s->textures: one
 * pb_texture per glTF texture, colour space, uv set and KHR_texture_transform
 * (scene.h), shared by every slot that reads it the same way. */
static pb_result texture_ref(loader *L, const pb_gltf_texture_ref *ref, int srgb, const char *where, int32_t *out) {
  pb_gltf_doc *d = L->doc;
  int32_t tex = ref->index;
  *out = PB_NO_TEXTURE;
  if (tex == -1) return PB_OK;
  if (tex < 0 || (size_t)tex >= d->texture_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.index: texture %d does not exist (%zu textures)", L->path, where,
                   tex, d->texture_count);
  /* KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) uv, i.e.
   * u' = cos sx u + sin sy v + ox, v' = -sin sx u + cos sy v + oy (the
   * extension's matrices, rotation counter-clockwise in uv with v down);
   * its texCoord replaces the textureInfo's. */
  const pb_gltf_texture_transform *x = &ref->transform;
  float m[6] = {0, 0, 0, 0, 0, 0};
  int texcoord = x->present && x->texcoord >= 0 ? x->texcoord : ref->texcoord;
  if (x->present) {
    const double v[5] = {x->offset[0], x->offset[1], x->rotation, x->scale[0], x->scale[1]};
    for (int k = 0; k < 5; ++k)
      if (!isfinite(v[k]) || fabs(v[k]) > 1e30)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.extensions.KHR_texture_transform: %s %g is not finite", L->path, where,
                       k < 2 ? "offset" : k == 2 ? "rotation" : "scale", v[k]);
    double c = cos(x->rotation), sn = sin(x->rotation);
    m[0] = (float)(c * x->scale[0]), m[1] = (float)(sn * x->scale[1]), m[2] = (float)x->offset[0];
    m[3] = (float)(-sn * x->scale[0]), m[4] = (float)(c * x->scale[1]), m[5] = (float)x->offset[1];
  }
  if (texcoord > 1) {
    pb_result r = warn(L, "%s.texCoord: %d (only TEXCOORD_0 and TEXCOORD_1 are read; using TEXCOORD_0)", where, texcoord);
    if (r != PB_OK) return r;
    texcoord = 0;
  }
  pb_scene *s = L->s;
  for (uint32_t i = 0; i < s->texture_count; ++i) {
    const pb_texture *pt = &s->textures[i];
    if (L->texture_src[i] == tex && pt->srgb == srgb && pt->texcoord == texcoord && pt->uv_transformed == x->present &&
        !memcmp(pt->uv_xform, m, sizeof m)) {
      *out = (int32_t)i;
      return PB_OK;
    }
  }
  const pb_gltf_texture *t0 = &d->textures[tex];
  if (t0->source < 0 || (size_t)t0->source >= d->image_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: textures[%d].source: image %d does not exist (%zu images)", L->path,
                   tex, t0->source, d->image_count);
  /* A float image in place of the 8-bit source (gltf_doc.h float_source). */
  pb_gltf_texture tf = *t0;
  const pb_gltf_texture *t = &tf;
  if (t0->float_source != -1) {
    if (t0->float_source < 0 || (size_t)t0->float_source >= d->image_count)
      return pb_fail(PB_ERR_SCENE_INVALID,
                     "%s: textures[%d].extensions.PHOTONBRIDGE_blender.source: not an image index (%zu images)", L->path,
                     tex, d->image_count);
    tf.source = t0->float_source;
  }
  pb_wrap ws = PB_WRAP_REPEAT, wt = PB_WRAP_REPEAT;
  int nearest = 0;
  if (t->sampler != -1) {
    if (t->sampler < 0 || (size_t)t->sampler >= d->sampler_count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: textures[%d].sampler: %d does not exist (%zu samplers)", L->path,
                     tex, t->sampler, d->sampler_count);
    const pb_gltf_sampler *sm = &d->samplers[t->sampler];
    pb_result r = wrap_mode(L, sm->wrap_s, t->sampler, "wrapS", &ws);
    if (r == PB_OK) r = wrap_mode(L, sm->wrap_t, t->sampler, "wrapT", &wt);
    if (r != PB_OK) return r;
    nearest = sm->mag_filter == 9728;
  }
  pb_result r = decode_image(L, t->source, where);
  if (r != PB_OK) return r;
  /* Every colour space, uv set and transform of an image is a copy of its
   * pixels (here and on the GPU): a few hundred bytes of materials could ask
   * for thousands of copies of one image at the size limit. The scene's
   * texels are bounded by 16 images at the limit. */
  /* A float image's texel is two 32-bit words (half RGBA) here and on the GPU. */
  int is_f = L->image_cache_f[t->source] != NULL;
  uint64_t texels = (uint64_t)L->image_w[t->source] * L->image_h[t->source] * (is_f ? 2u : 1u);
  uint64_t budget = 16 * L->desc->max_image_pixels;
  if (L->texels + texels > budget)
    return pb_fail(PB_ERR_LIMIT, "%s: %s: textures[%d] (images[%d], %ux%u) takes the scene's textures over %llu texels "
                   "(16 x the image limit; each colour space, uv set and texture transform of an image is a copy)",
                   L->path, where, tex, t->source, L->image_w[t->source], L->image_h[t->source], (unsigned long long)budget);
  L->texels += texels;
  uint32_t cap = L->texture_cap;
  r = grow(L, (void **)&s->textures, &L->texture_cap, (uint64_t)s->texture_count + 1, sizeof *s->textures, "textures");
  if (r != PB_OK) return r;
  if (cap != L->texture_cap) {
    int32_t *q = realloc(L->texture_src, (size_t)L->texture_cap * sizeof *q);
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for textures", L->path);
    L->texture_src = q;
  }
  L->texture_src[s->texture_count] = tex;
  pb_texture *pt = &s->textures[s->texture_count];
  memset(pt, 0, sizeof *pt);
  size_t count = (size_t)L->image_w[t->source] * L->image_h[t->source] * 4;
  if (is_f) {
    /* Half RGBA for the slot: a 16-bit PNG's samples are sRGB-decoded here
     * when the slot is a colour one (as pb_texture_sample does for 8 bits);
     * HDR and EXR values are scene-linear in every slot. */
    pt->rgbah = malloc(count * sizeof *pt->rgbah);
    if (!pt->rgbah) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for textures[%d]", L->path, tex);
    const float *f = L->image_cache_f[t->source];
    int decode = srgb && !L->image_linear[t->source];
    uint64_t odd = 0;
    for (size_t k = 0; k < count; ++k) {
      float v = f[k];
      if (!(v >= 0.0f)) v = 0.0f, ++odd; /* NaN and negative texels: 0 */
      if (v > 65504.0f) v = 65504.0f, ++odd; /* half's largest */
      if (decode && k % 4 != 3) v = pb_srgb_to_linear(v);
      pt->rgbah[k] = pb_float_to_half(v);
    }
    if (odd) {
      pb_result r2 = warn(L, "images[%d]: %llu texel values negative, NaN or over 65504 were set to 0 or 65504",
                          t->source, (unsigned long long)odd);
      if (r2 != PB_OK) return r2;
    }
  } else {
    pt->rgba8 = malloc(count);
    if (!pt->rgba8) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for textures[%d]", L->path, tex);
    memcpy(pt->rgba8, L->image_cache[t->source], count);
  }
  pt->width = L->image_w[t->source];
  pt->height = L->image_h[t->source];
  pt->srgb = srgb;
  pt->wrap_s = ws;
  pt->wrap_t = wt;
  pt->nearest = nearest;
  pt->texcoord = texcoord;
  pt->uv_transformed = x->present;
  memcpy(pt->uv_xform, m, sizeof m);
  if (texcoord == 1) L->need_uv1 = 1;
  copy_name(pt->name, d->images[t->source].name, d->images[t->source].uri);
  *out = (int32_t)s->texture_count++;
  return PB_OK;
}

/* ---- materials ----------------------------------------------------------- */

static float clamp01(double v) { return (float)(v < 0 ? 0 : (v > 1 ? 1 : v)); }

static pb_result check_factor(loader *L, int i, const char *field, double v, double lo, double hi) {
  if (!isfinite(v) || v < lo || v > hi)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: materials[%d].%s: %g is outside [%g, %g]", L->path, i, field, v, lo, hi);
  return PB_OK;
}

/* The PHOTONBRIDGE_blender material reader's way to textures (glTF
 * textureInfos, through the same texture_ref as glTF's own: uv set and
 * KHR_texture_transform included) and warnings (blender_material.h). */
static pb_result blender_texture(void *user, const pb_gltf_texture_ref *ref, int srgb, const char *where, int32_t *out) {
  return texture_ref(user, ref, srgb, where, out);
}
static pb_result blender_warn(void *user, const char *line) { return warn(user, "%s", line); }

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
      (r = warn(L, "materials[%d].%s: no transmission, so no light enters the volume", i, vw)) != PB_OK)
    return r;
  return PB_OK;
}

static pb_result convert_material(loader *L, int i, pb_material *m) {
  const pb_gltf_material *g = &L->doc->materials[i];
  pb_result r = PB_OK;
  char w[128];
  memset(m, 0, sizeof *m);
  copy_name(m->name, g->name, "");
  if (!m->name[0]) snprintf(m->name, PB_NAME_MAX, "materials[%d]", i);
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
  if (g->ior != 0 && g->ior < 1)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: materials[%d].extensions.KHR_materials_ior.ior: %g is below 1", L->path, i, g->ior);
  m->normal_scale = (float)g->normal_tex.scale;
  m->double_sided = g->double_sided;
  m->alpha_cutoff = clamp01(g->alpha_cutoff);
  if (!g->alpha_mode[0] || strcmp(g->alpha_mode, "OPAQUE") == 0) m->alpha_mode = PB_ALPHA_OPAQUE;
  else if (strcmp(g->alpha_mode, "MASK") == 0) m->alpha_mode = PB_ALPHA_MASK;
  else if (strcmp(g->alpha_mode, "BLEND") == 0) m->alpha_mode = PB_ALPHA_BLEND;
  else return pb_fail(PB_ERR_SCENE_INVALID, "%s: materials[%d].alphaMode: '%s' is not OPAQUE, MASK or BLEND", L->path, i, g->alpha_mode);

  if ((r = material_extensions(L, i, g, m)) != PB_OK) return r;
  const pb_gltf_texture_ref *refs[4] = {&g->base_color_tex, &g->metallic_roughness_tex, &g->emissive_tex, &g->normal_tex};
  static const char *const names[4] = {"pbrMetallicRoughness.baseColorTexture", "pbrMetallicRoughness.metallicRoughnessTexture",
                                       "emissiveTexture", "normalTexture"};
  static const int srgb[4] = {1, 0, 1, 0};
  int32_t *dst[4] = {&m->base_color_tex, &m->metallic_roughness_tex, &m->emissive_tex, &m->normal_tex};
  for (int k = 0; k < 4; ++k) {
    snprintf(w, sizeof w, "materials[%d].%s", i, names[k]);
    r = texture_ref(L, refs[k], srgb[k], w, dst[k]);
    if (r != PB_OK) return r;
  }
  if (g->blender) {
    pb_blender_material_io io = {L->path, L, blender_texture, blender_warn, L->doc->blender};
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
static int32_t default_material(loader *L) {
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

/* ---- animations ----------------------------------------------------------
 * glTF animations are checked like every other accessor user, then kept in
 * a pb_scene_anim (anim.h) for pb_scene_set_time. All animations of the file
 * play together on one timeline: Blender exports one action per object as
 * one animation each, and a file's animations are meant to be seen at once
 * (a player that picks one would freeze every other object). Channels apply
 * in file order, so where two animations drive the same node property the
 * later one wins (warned). "weights" channels drive the morph weights of
 * their node's mesh (deform.h). Translation, rotation and scale channels on
 * nodes given by `matrix` (which glTF does not allow to animate) are ignored
 * with a warning. */

static const char *const anim_paths[] = {"translation", "rotation", "scale", "weights"};

/* Morph targets of the mesh nodes[node] draws (every primitive has as many:
 * pb_morph_weights_load). */
static size_t node_targets(const pb_gltf_doc *d, int32_t node) {
  int32_t m = d->nodes[node].mesh;
  if (m < 0 || (size_t)m >= d->mesh_count || !d->meshes[m].primitive_count) return 0;
  return d->meshes[m].primitives[0].target_count;
}

static pb_result anim_reserve(loader *L, struct pb_scene_anim *a, uint64_t more) {
  uint64_t need = (uint64_t)a->local_count + more;
  if (need <= a->local_cap) return PB_OK;
  if (need > UINT32_MAX / 2) return pb_fail(PB_ERR_LIMIT, "%s: too many animated vertices (%llu)", L->path, (unsigned long long)need);
  uint64_t c = a->local_cap ? a->local_cap : 256;
  while (c < need) c *= 2;
  void *p = realloc(a->local_pos, (size_t)c * sizeof *a->local_pos);
  if (p) a->local_pos = p;
  void *n = p ? realloc(a->local_nrm, (size_t)c * sizeof *a->local_nrm) : NULL;
  if (n) a->local_nrm = n;
  if (!p || !n) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for animated vertices", L->path);
  a->local_cap = (uint32_t)c;
  return PB_OK;
}

static pb_result anim_push_node(loader *L, int32_t **arr, uint32_t *cap, uint32_t at, int32_t node) {
  if (at >= *cap) {
    uint32_t c = *cap ? *cap : 8;
    while (c <= at) c *= 2;
    int32_t *q = realloc(*arr, (size_t)c * sizeof *q);
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
    for (uint32_t i = *cap; i < c; ++i) q[i] = -1;
    *arr = q;
    *cap = c;
  }
  (*arr)[at] = node;
  return PB_OK;
}

/* Checks animations[ai].samplers[si]'s interpolation and input (key times:
 * float SCALAR, finite, non-decreasing) and that its output accessor exists. */
static pb_result check_anim_sampler(loader *L, size_t ai, size_t si, int *interp) {
  pb_gltf_doc *d = L->doc;
  const pb_gltf_anim_sampler *g = &d->animations[ai].samplers[si];
  static const int32_t float_only[] = {PB_CT_FLOAT, 0};
  char w[96];
  const char *ip = g->interpolation ? g->interpolation : "LINEAR";
  if (strcmp(ip, "LINEAR") == 0) *interp = PB_ANIM_LINEAR;
  else if (strcmp(ip, "STEP") == 0) *interp = PB_ANIM_STEP;
  else if (strcmp(ip, "CUBICSPLINE") == 0) *interp = PB_ANIM_CUBICSPLINE;
  else
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].samplers[%zu].interpolation: '%s' is not LINEAR, STEP or CUBICSPLINE",
                   L->path, ai, si, ip);
  snprintf(w, sizeof w, "animations[%zu].samplers[%zu].input", ai, si);
  pb_span in;
  pb_result r = pb_accessor_check(L->path, L->doc, g->input, w, 1, float_only, &in);
  if (r != PB_OK) return r;
  /* Keys cost at least 4 bytes of times and 12 of values per key in memory,
   * nothing in the file when the accessors have no bufferView (zeros pass
   * every check below): bounded like vertices (3 x max_triangles) before the
   * per-key loop; convert_anim_sampler bounds the values the same way. */
  if (in.count > 3 * L->desc->max_triangles)
    return pb_fail(PB_ERR_LIMIT, "%s: %s: %llu keys is over the limit of %llu", L->path, w, (unsigned long long)in.count,
                   (unsigned long long)(3 * L->desc->max_triangles));
  float prev = 0;
  for (uint64_t k = 0; k < in.count; ++k) {
    float v = pb_span_f(&in, k, 0);
    if (!isfinite(v)) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: time at key %llu is not finite", L->path, w, (unsigned long long)k);
    if (k > 0 && v < prev)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: times decrease at key %llu (%g after %g)", L->path, w, (unsigned long long)k,
                     (double)v, (double)prev);
    prev = v;
  }
  if (*interp == PB_ANIM_CUBICSPLINE && in.count < 2)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: CUBICSPLINE needs at least 2 keys, accessor %d has %llu", L->path, w, g->input,
                   (unsigned long long)in.count);
  if (g->output < 0 || (size_t)g->output >= d->accessor_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].samplers[%zu].output: accessor %d does not exist (%zu accessors)",
                   L->path, ai, si, g->output, d->accessor_count);
  return PB_OK;
}

/* Reads animations[ai].samplers[si] for a channel of `path` into a new
 * pb_anim_sampler: output shape per path, count = keys (x3 for CUBICSPLINE),
 * every value finite. */
static pb_result convert_anim_sampler(loader *L, struct pb_scene_anim *a, size_t ai, size_t si, int interp, int path,
                                      size_t weights, int *negative_scale) {
  pb_gltf_doc *d = L->doc;
  const pb_gltf_anim_sampler *g = &d->animations[ai].samplers[si];
  static const int32_t float_only[] = {PB_CT_FLOAT, 0};
  static const int32_t norm_types[] = {PB_CT_FLOAT, PB_CT_BYTE, PB_CT_UBYTE, PB_CT_SHORT, PB_CT_USHORT, 0};
  /* Weights: one SCALAR per target per key (glTF 2.0 5.6.2). */
  int comps = path == PB_ANIM_ROTATION ? 4 : path == PB_ANIM_WEIGHTS ? (int)weights : 3;
  char wi[96], wo[128];
  snprintf(wi, sizeof wi, "animations[%zu].samplers[%zu].input", ai, si);
  snprintf(wo, sizeof wo, "animations[%zu].samplers[%zu].output (%s)", ai, si, anim_paths[path]);
  pb_span in, out;
  pb_result r = pb_accessor_check(L->path, L->doc, g->input, wi, 1, float_only, &in);
  int normalizable = path == PB_ANIM_ROTATION || path == PB_ANIM_WEIGHTS;
  if (r == PB_OK)
    r = pb_accessor_check(L->path, L->doc, g->output, wo, path == PB_ANIM_WEIGHTS ? 1 : comps,
                          normalizable ? norm_types : float_only, &out);
  if (r != PB_OK) return r;
  if (out.ct != PB_CT_FLOAT && !out.normalized)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: integer %s keys must be normalized (%s)", L->path, g->output,
                   anim_paths[path], wo);
  uint64_t per = (interp == PB_ANIM_CUBICSPLINE ? 3 : 1) * (path == PB_ANIM_WEIGHTS ? (uint64_t)comps : 1);
  if (out.count != in.count * per)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d has %llu elements, %s with %llu keys%s needs %llu", L->path, wo,
                   g->output, (unsigned long long)out.count, interp == PB_ANIM_CUBICSPLINE ? "CUBICSPLINE" : "LINEAR/STEP",
                   (unsigned long long)in.count, path == PB_ANIM_WEIGHTS ? " for its node's morph targets" : "",
                   (unsigned long long)(in.count * per));
  /* Values: at most 4 floats per key of the budget check_anim_sampler gave
   * the keys (weights keys carry one per morph target). */
  uint64_t nvalues = out.count * (uint64_t)(path == PB_ANIM_WEIGHTS ? 1 : comps);
  if (nvalues > 4 * 3 * L->desc->max_triangles)
    return pb_fail(PB_ERR_LIMIT, "%s: %s: %llu values is over the limit of %llu", L->path, wo, (unsigned long long)nvalues,
                   (unsigned long long)(4 * 3 * L->desc->max_triangles));
  pb_anim_sampler *S = &a->samplers[a->sampler_count];
  memset(S, 0, sizeof *S);
  S->times = malloc((size_t)in.count * sizeof *S->times);
  S->values = malloc((size_t)nvalues * sizeof *S->values);
  if (!S->times || !S->values) {
    free(S->times);
    free(S->values);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory for %s", L->path, wo);
  }
  a->sampler_count++; /* owned by a from here */
  S->key_count = (uint32_t)in.count;
  S->comps = comps;
  S->interp = interp;
  for (uint64_t k = 0; k < in.count; ++k) S->times[k] = pb_span_f(&in, k, 0);
  /* Weights arrive as scalars, `comps` per key (element): the same layout. */
  int ec = path == PB_ANIM_WEIGHTS ? 1 : comps;
  for (uint64_t k = 0; k < out.count; ++k)
    for (int c = 0; c < ec; ++c) {
      float v = pb_span_f(&out, k, c);
      if (!isfinite(v))
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: element %llu is not finite", L->path, wo, (unsigned long long)k);
      if (path == PB_ANIM_SCALE && (per == 1 || k % 3 == 1) && v < 0) *negative_scale = 1;
      S->values[k * (uint64_t)ec + (uint64_t)c] = v;
    }
  return PB_OK;
}

static pb_result build_anim(loader *L) {
  pb_gltf_doc *d = L->doc;
  pb_result r = PB_OK;
  if (!d->animation_count || !d->animations) return PB_OK;
  size_t nch = 0;
  for (size_t ai = 0; ai < d->animation_count; ++ai) nch += d->animations[ai].channel_count;
  struct pb_scene_anim *a = calloc(1, sizeof *a);
  if (!a) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  L->anim = a; /* freed by pb_scene_load unless moved to the scene */
  /* Per node and path: which animation and channel drives it (1-based). */
  size_t (*owner)[4][2] = calloc(d->node_count + 1, sizeof *owner);
  a->channels = calloc(nch + 1, sizeof *a->channels);
  a->samplers = calloc(nch + 1, sizeof *a->samplers);
  if (!owner || !a->channels || !a->samplers) {
    free(owner);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  }
  int negative_scale = 0;
  for (size_t ai = 0; ai < d->animation_count && r == PB_OK; ++ai) {
    const pb_gltf_animation *an = &d->animations[ai];
    int *interp = calloc(an->sampler_count + 1, sizeof *interp);
    if (!interp) r = pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
    for (size_t si = 0; si < an->sampler_count && r == PB_OK; ++si) r = check_anim_sampler(L, ai, si, &interp[si]);
    for (size_t ci = 0; ci < an->channel_count && r == PB_OK; ++ci) {
      const pb_gltf_anim_channel *ch = &an->channels[ci];
      if (ch->sampler < 0 || (size_t)ch->sampler >= an->sampler_count) {
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].channels[%zu].sampler: %d does not exist (%zu samplers)", L->path, ai,
                    ci, ch->sampler, an->sampler_count);
        break;
      }
      const char *ps = ch->path ? ch->path : "";
      int path = -1;
      for (int k = 0; k < 4; ++k)
        if (strcmp(ps, anim_paths[k]) == 0) path = k;
      if (path < 0 && strcmp(ps, "pointer") != 0) {
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].channels[%zu].target.path: '%s' is not translation, rotation, scale or weights",
                    L->path, ai, ci, ps);
        break;
      }
      if (ch->target_node != -1 && (ch->target_node < 0 || (size_t)ch->target_node >= d->node_count)) {
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].channels[%zu].target.node: %d does not exist (%zu nodes)", L->path, ai,
                    ci, ch->target_node, d->node_count);
        break;
      }
      if (path < 0) {
        r = warn(L, "animations[%zu].channels[%zu]: '%s' channel ignored (animation pointers are not animated)", ai, ci, ps);
        continue;
      }
      if (ch->target_node == -1) {
        r = warn(L, "animations[%zu].channels[%zu].target: no node; channel ignored", ai, ci);
        continue;
      }
      int32_t node = ch->target_node;
      size_t targets = path == PB_ANIM_WEIGHTS ? node_targets(d, node) : 0;
      if (path == PB_ANIM_WEIGHTS && !targets) {
        r = warn(L, "animations[%zu].channels[%zu]: nodes[%d] draws no morph targets; 'weights' channel ignored", ai, ci, node);
        continue;
      }
      if (path != PB_ANIM_WEIGHTS && d->nodes[node].has_matrix) {
        r = warn(L, "animations[%zu].channels[%zu]: nodes[%d] is given by a matrix, which glTF does not allow to animate; channel ignored",
                 ai, ci, node);
        continue;
      }
      size_t *own = owner[node][path];
      if (own[0] == ai + 1) {
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].channels[%zu].target: nodes[%d].%s is already animated by channels[%zu]",
                    L->path, ai, ci, node, anim_paths[path], own[1] - 1);
        break;
      }
      if (own[0] &&
          (r = warn(L, "animations[%zu].channels[%zu]: nodes[%d].%s is also animated by animations[%zu].channels[%zu]; the later one wins",
                    ai, ci, node, anim_paths[path], own[0] - 1, own[1] - 1)) != PB_OK)
        break;
      own[0] = ai + 1;
      own[1] = ci + 1;
      uint32_t sidx = a->sampler_count;
      if ((r = convert_anim_sampler(L, a, ai, (size_t)ch->sampler, interp[ch->sampler], path, targets, &negative_scale)) != PB_OK)
        break;
      a->channels[a->channel_count++] = (pb_anim_channel){.sampler = sidx, .node = node, .path = path};
    }
    free(interp);
  }
  free(owner);
  if (r != PB_OK) return r;
  if (negative_scale &&
      (r = warn(L, "animations: negative scale keys; a pose mirrored differently from the rest pose keeps the rest pose's winding")) != PB_OK)
    return r;
  if (a->channel_count == 0) { /* nothing to pose */
    pb_scene_anim_destroy(a);
    L->anim = NULL;
    return PB_OK;
  }
  a->node_count = (uint32_t)d->node_count;
  a->nodes = calloc(d->node_count + 1, sizeof *a->nodes);
  a->order = calloc(d->node_count + 1, sizeof *a->order);
  a->trs = calloc(d->node_count + 1, sizeof *a->trs);
  a->world = calloc(d->node_count + 1, sizeof *a->world);
  int comps = 4;
  for (uint32_t i = 0; i < a->sampler_count; ++i)
    if (a->samplers[i].comps > comps) comps = a->samplers[i].comps;
  a->values = calloc((size_t)comps, sizeof *a->values);
  if (!a->nodes || !a->order || !a->trs || !a->world || !a->values) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  for (size_t i = 0; i < d->node_count; ++i) {
    const pb_gltf_node *n = &d->nodes[i];
    pb_anim_node *o = &a->nodes[i];
    o->parent = L->parent[i];
    o->has_matrix = n->has_matrix;
    o->matrix = node_local(n);
    memcpy(o->t, n->translation, sizeof o->t);
    memcpy(o->r, n->rotation, sizeof o->r);
    memcpy(o->s, n->scale, sizeof o->s);
  }
  /* A node with a translation, rotation or scale channel is animated, and
   * so is every descendant: walk up from each node to the first one known
   * (node_state as scratch: 0 unknown, 1 no, 2 yes; the graph is a forest,
   * check_nodes). */
  for (uint32_t i = 0; i < a->channel_count; ++i) {
    pb_anim_node *o = &a->nodes[a->channels[i].node];
    if (a->channels[i].path == PB_ANIM_WEIGHTS) o->weights_animated = 1;
    else o->animated = 1;
  }
  uint8_t *st = L->node_state;
  for (size_t i = 0; i < d->node_count; ++i) {
    int32_t p = (int32_t)i;
    while (p >= 0 && !st[p] && !a->nodes[p].animated) p = L->parent[p];
    uint8_t v = p >= 0 && (a->nodes[p].animated || st[p] == 2) ? 2 : 1;
    for (int32_t q = (int32_t)i; q >= 0 && q != p; q = L->parent[q]) st[q] = v;
    if (p >= 0 && !st[p]) st[p] = v;
  }
  for (size_t i = 0; i < d->node_count; ++i) a->nodes[i].animated = st[i] == 2;
  memset(st, 0, d->node_count); /* visit() starts from zero */
  return PB_OK;
}

/* The union of the key times of the samplers in use. */
static void anim_range(const struct pb_scene_anim *a, double *start, double *end) {
  double lo = INFINITY, hi = -INFINITY;
  for (uint32_t i = 0; i < a->sampler_count; ++i) {
    const pb_anim_sampler *S = &a->samplers[i];
    lo = fmin(lo, S->times[0]);
    hi = fmax(hi, S->times[S->key_count - 1]);
  }
  *start = lo <= hi ? lo : 0;
  *end = lo <= hi ? hi : 0;
}

/* Once every camera (a synthesized one included) and light exists: their
 * nodes for the whole arrays, and their rest frames. */
static pb_result anim_finish(loader *L, struct pb_scene_anim *a) {
  pb_scene *s = L->s;
  pb_result r = PB_OK;
  if (s->camera_count) r = anim_push_node(L, &a->camera_node, &a->camera_cap, s->camera_count - 1,
                                          a->camera_cap >= s->camera_count ? a->camera_node[s->camera_count - 1] : -1);
  if (r == PB_OK && s->light_count)
    r = anim_push_node(L, &a->light_node, &a->light_cap, s->light_count - 1,
                       a->light_cap >= s->light_count ? a->light_node[s->light_count - 1] : -1);
  if (r != PB_OK) return r;
  a->camera_frame = calloc(s->camera_count + 1, sizeof *a->camera_frame);
  a->light_dir = calloc(s->light_count + 1, sizeof *a->light_dir);
  if (!a->camera_frame || !a->light_dir) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  for (uint32_t i = 0; i < s->camera_count; ++i) {
    memcpy(a->camera_frame[i], s->cameras[i].forward, 3 * sizeof(float));
    memcpy(a->camera_frame[i] + 3, s->cameras[i].up, 3 * sizeof(float));
    memcpy(a->camera_frame[i] + 6, s->cameras[i].right, 3 * sizeof(float));
  }
  for (uint32_t i = 0; i < s->light_count; ++i) memcpy(a->light_dir[i], s->lights[i].direction, 3 * sizeof(float));
  return PB_OK;
}

/* ---- meshes -------------------------------------------------------------- */

/* Records the file's TANGENT element `src` as vertex `dst` of the scene, in
 * world space: xyz by the node's 3x3 (a direction in the surface, like an
 * edge), w reduced to its sign and flipped by a mirroring transform, since
 * the world normal keeps pointing out while cross(n, t) changes orientation.
 * A non-finite or collapsed tangent is left to pb_tangents_generate. */
static pb_result store_tangent(loader *L, uint32_t dst, const pb_span *tg, uint64_t src, const mat4 *M, int flip) {
  if (dst >= L->tan_cap) {
    uint32_t old = L->tan_cap;
    pb_result r = grow(L, (void **)&L->tan, &L->tan_cap, (uint64_t)dst + 1, sizeof *L->tan, "tangents");
    if (r != PB_OK) return r;
    uint8_t *q = realloc(L->tan_given, L->tan_cap);
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for tangents", L->path);
    memset(q + old, 0, L->tan_cap - old);
    L->tan_given = q;
  }
  double tl[3] = {pb_span_f(tg, src, 0), pb_span_f(tg, src, 1), pb_span_f(tg, src, 2)}, tw[3];
  float w = pb_span_f(tg, src, 3);
  xform_dir(M, tl, tw);
  if (!isfinite(w) || !normalize3(tw)) return PB_OK;
  for (int k = 0; k < 3; ++k) L->tan[dst][k] = (float)tw[k];
  L->tan[dst][3] = ((w < 0.0f) != (flip != 0)) ? -1.0f : 1.0f;
  L->tan_given[dst] = 1;
  return PB_OK;
}

/* Cycles' default anisotropy tangent for vertex dst (local position pl) of
 * an anisotropic Blender material (pb_blender_radial_tangent), kept like a
 * file TANGENT. */
static pb_result store_radial_tangent(loader *L, uint32_t dst, const double pl[3], const double bmin[3],
                                      const double bmax[3], const double N[9]) {
  if (dst >= L->tan_cap) {
    uint32_t old = L->tan_cap;
    pb_result r = grow(L, (void **)&L->tan, &L->tan_cap, (uint64_t)dst + 1, sizeof *L->tan, "tangents");
    if (r != PB_OK) return r;
    uint8_t *q = realloc(L->tan_given, L->tan_cap);
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for tangents", L->path);
    memset(q + old, 0, L->tan_cap - old);
    L->tan_given = q;
  }
  if (!pb_blender_radial_tangent(pl, bmin, bmax, N, L->tan[dst])) return PB_OK;
  L->tan[dst][3] = 1.0f;
  L->tan_given[dst] = 1;
  return PB_OK;
}

/* The local bounds of every POSITION of glTF mesh `mesh` (Blender's texture
 * space of the mesh); from the accessors' min/max, the data where those are
 * missing. */
static void mesh_bounds(loader *L, int32_t mesh, double bmin[3], double bmax[3]) {
  const pb_gltf_mesh *me = &L->doc->meshes[mesh];
  for (int k = 0; k < 3; ++k) bmin[k] = INFINITY, bmax[k] = -INFINITY;
  for (size_t pi = 0; pi < me->primitive_count; ++pi) {
    int32_t a = me->primitives[pi].position;
    if (a < 0 || (size_t)a >= L->doc->accessor_count) continue;
    const pb_gltf_accessor *acc = &L->doc->accessors[a];
    if (acc->has_min_max) {
      for (int k = 0; k < 3; ++k) bmin[k] = fmin(bmin[k], acc->min[k]), bmax[k] = fmax(bmax[k], acc->max[k]);
      continue;
    }
    static const int32_t float_only[] = {PB_CT_FLOAT, 0};
    pb_span sp;
    if (pb_accessor_check(L->path, L->doc, a, "POSITION", 3, float_only, &sp) != PB_OK) {
      pb_error_clear(); /* add_primitive reports it */
      continue;
    }
    if (sp.count > 3 * L->desc->max_triangles) continue; /* add_primitive reports it */
    for (uint64_t i = 0; pb_span_has_data(&sp) && i < sp.count; ++i)
      for (int k = 0; k < 3; ++k) {
        double v = pb_span_f(&sp, i, k);
        if (isfinite(v)) bmin[k] = fmin(bmin[k], v), bmax[k] = fmax(bmax[k], v);
      }
  }
  for (int k = 0; k < 3; ++k)
    if (!(bmin[k] <= bmax[k])) bmin[k] = bmax[k] = 0.0;
}

/* Whether any texture of m (a Blender material's input textures included)
 * reads uv set 1. */
static int reads_uv1(const pb_scene *s, const pb_material *m) {
  int32_t t[4 + 1 + PB_IN_COUNT] = {m->base_color_tex, m->metallic_roughness_tex, m->emissive_tex, m->normal_tex};
  int n = 4;
  if (m->blender.model != PB_MODEL_GLTF) { /* the zeroed struct holds no texture */
    t[n++] = m->blender.subsurface_color_tex;
    for (int in = 0; in < PB_IN_COUNT; ++in) t[n++] = m->blender.input_tex[in].tex;
  }
  for (int k = 0; k < n; ++k)
    if (t[k] >= 0 && (uint32_t)t[k] < s->texture_count && s->textures[t[k]].texcoord == 1) return 1;
  return 0;
}

/* A vertex attribute of meshes[mesh].primitives[pi] named `name`:
 * `comps` components of the allowed types (integers normalized), with
 * POSITION's count. */
static pb_result check_attribute(loader *L, int32_t mesh, size_t pi, const char *name, int32_t acc, int comps,
                                 const int32_t *types, uint64_t count, pb_span *out) {
  char w[128];
  snprintf(w, sizeof w, "meshes[%d].primitives[%zu].attributes.%s", mesh, pi, name);
  pb_result r = pb_accessor_check(L->path, L->doc, acc, w, comps, types, out);
  if (r != PB_OK) return r;
  if (out->ct != PB_CT_FLOAT && !out->normalized)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: integer %s must be normalized", L->path, acc, name);
  if (out->count != count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d has %llu elements, POSITION has %llu", L->path, w, acc,
                   (unsigned long long)out->count, (unsigned long long)count);
  return PB_OK;
}

/* What one primitive instance writes per vertex (add_primitive). */
typedef struct prim_src {
  pb_span pos, nrm, uv, uv1, col, tng;
  int has_n, has_uv, has_uv1, has_col, use_t;
  const mat4 *M;        /* vertices are written through it (identity for a
                           deformed instance, which pb_deform_pose poses) */
  double N[9];          /* its normal matrix */
  int flip;
  struct pb_scene_anim *an; /* rigid animation: local vertices kept */
  uint32_t local, base;
  uint32_t *src_of;     /* deformed: scene vertex - base -> source vertex */
  int radial;           /* the material needs Cycles' default anisotropy
                           tangent (pb_blender_needs_tangent) ... */
  double bmin[3], bmax[3]; /* ... over the mesh's local bounds */
} prim_src;

/* Grows a per-vertex array of the scene that exists only once some
 * primitive has the attribute: `*arr` NULL until then; the vertices before
 * it get `fill`. */
static pb_result vertex_attr(loader *L, void **arr, size_t comps, const float *fill, int present) {
  pb_scene *s = L->s;
  if (!*arr && !present) return PB_OK;
  int fresh = !*arr;
  if ((uint64_t)L->vertex_cap > SIZE_MAX / (comps * sizeof(float))) /* a 32-bit host: would wrap (to 0: a free) */
    return pb_fail(PB_ERR_LIMIT, "%s: too many vertices (%u) for this machine's address space", L->path, L->vertex_cap);
  float *q = realloc(*arr, (size_t)(L->vertex_cap ? L->vertex_cap : 1) * comps * sizeof *q); /* 0 bytes would free */
  if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for vertices", L->path);
  *arr = q;
  if (fresh)
    for (uint32_t v = 0; v < s->vertex_count; ++v) memcpy(q + (size_t)v * comps, fill, comps * sizeof *fill);
  return PB_OK;
}

/* Scene vertex `dst` from source element `i`. World position and normal
 * come from the caller (the flat path computes the face normal). */
static pb_result emit_vertex(loader *L, prim_src *P, uint32_t dst, uint64_t i, const double pw[3], const double nw[3],
                             const double pl[3], const double nl[3]) {
  pb_scene *s = L->s;
  static const float white[4] = {1, 1, 1, 1};
  for (int c = 0; c < 3; ++c) s->positions[dst][c] = (float)pw[c], s->normals[dst][c] = (float)nw[c];
  if (P->an)
    for (int c = 0; c < 3; ++c)
      P->an->local_pos[P->local + (dst - P->base)][c] = (float)pl[c], P->an->local_nrm[P->local + (dst - P->base)][c] = (float)nl[c];
  float *U = s->uvs[dst];
  U[0] = P->has_uv ? pb_span_f(&P->uv, i, 0) : 0.0f;
  U[1] = P->has_uv ? pb_span_f(&P->uv, i, 1) : 0.0f;
  if (!isfinite(U[0]) || !isfinite(U[1])) U[0] = U[1] = 0;
  if (s->uvs1) {
    float *U1 = s->uvs1[dst];
    U1[0] = P->has_uv1 ? pb_span_f(&P->uv1, i, 0) : 0.0f;
    U1[1] = P->has_uv1 ? pb_span_f(&P->uv1, i, 1) : 0.0f;
    if (!isfinite(U1[0]) || !isfinite(U1[1])) U1[0] = U1[1] = 0;
  }
  if (s->colors) {
    /* COLOR_0 (glTF 2.0 3.7.2.1): linear RGB or RGBA, alpha 1 for VEC3;
     * clamped to [0, 1] (float colours may stray; a base colour is a
     * reflectance). */
    float *C = s->colors[dst];
    memcpy(C, white, sizeof white);
    if (P->has_col)
      for (int c = 0; c < (P->col.elem / pb_component_size(P->col.ct) == 4 ? 4 : 3); ++c) {
        float x = pb_span_f(&P->col, i, c);
        C[c] = isfinite(x) ? (x < 0 ? 0 : x > 1 ? 1 : x) : 0;
      }
  }
  if (P->src_of) P->src_of[dst - P->base] = (uint32_t)i;
  if (P->use_t && !P->src_of) return store_tangent(L, dst, &P->tng, i, P->M, P->flip);
  if (P->radial && !P->src_of) return store_radial_tangent(L, dst, pl, P->bmin, P->bmax, P->N);
  return PB_OK;
}

/* A deformed instance's range (deform.c keeps it), posed once with the
 * file's transforms and weights; the file's tangents go to the loader's
 * TANGENT table (finish_tangents keeps them). */
static pb_result deform_add(loader *L, int32_t node, const pb_deform_src *D, const prim_src *P, uint32_t tri_base) {
  pb_scene *s = L->s;
  pb_deform_range *R = NULL;
  pb_result r = pb_deform_add_range(L->path, &L->deform, D, node, P->src_of, P->base, s->vertex_count - P->base, tri_base,
                                    s->triangle_count - tri_base, !P->has_n, &R);
  if (r != PB_OK || !R) return r;
  if (R->tan) {
    /* The grown bytes are cleared as in store_tangent: finish_tangents reads
     * tan_given for every vertex below tan_cap, also the rigid ones before
     * this range (they were left uninitialised, read as "file tangent"). */
    uint32_t old = L->tan_cap;
    if ((r = grow(L, (void **)&L->tan, &L->tan_cap, s->vertex_count, sizeof *L->tan, "tangents")) != PB_OK) return r;
    uint8_t *q = realloc(L->tan_given, L->tan_cap ? L->tan_cap : 1); /* 0 bytes would free */
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for tangents", L->path);
    L->tan_given = q;
    memset(q + old, 0, L->tan_cap - old);
    memset(L->tan + P->base, 0, (size_t)R->vertex_count * sizeof *L->tan);
  }
  if ((r = pb_deform_pose(s, &L->deform, R, L->world, L->tan, NAN)) != PB_OK || !R->tan) return r;
  /* pb_deform_pose writes a tangent only where it normalises (w = +-1): a
   * zero or collapsed file TANGENT is left to pb_tangents_generate, as
   * store_tangent leaves a rigid one (marking the whole range kept garbage). */
  for (uint32_t v = 0; v < R->vertex_count; ++v) L->tan_given[P->base + v] = L->tan[P->base + v][3] != 0.0f;
  return PB_OK;
}

static pb_result add_primitive(loader *L, int32_t node, int32_t mesh, size_t pi, const mat4 *M) {
  pb_gltf_doc *d = L->doc;
  pb_scene *s = L->s;
  const pb_gltf_primitive *p = &d->meshes[mesh].primitives[pi];
  char w[128];
  pb_result r;
  if (p->mode != MODE_TRIANGLES && p->mode != MODE_TRIANGLE_STRIP && p->mode != MODE_TRIANGLE_FAN) {
    const char *mn = p->mode >= 0 && p->mode <= 6 ? mode_names[p->mode] : "unknown";
    return warn(L, "meshes[%d].primitives[%zu]: mode %d (%s) skipped: only triangles are rendered", mesh, pi, p->mode, mn);
  }
  if (p->position == -1)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: meshes[%d].primitives[%zu].attributes: no POSITION", L->path, mesh, pi);
  static const int32_t float_only[] = {PB_CT_FLOAT, 0};
  static const int32_t uv_types[] = {PB_CT_FLOAT, PB_CT_UBYTE, PB_CT_USHORT, 0};
  static const int32_t index_types[] = {PB_CT_UBYTE, PB_CT_USHORT, PB_CT_UINT, 0};
  prim_src P;
  memset(&P, 0, sizeof P);
  pb_span idx;
  snprintf(w, sizeof w, "meshes[%d].primitives[%zu].attributes.POSITION", mesh, pi);
  if ((r = pb_accessor_check(L->path, L->doc, p->position, w, 3, float_only, &P.pos)) != PB_OK) return r;
  uint64_t count = P.pos.count;
  int indexed = p->indices != -1;
  P.has_n = p->normal != -1, P.has_uv = p->texcoord0 != -1;
  if (P.has_n && (r = check_attribute(L, mesh, pi, "NORMAL", p->normal, 3, float_only, count, &P.nrm)) != PB_OK) return r;
  if (P.has_uv && (r = check_attribute(L, mesh, pi, "TEXCOORD_0", p->texcoord0, 2, uv_types, count, &P.uv)) != PB_OK)
    return r;
  /* TEXCOORD_1: checked whenever present, kept only when a texture reads
   * uv set 1. */
  if (p->texcoord1 != -1) {
    if ((r = check_attribute(L, mesh, pi, "TEXCOORD_1", p->texcoord1, 2, uv_types, count, &P.uv1)) != PB_OK) return r;
    P.has_uv1 = L->need_uv1;
  }
  /* COLOR_0 (glTF 2.0 3.7.2.1): VEC3 or VEC4, float or normalized UBYTE /
   * USHORT. */
  if (p->color0 != -1) {
    int32_t ca = p->color0;
    int comps = ca >= 0 && (size_t)ca < d->accessor_count && d->accessors[ca].components == 3 ? 3 : 4;
    if ((r = check_attribute(L, mesh, pi, "COLOR_0", ca, comps, uv_types, count, &P.col)) != PB_OK) return r;
    P.has_col = 1;
  }
  /* TANGENT (glTF 2.0 3.7.2.1: VEC4 float, w = +-1 the handedness): checked
   * whenever present, read only for a normal-mapped material. */
  int has_t = p->tangent != -1;
  if (has_t && (r = check_attribute(L, mesh, pi, "TANGENT", p->tangent, 4, float_only, count, &P.tng)) != PB_OK) return r;
  uint64_t nidx = count;
  if (indexed) {
    snprintf(w, sizeof w, "meshes[%d].primitives[%zu].indices", mesh, pi);
    if ((r = pb_accessor_check(L->path, L->doc, p->indices, w, 1, index_types, &idx)) != PB_OK) return r;
    nidx = idx.count;
  }
  int32_t mat;
  if (p->material != -1) {
    if (p->material < 0 || (size_t)p->material >= d->material_count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: meshes[%d].primitives[%zu].material: %d does not exist (%zu materials)",
                     L->path, mesh, pi, p->material, d->material_count);
    mat = p->material;
  } else {
    mat = default_material(L);
  }
  P.use_t = has_t && pb_span_has_data(&P.tng) && mat >= 0 && (uint32_t)mat < s->material_count &&
            s->materials[mat].normal_tex >= 0;
  P.radial = mat >= 0 && (uint32_t)mat < s->material_count && pb_blender_needs_tangent(&s->materials[mat]);
  if (P.radial) mesh_bounds(L, mesh, P.bmin, P.bmax);
  if (p->texcoord1 == -1 && reads_uv1(s, &s->materials[mat]) &&
      (r = warn(L, "meshes[%d].primitives[%zu]: its material reads TEXCOORD_1, which the primitive lacks: (0, 0) is used",
                mesh, pi)) != PB_OK)
    return r;
  if (p->variant_mapping_count &&
      (r = warn(L, "meshes[%d].primitives[%zu]: KHR_materials_variants: %zu variant mapping(s); the default material is shown",
                mesh, pi, p->variant_mapping_count)) != PB_OK)
    return r;

  /* Skin and morph targets (deform.h). */
  int32_t skin = d->nodes[node].skin;
  int skinned = skin >= 0 && (p->joint_set_count || p->weight_set_count);
  if (skin >= 0 && !skinned &&
      (r = warn(L, "nodes[%d]: skins[%d], but meshes[%d].primitives[%zu] has no JOINTS_0 / WEIGHTS_0: drawn with the node's transform",
                node, skin, mesh, pi)) != PB_OK)
    return r;
  int deformed = skinned || p->target_count;

  /* Triangle list from the mode. Limits come before any per-element work:
   * an accessor without a bufferView costs the file nothing per element. */
  uint64_t ntri = p->mode == MODE_TRIANGLES ? nidx / 3 : (nidx >= 3 ? nidx - 2 : 0);
  /* Fewer than 3 indices (or vertices) make no triangle: skipped before any
   * allocation (a primitive of 0 vertices made the vertex arrays realloc to 0
   * bytes, which frees them: fuzz_gltf found the double free that followed). */
  if (ntri == 0)
    return warn(L, "meshes[%d].primitives[%zu]: %llu %s make no triangle: primitive skipped", mesh, pi,
                (unsigned long long)nidx, indexed ? "indices" : "vertices");
  if ((uint64_t)s->triangle_count + ntri > L->desc->max_triangles)
    return pb_fail(PB_ERR_LIMIT, "%s: meshes[%d].primitives[%zu]: more than %llu triangles in the scene", L->path, mesh,
                   pi, (unsigned long long)L->desc->max_triangles);
  /* Flat normals (the glTF rule when NORMAL is absent) need 3 vertices per
   * triangle; otherwise the accessor's vertices are shared. */
  uint64_t nverts = P.has_n ? count : ntri * 3;
  if ((uint64_t)s->vertex_count + nverts > 3 * L->desc->max_triangles)
    return pb_fail(PB_ERR_LIMIT, "%s: meshes[%d].primitives[%zu]: %llu vertices is over the limit of %llu in the scene",
                   L->path, mesh, pi, (unsigned long long)nverts, (unsigned long long)(3 * L->desc->max_triangles));

  /* An accessor without a bufferView reads as zeros (glTF 2.0, 3.6.2.3): zero
   * positions or zero indices make every triangle degenerate. Within the
   * limits such a primitive is skipped before any per-element work or
   * allocation. */
  if (!pb_span_has_data(&P.pos) || (indexed && !pb_span_has_data(&idx)))
    return warn(L, "meshes[%d].primitives[%zu]: %s has no bufferView (all zeros): primitive skipped", mesh, pi,
                !pb_span_has_data(&P.pos) ? "POSITION" : "indices");

  /* The source elements are bounded like the scene's vertices before the
   * per-element loops: an indexed primitive without NORMAL makes only its
   * indexed corners count above, and a sparse POSITION without a bufferView
   * holds its count in the file at the cost of one element (2^31 of them
   * took a minute of checking). */
  if (count > 3 * L->desc->max_triangles)
    return pb_fail(PB_ERR_LIMIT, "%s: meshes[%d].primitives[%zu].attributes.POSITION: %llu elements is over the limit of %llu",
                   L->path, mesh, pi, (unsigned long long)count, (unsigned long long)(3 * L->desc->max_triangles));
  /* Vertex positions: all finite, checked once per accessor element. */
  for (uint64_t i = 0; i < count; ++i)
    for (int c = 0; c < 3; ++c)
      if (!isfinite(pb_span_f(&P.pos, i, c)))
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: POSITION element %llu is not finite (%g)", L->path,
                       p->position, (unsigned long long)i, (double)pb_span_f(&P.pos, i, c));
  if (p->mode == MODE_TRIANGLES && nidx % 3 &&
      (r = warn(L, "meshes[%d].primitives[%zu]: %llu indices is not a multiple of 3; the last %llu ignored", mesh, pi,
                (unsigned long long)nidx, (unsigned long long)(nidx % 3))) != PB_OK)
    return r;
  /* Morph targets cost 12 bytes per target, vertex and attribute (twice:
   * the source and the range, deform.h), and a target accessor without a
   * bufferView costs the file nothing: target x vertex pairs are bounded
   * like vertices, before any allocation (also keeps every product below
   * in size_t on 32-bit hosts). */
  uint64_t dverts = count > nverts ? count : nverts;
  if (p->target_count && (uint64_t)p->target_count > 3 * L->desc->max_triangles / dverts)
    return pb_fail(PB_ERR_LIMIT, "%s: meshes[%d].primitives[%zu].targets: %zu morph targets x %llu vertices is over the limit of %llu",
                   L->path, mesh, pi, p->target_count, (unsigned long long)dverts,
                   (unsigned long long)(3 * L->desc->max_triangles));
  pb_deform_src D;
  memset(&D, 0, sizeof D);
  if (deformed && (r = pb_deform_read(L->path, d, s, &L->deform, mesh, pi, skinned ? skin : -1, &P.pos,
                                      P.has_n ? &P.nrm : NULL, P.use_t ? &P.tng : NULL, &D)) != PB_OK)
    goto done;
  if ((r = grow(L, (void **)&s->positions, &L->vertex_cap, (uint64_t)s->vertex_count + nverts, sizeof *s->positions, "vertices")) != PB_OK)
    goto done;
  uint32_t vcap = L->vertex_cap ? L->vertex_cap : 1; /* never realloc to 0 bytes (that frees) */
  void *q1 = realloc(s->normals, (size_t)vcap * sizeof *s->normals);
  if (q1) s->normals = q1;
  void *q2 = q1 ? realloc(s->uvs, (size_t)vcap * sizeof *s->uvs) : NULL;
  if (q2) s->uvs = q2;
  if (!q1 || !q2) {
    r = pb_fail(PB_ERR_NOMEM, "%s: out of memory for vertices", L->path);
    goto done;
  }
  static const float zero2[2] = {0, 0}, white[4] = {1, 1, 1, 1};
  if ((r = vertex_attr(L, (void **)&s->uvs1, 2, zero2, P.has_uv1)) != PB_OK) goto done;
  if ((r = vertex_attr(L, (void **)&s->colors, 4, white, P.has_col)) != PB_OK) goto done;
  uint32_t tcap = L->triangle_cap;
  if ((r = grow(L, (void **)&s->triangles, &L->triangle_cap, (uint64_t)s->triangle_count + ntri, sizeof *s->triangles, "triangles")) != PB_OK)
    goto done;
  if (L->triangle_cap != tcap) {
    void *q = realloc(s->triangle_material, (size_t)L->triangle_cap * sizeof *s->triangle_material);
    if (!q) {
      r = pb_fail(PB_ERR_NOMEM, "%s: out of memory for triangles", L->path);
      goto done;
    }
    s->triangle_material = q;
  }

  /* Under an animated node the local-space vertices of a rigid instance are
   * kept for posing (anim.h); a deformed one keeps its own (deform.h) and is
   * written in mesh space here, then posed. */
  mat4 I;
  memset(&I, 0, sizeof I);
  I.m[0] = I.m[5] = I.m[10] = I.m[15] = 1;
  P.M = deformed ? &I : M;
  P.an = !deformed && L->anim && L->anim->nodes[node].animated ? L->anim : NULL;
  if (P.an) {
    if ((r = anim_reserve(L, P.an, nverts)) != PB_OK) goto done;
    P.local = P.an->local_count;
  }
  if (deformed && !(P.src_of = malloc((size_t)(nverts ? nverts : 1) * sizeof *P.src_of))) {
    r = pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
    goto done;
  }
  /* A mirroring transform reverses the winding. */
  P.flip = skinned ? pb_deform_src_mirrors(&L->deform, &D, node, &L->world[node]) : det3(M) < 0;
  normal_matrix(P.M, P.N);
  P.base = s->vertex_count;
  uint32_t tri_base = s->triangle_count;
  uint64_t dropped = 0;
  if (P.has_n) {
    for (uint64_t i = 0; i < count; ++i) {
      double pl[3] = {pb_span_f(&P.pos, i, 0), pb_span_f(&P.pos, i, 1), pb_span_f(&P.pos, i, 2)}, pw[3];
      xform_point(P.M, pl, pw);
      if (!fits_float3(pw)) {
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: transform takes accessors[%d] POSITION element %llu out of float range",
                    L->path, node, p->position, (unsigned long long)i);
        goto done;
      }
      double nl[3] = {pb_span_f(&P.nrm, i, 0), pb_span_f(&P.nrm, i, 1), pb_span_f(&P.nrm, i, 2)}, nw[3];
      for (int rr = 0; rr < 3; ++rr) nw[rr] = P.N[rr] * nl[0] + P.N[3 + rr] * nl[1] + P.N[6 + rr] * nl[2];
      if (!normalize3(nw)) nw[0] = nw[1] = 0, nw[2] = 0; /* fixed below from the face */
      if ((r = emit_vertex(L, &P, P.base + (uint32_t)i, i, pw, nw, pl, nl)) != PB_OK) goto done;
    }
    s->vertex_count += (uint32_t)count;
  }
  for (uint64_t t = 0; t < ntri; ++t) {
    uint64_t k[3];
    if (p->mode == MODE_TRIANGLES) k[0] = 3 * t, k[1] = 3 * t + 1, k[2] = 3 * t + 2;
    else if (p->mode == MODE_TRIANGLE_STRIP) k[0] = t + (t & 1), k[1] = t + 1 - (t & 1), k[2] = t + 2;
    else k[0] = t + 1, k[1] = t + 2, k[2] = 0;
    uint32_t v[3];
    for (int c = 0; c < 3; ++c) {
      uint64_t vi = indexed ? pb_span_u(&idx, k[c], 0) : k[c];
      if (vi >= count) {
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: index %llu at element %llu is out of range (%llu vertices)",
                    L->path, p->indices, (unsigned long long)vi, (unsigned long long)k[c], (unsigned long long)count);
        goto done;
      }
      v[c] = (uint32_t)vi;
    }
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
      dropped++;
      continue;
    }
    if (P.flip) {
      uint32_t tmp = v[1];
      v[1] = v[2];
      v[2] = tmp;
    }
    uint32_t out[3];
    if (P.has_n) {
      for (int c = 0; c < 3; ++c) out[c] = P.base + v[c];
    } else {
      double pl[3][3], pw[3][3];
      for (int c = 0; c < 3; ++c) {
        for (int a = 0; a < 3; ++a) pl[c][a] = pb_span_f(&P.pos, v[c], a);
        xform_point(P.M, pl[c], pw[c]);
        if (!fits_float3(pw[c])) {
          r = pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: transform takes accessors[%d] POSITION element %u out of float range",
                      L->path, node, p->position, v[c]);
          goto done;
        }
      }
      double e1[3] = {pw[1][0] - pw[0][0], pw[1][1] - pw[0][1], pw[1][2] - pw[0][2]};
      double e2[3] = {pw[2][0] - pw[0][0], pw[2][1] - pw[0][1], pw[2][2] - pw[0][2]};
      double fn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      if (!normalize3(fn)) fn[0] = 0, fn[1] = 0, fn[2] = 1; /* zero area: any unit normal */
      static const double none[3] = {0, 0, 0};
      for (int c = 0; c < 3; ++c) {
        uint32_t o = s->vertex_count++;
        if ((r = emit_vertex(L, &P, o, v[c], pw[c], fn, pl[c], none)) != PB_OK) goto done;
        out[c] = o;
      }
    }
    uint32_t tri = s->triangle_count++;
    memcpy(s->triangles[tri], out, sizeof out);
    s->triangle_material[tri] = (uint32_t)mat;
  }
  /* Zero normals in the file (or collapsed by a degenerate transform): use the
   * face normal of a triangle that uses the vertex. */
  if (P.has_n)
    for (uint32_t t = tri_base; t < s->triangle_count; ++t)
      for (int c = 0; c < 3; ++c) {
        uint32_t vi = s->triangles[t][c];
        float *Nn = s->normals[vi];
        if (Nn[0] == 0 && Nn[1] == 0 && Nn[2] == 0) {
          const float *a = s->positions[s->triangles[t][0]], *b = s->positions[s->triangles[t][1]],
                      *cc = s->positions[s->triangles[t][2]];
          double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]};
          double fn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
          if (!normalize3(fn)) fn[0] = 0, fn[1] = 0, fn[2] = 1;
          for (int a2 = 0; a2 < 3; ++a2) Nn[a2] = (float)fn[a2];
        }
      }
  struct pb_scene_anim *an = P.an;
  if (an && s->vertex_count > P.base) {
    if (an->range_count == an->range_cap) {
      uint32_t c = an->range_cap ? 2 * an->range_cap : 16;
      void *q = realloc(an->ranges, (size_t)c * sizeof *an->ranges);
      if (!q) {
        r = pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
        goto done;
      }
      an->ranges = q;
      an->range_cap = c;
    }
    an->ranges[an->range_count++] = (pb_anim_range){.node = node, .first_vertex = P.base, .vertex_count = s->vertex_count - P.base,
                                                    .first_tri = tri_base, .tri_count = s->triangle_count - tri_base,
                                                    .local = P.local, .flat = !P.has_n};
    an->local_count += s->vertex_count - P.base;
  }
  if (deformed && (r = deform_add(L, node, &D, &P, tri_base)) != PB_OK) goto done;
  if (dropped)
    r = warn(L, "meshes[%d].primitives[%zu]: %llu degenerate triangles (repeated index) dropped", mesh, pi,
             (unsigned long long)dropped);
done:
  pb_deform_src_free(&D);
  free(P.src_of);
  return r;
}

/* ---- cameras and lights -------------------------------------------------- */

static pb_result add_camera(loader *L, int32_t node, const mat4 *M) {
  pb_gltf_doc *d = L->doc;
  int32_t ci = d->nodes[node].camera;
  if (ci < 0 || (size_t)ci >= d->camera_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d].camera: %d does not exist (%zu cameras)", L->path, node, ci,
                   d->camera_count);
  const pb_gltf_camera *c = &d->cameras[ci];
  if (!c->perspective && !c->orthographic && !c->blender.present)
    return warn(L, "cameras[%d]: type '%s' skipped: only perspective and orthographic cameras are supported", ci,
                c->type);
  pb_camera proj;
  pb_result r = pb_camera_projection_from_gltf(L->path, ci, c, &proj);
  if (r != PB_OK) return r;
  double o[3] = {0, 0, 0}, pos[3], f[3], u[3];
  double fz[3] = {0, 0, -1}, uy[3] = {0, 1, 0};
  xform_point(M, o, pos);
  xform_dir(M, fz, f);
  xform_dir(M, uy, u);
  if (!fits_float3(pos))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: camera position is out of float range", L->path, node);
  if (!normalize3(f))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: camera transform is degenerate", L->path, node);
  /* Orthonormalise (Gram-Schmidt) so a sheared or scaled node still gives a
   * proper camera frame. */
  double dp = u[0] * f[0] + u[1] * f[1] + u[2] * f[2];
  for (int k = 0; k < 3; ++k) u[k] -= dp * f[k];
  if (!normalize3(u))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: camera transform is degenerate", L->path, node);
  pb_scene *s = L->s;
  r = grow(L, (void **)&s->cameras, &L->camera_cap, (uint64_t)s->camera_count + 1, sizeof *s->cameras, "cameras");
  if (r != PB_OK) return r;
  pb_camera *cam = &s->cameras[s->camera_count++];
  *cam = proj;
  copy_name(cam->name, d->nodes[node].name, c->name);
  if (!cam->name[0]) snprintf(cam->name, PB_NAME_MAX, "cameras[%d]", ci);
  for (int k = 0; k < 3; ++k) cam->position[k] = (float)pos[k], cam->forward[k] = (float)f[k], cam->up[k] = (float)u[k];
  cam->right[0] = (float)(f[1] * u[2] - f[2] * u[1]);
  cam->right[1] = (float)(f[2] * u[0] - f[0] * u[2]);
  cam->right[2] = (float)(f[0] * u[1] - f[1] * u[0]);
  return PB_OK;
}

static pb_result add_light(loader *L, int32_t node, const mat4 *M) {
  pb_gltf_doc *d = L->doc;
  int32_t li = d->nodes[node].light;
  if (li == -2)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d].extensions.KHR_lights_punctual.light: missing or not a light index",
                   L->path, node);
  if (li < 0 || (size_t)li >= d->light_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d].extensions.KHR_lights_punctual.light: %d does not exist (%zu lights)",
                   L->path, node, li, d->light_count);
  const pb_gltf_light *g = &d->lights[li];
  pb_light_type type;
  if (strcmp(g->type, "point") == 0) type = PB_LIGHT_POINT;
  else if (strcmp(g->type, "spot") == 0) type = PB_LIGHT_SPOT;
  else if (strcmp(g->type, "directional") == 0) type = PB_LIGHT_DIRECTIONAL;
  else return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensions.KHR_lights_punctual.lights[%d].type: '%s' is not point, spot or directional",
                      L->path, li, g->type);
  if (!fits_float(g->intensity) || g->intensity < 0)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensions.KHR_lights_punctual.lights[%d].intensity: %g is not a non-negative float",
                   L->path, li, g->intensity);
  for (int k = 0; k < 3; ++k)
    if (!fits_float(g->color[k]) || g->color[k] < 0)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensions.KHR_lights_punctual.lights[%d].color[%d]: %g is not a non-negative float",
                     L->path, li, k, g->color[k]);
  if (!fits_float(g->range) || g->range < 0)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: extensions.KHR_lights_punctual.lights[%d].range: %g is not a non-negative float", L->path, li, g->range);
  if (type == PB_LIGHT_SPOT && !(g->inner_cone >= 0 && g->inner_cone <= g->outer_cone && g->outer_cone > 0 &&
                                 g->outer_cone <= M_PI / 2 + 1e-6))
    return pb_fail(PB_ERR_SCENE_INVALID,
                   "%s: extensions.KHR_lights_punctual.lights[%d].spot: need 0 <= innerConeAngle (%g) < outerConeAngle (%g) <= pi/2",
                   L->path, li, g->inner_cone, g->outer_cone);
  /* Blender writes a spot of blend 0 as innerConeAngle = outerConeAngle
   * (inner = outer (1 - blend)), which glTF's schema forbids (inner <
   * outer) but which means what Cycles draws: a hard-edged cone. Every
   * renderer's falloff is a step when the two are equal (pb_spot_falloff). */
  pb_result wr;
  if (type == PB_LIGHT_SPOT && g->inner_cone == g->outer_cone &&
      (wr = warn(L, "extensions.KHR_lights_punctual.lights[%d].spot: innerConeAngle = outerConeAngle (%g, Blender's spot blend 0): a hard-edged spot",
                 li, g->outer_cone)) != PB_OK)
    return wr;
  double o[3] = {0, 0, 0}, pos[3], dir[3], fz[3] = {0, 0, -1};
  xform_point(M, o, pos);
  xform_dir(M, fz, dir);
  if (!fits_float3(pos))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: light position is out of float range", L->path, node);
  if (type != PB_LIGHT_POINT && !normalize3(dir))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: light transform is degenerate", L->path, node);
  pb_scene *s = L->s;
  pb_result r = grow(L, (void **)&s->lights, &L->light_cap, (uint64_t)s->light_count + 1, sizeof *s->lights, "lights");
  if (r != PB_OK) return r;
  pb_light *l = &s->lights[s->light_count++];
  memset(l, 0, sizeof *l);
  copy_name(l->name, d->nodes[node].name, g->name);
  if (!l->name[0]) snprintf(l->name, PB_NAME_MAX, "lights[%d]", li);
  l->type = type;
  for (int k = 0; k < 3; ++k) l->position[k] = (float)pos[k], l->direction[k] = (float)dir[k], l->color[k] = (float)g->color[k];
  if (type == PB_LIGHT_POINT) l->direction[0] = l->direction[1] = 0, l->direction[2] = -1;
  l->file_intensity = (float)g->intensity;
  /* shared/VALIDATION.md: standard = photometric (cd, lx): W = lm / 683;
   * Blender's unitless mode writes W/(4 pi) (point, spot) and W/m^2 (sun). */
  l->intensity = (float)(L->desc->light_units == PB_LIGHT_UNITS_UNITLESS ? g->intensity : g->intensity / PB_LUMENS_PER_WATT);
  l->inner_cone = type == PB_LIGHT_SPOT ? (float)g->inner_cone : 0;
  l->outer_cone = type == PB_LIGHT_SPOT ? (float)g->outer_cone : 0;
  l->range = (float)g->range;
  return PB_OK;
}

/* ---- node graph ---------------------------------------------------------- */

/* The node graph must be a forest: every child index valid, no node with two
 * parents, no cycle (a cycle also shows up as a second parent, or as a root
 * that is someone's child). */
static pb_result check_nodes(loader *L) {
  pb_gltf_doc *d = L->doc;
  for (size_t i = 0; i < d->node_count; ++i) L->parent[i] = -1;
  for (size_t i = 0; i < d->node_count; ++i) {
    const pb_gltf_node *n = &d->nodes[i];
    for (size_t c = 0; c < n->child_count; ++c) {
      int32_t ch = n->children[c];
      if (ch < 0 || (size_t)ch >= d->node_count)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu].children[%zu]: node %d does not exist (%zu nodes)", L->path,
                       i, c, ch, d->node_count);
      if ((size_t)ch == i)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu].children[%zu]: a node cannot be its own child", L->path, i, c);
      if (L->parent[ch] >= 0)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu].children[%zu]: node %d already has parent nodes[%d] (the node graph must be a tree)",
                       L->path, i, c, ch, L->parent[ch]);
      L->parent[ch] = (int32_t)i;
    }
    if (!n->has_matrix) {
      for (int k = 0; k < 3; ++k)
        if (!isfinite(n->translation[k]) || !isfinite(n->scale[k]))
          return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu]: translation or scale is not finite", L->path, i);
      for (int k = 0; k < 4; ++k)
        if (!isfinite(n->rotation[k]))
          return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu].rotation: not finite", L->path, i);
    }
  }
  /* With one parent each, a cycle is a loop of parents: walk up from each
   * node until a node already known to reach a root (state 2); meeting a
   * node of the current walk (state 1) is a cycle. Linear in the node count,
   * so a long chain cannot stall us. node_state is left zeroed for visit(). */
  uint8_t *st = L->node_state;
  pb_result r = PB_OK;
  for (size_t i = 0; i < d->node_count && r == PB_OK; ++i) {
    int32_t p = (int32_t)i;
    while (p >= 0 && st[p] == 0) {
      st[p] = 1;
      p = L->parent[p];
    }
    if (p >= 0 && st[p] == 1)
      r = pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: cycle in the node graph", L->path, p);
    for (int32_t q = (int32_t)i; q >= 0 && st[q] == 1; q = L->parent[q]) st[q] = 2;
  }
  memset(st, 0, d->node_count);
  return r;
}

static pb_result visit(loader *L, int32_t node, const mat4 *parent, int depth) {
  pb_gltf_doc *d = L->doc;
  if (depth > MAX_NODE_DEPTH)
    return pb_fail(PB_ERR_LIMIT, "%s: nodes[%d]: node tree deeper than %d", L->path, node, MAX_NODE_DEPTH);
  if (L->node_state[node])
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: reached twice (listed in a scene and as a child?)", L->path, node);
  L->node_state[node] = 1;
  const pb_gltf_node *n = &d->nodes[node];
  struct pb_scene_anim *an = L->anim;
  if (an) an->order[an->order_count++] = node;
  mat4 local = node_local(n);
  mat4 M = mat_mul(parent, &local);
  if (!finite_mat(&M))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: transform is not finite", L->path, node);
  pb_result r = PB_OK;
  if (n->skin != -1 && (n->skin < 0 || (size_t)n->skin >= d->skin_count))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d].skin: %d does not exist (%zu skins)", L->path, node, n->skin, d->skin_count);
  if (n->skin >= 0 && n->mesh == -1 &&
      (r = warn(L, "nodes[%d]: skin %d but no mesh; the skin is unused", node, n->skin)) != PB_OK)
    return r;
  if (n->mesh != -1) {
    if (n->mesh < 0 || (size_t)n->mesh >= d->mesh_count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d].mesh: %d does not exist (%zu meshes)", L->path, node, n->mesh,
                     d->mesh_count);
    for (size_t pi = 0; pi < d->meshes[n->mesh].primitive_count; ++pi)
      if ((r = add_primitive(L, node, n->mesh, pi, &M)) != PB_OK) return r;
  }
  uint32_t nc = L->s->camera_count, nl = L->s->light_count;
  if (n->camera != -1 && (r = add_camera(L, node, &M)) != PB_OK) return r;
  /* PHOTONBRIDGE_blender's light replaces the node's KHR_lights_punctual
   * approximation of it (never both: no light counted twice). */
  int blender_light = 0;
  if (n->blender) {
    pb_light bl;
    if ((r = pb_blender_read_light(L->path, node, n->name, n->blender, &M, &bl, &blender_light)) != PB_OK) return r;
    if (blender_light) {
      if ((r = grow(L, (void **)&L->s->lights, &L->light_cap, (uint64_t)L->s->light_count + 1, sizeof *L->s->lights,
                    "lights")) != PB_OK)
        return r;
      L->s->lights[L->s->light_count++] = bl;
    }
  }
  if (!blender_light && n->light != -1 && (r = add_light(L, node, &M)) != PB_OK) return r;
  if (an && L->s->camera_count > nc && (r = anim_push_node(L, &an->camera_node, &an->camera_cap, nc, node)) != PB_OK) return r;
  if (an && L->s->light_count > nl && (r = anim_push_node(L, &an->light_node, &an->light_cap, nl, node)) != PB_OK) return r;
  for (size_t c = 0; c < n->child_count; ++c)
    if ((r = visit(L, n->children[c], &M, depth + 1)) != PB_OK) return r;
  return PB_OK;
}

/* ---- precision origin ---------------------------------------------------
 * Blender writes an object's location as its node's translation, so a scene
 * modelled far from the world origin (survey coordinates, a level at 1e5 m)
 * has world positions whose float spacing (1e5 m: 8 mm) moves edges and
 * defeats ray offsets. The world box of the mesh accessors' min/max (glTF
 * requires them on POSITION; when a primitive lacks them the scene is left
 * where it is) is found first, in double; when its centre lies more than
 * PRECISION_FAR box radii from the world origin, every world point (vertices,
 * cameras, lights) is computed relative to that centre, which scene.origin
 * records. Nothing is read here that visit() does not check again. */
enum { PRECISION_FAR = 8 };

static void extent_add(double box[6], const double p[3]) {
  for (int k = 0; k < 3; ++k) {
    if (p[k] < box[k]) box[k] = p[k];
    if (p[k] > box[3 + k]) box[3 + k] = p[k];
  }
}

static void world_extent(loader *L, int32_t node, const mat4 *parent, int depth, double box[6], int *unknown) {
  pb_gltf_doc *d = L->doc;
  if (depth > MAX_NODE_DEPTH || node < 0 || (size_t)node >= d->node_count) return;
  const pb_gltf_node *n = &d->nodes[node];
  mat4 local = node_local(n);
  mat4 M = mat_mul(parent, &local);
  if (!finite_mat(&M)) return;
  if (n->mesh >= 0 && (size_t)n->mesh < d->mesh_count) {
    const pb_gltf_mesh *m = &d->meshes[n->mesh];
    /* A skinned mesh ignores its node's transform: its bind pose maps
     * through the first joint (L->world holds the origin-free rest worlds
     * here, load()). */
    mat4 B = M;
    if (n->skin >= 0 && (uint32_t)n->skin < L->deform.skin_count) {
      const pb_skin *k = &L->deform.skins[n->skin];
      B = mat_mul(&L->world[k->joints[0]], &k->ibm[0]);
    }
    for (size_t pi = 0; pi < m->primitive_count; ++pi) {
      int32_t a = m->primitives[pi].position;
      double w[3];
      if (a >= 0 && (size_t)a < d->accessor_count && d->accessors[a].has_min_max) {
        const pb_gltf_accessor *ac = &d->accessors[a];
        for (int c = 0; c < 8; ++c) {
          double p[3] = {(c & 1) ? ac->max[0] : ac->min[0], (c & 2) ? ac->max[1] : ac->min[1],
                         (c & 4) ? ac->max[2] : ac->min[2]};
          xform_point(&B, p, w);
          if (isfinite(w[0]) && isfinite(w[1]) && isfinite(w[2])) extent_add(box, w);
        }
      } else {
        *unknown = 1;
      }
    }
  }
  for (size_t c = 0; c < n->child_count; ++c) world_extent(L, n->children[c], &M, depth + 1, box, unknown);
}

/* The translation every world point gets: -origin, or none. */
static void precision_origin(loader *L, const int32_t *roots, size_t count, double origin[3]) {
  mat4 I;
  memset(&I, 0, sizeof I);
  I.m[0] = I.m[5] = I.m[10] = I.m[15] = 1;
  double box[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
  int unknown = 0;
  for (size_t i = 0; i < count; ++i) world_extent(L, roots[i], &I, 0, box, &unknown);
  origin[0] = origin[1] = origin[2] = 0;
  if (unknown || !(box[0] <= box[3])) return;
  double c[3], r2 = 0, far = 0;
  for (int k = 0; k < 3; ++k) {
    c[k] = 0.5 * (box[k] + box[3 + k]);
    double e = 0.5 * (box[3 + k] - box[k]);
    r2 += e * e;
    if (fabs(c[k]) > far) far = fabs(c[k]);
  }
  if (r2 > 0 && far > PRECISION_FAR * sqrt(r2))
    for (int k = 0; k < 3; ++k) origin[k] = c[k];
}

/* A camera framing the whole scene, for files without one: 50 degrees
 * vertical field of view, looking at the bounds' centre from the front (+Z)
 * and a little above, far enough for the bounding sphere to fit. */
static pb_result synthesize_camera(loader *L) {
  pb_scene *s = L->s;
  /* In double: the bounds of a scene that fits in float may not (a 1e20 m
   * box's squared radius overflows float, found by fuzz_gltf). */
  const float yfov = 50.0f * (float)M_PI / 180.0f;
  double ctr[3], rad = 0;
  for (int k = 0; k < 3; ++k) {
    ctr[k] = 0.5 * ((double)s->bounds_min[k] + s->bounds_max[k]);
    double e = 0.5 * ((double)s->bounds_max[k] - s->bounds_min[k]);
    rad += e * e;
  }
  rad = sqrt(rad);
  if (!(rad > 0)) rad = 1;
  double dist = 1.1 * rad / sin(0.5 * yfov);
  double f[3] = {0, -0.25, -1}, pos[3];
  normalize3(f);
  for (int k = 0; k < 3; ++k) pos[k] = ctr[k] - dist * f[k];
  if (!fits_float3(pos))
    return pb_fail(PB_ERR_LIMIT, "%s: cameras: none, and the scene (%g across) is too large to frame with a default camera",
                   L->path, 2 * rad);
  pb_result r = grow(L, (void **)&s->cameras, &L->camera_cap, 1, sizeof *s->cameras, "cameras");
  if (r != PB_OK) return r;
  pb_camera *c = &s->cameras[0];
  memset(c, 0, sizeof *c);
  snprintf(c->name, PB_NAME_MAX, "default");
  c->synthesized = 1;
  c->yfov = yfov; /* no clip planes: it frames the bounds whatever their size */
  for (int k = 0; k < 3; ++k) {
    c->forward[k] = (float)f[k];
    c->position[k] = (float)pos[k];
  }
  /* up = orthonormalised +Y, right = forward x up */
  double u[3] = {0, 1, 0}, dp = f[1];
  for (int k = 0; k < 3; ++k) u[k] -= dp * f[k];
  normalize3(u);
  for (int k = 0; k < 3; ++k) c->up[k] = (float)u[k];
  c->right[0] = (float)(f[1] * u[2] - f[2] * u[1]);
  c->right[1] = (float)(f[2] * u[0] - f[0] * u[2]);
  c->right[2] = (float)(f[0] * u[1] - f[1] * u[0]);
  s->camera_count = 1;
  return PB_OK;
}

/* Every node's world matrix in the file's pose, parents first (iterative:
 * a chain of nodes may be deeper than visit() allows, and the nodes outside
 * the shown scene count too: joints may be among them). `root` is the
 * roots' parent (the precision origin's translation). */
static pb_result rest_worlds(loader *L, const mat4 *root) {
  pb_gltf_doc *d = L->doc;
  if (!L->world) L->world = malloc((d->node_count + 1) * sizeof *L->world);
  int32_t *stack = malloc((d->node_count + 1) * sizeof *stack);
  if (!L->world || !stack) {
    free(stack);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  }
  for (size_t n = 0; n < d->node_count; ++n) {
    if (L->parent[n] >= 0) continue;
    size_t top = 0;
    stack[top++] = (int32_t)n;
    while (top) {
      int32_t k = stack[--top];
      mat4 local = node_local(&d->nodes[k]);
      L->world[k] = mat_mul(L->parent[k] >= 0 ? &L->world[L->parent[k]] : root, &local);
      /* A forest (check_nodes): each node is pushed once, so top stays
       * below node_count. */
      for (size_t c = 0; c < d->nodes[k].child_count; ++c) stack[top++] = d->nodes[k].children[c];
    }
  }
  free(stack);
  pb_skins_update(&L->deform, L->world);
  return PB_OK;
}

/* After visit(): a scene with animation keeps the instances that move
 * (dynamic: an animated joint or mesh node, or animated weights) with the nodes visit() did not reach appended to the pose order
 * (joints outside the shown scene); everything else was posed once. */
static pb_result deform_finish(loader *L) {
  pb_scene *s = L->s;
  pb_deform *df = &L->deform;
  struct pb_scene_anim *an = L->anim;
  s->skinned_vertex_count = df->skinned_vertices;
  s->morphed_vertex_count = df->morphed_vertices;
  uint32_t dynamic = 0;
  for (uint32_t i = 0; an && i < df->range_count; ++i) {
    pb_deform_range *R = &df->ranges[i];
    /* The mesh node counts for a skinned instance too: its vertices
     * without weight follow it (skin.c). */
    int moves = an->nodes[R->node].animated;
    if (R->target_count && an->nodes[R->node].weights_animated) moves = 1;
    for (uint32_t j = 0; R->skin >= 0 && j < df->skins[R->skin].joint_count; ++j)
      if (an->nodes[df->skins[R->skin].joints[j]].animated) moves = 1;
    R->dynamic = moves;
    dynamic += (uint32_t)moves;
    s->posed_vertex_count += moves ? R->vertex_count : 0;
  }
  if (!dynamic) {
    pb_deform_destroy(df);
    return PB_OK;
  }
  /* The pose order: visit()'s, then every node it did not reach, parents
   * first (node_state marks the visited ones). */
  pb_gltf_doc *d = L->doc;
  for (size_t n = 0; n < d->node_count; ++n) {
    if (L->node_state[n] || L->parent[n] >= 0) continue;
    size_t first = an->order_count;
    an->order[an->order_count++] = (int32_t)n;
    for (size_t k = first; k < an->order_count; ++k) {
      const pb_gltf_node *g = &d->nodes[an->order[k]];
      for (size_t c = 0; c < g->child_count; ++c) an->order[an->order_count++] = g->children[c];
    }
  }
  an->deform = malloc(sizeof *an->deform);
  if (!an->deform) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  *an->deform = *df; /* the anim owns it from here */
  memset(df, 0, sizeof *df);
  for (uint32_t i = 0; i < an->deform->range_count; ++i) {
    const pb_deform_range *R = &an->deform->ranges[i];
    if (!R->tan) continue;
    if (!an->tan_given && !(an->tan_given = calloc(s->vertex_count + 1, 1)))
      return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
    memset(an->tan_given + R->first_vertex, 1, R->vertex_count);
  }
  return PB_OK;
}

/* Tangent frames for normal maps: only scenes with PB_FEATURE_NORMAL_MAPS
 * get s->tangents (the others pay nothing). The file's TANGENTs are kept,
 * every other vertex gets one from its uvs (tangents.c). */
static pb_result finish_tangents(loader *L) {
  pb_scene *s = L->s;
  if (!(s->features & (PB_FEATURE_NORMAL_MAPS | PB_FEATURE_ANISOTROPY)) || s->vertex_count == 0) return PB_OK;
  s->tangents = calloc(s->vertex_count, sizeof *s->tangents);
  uint8_t *given = calloc(s->vertex_count, 1);
  if (!s->tangents || !given) {
    free(given);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory for tangents", L->path);
  }
  for (uint32_t v = 0; v < s->vertex_count && v < L->tan_cap; ++v)
    if (L->tan_given[v]) {
      memcpy(s->tangents[v], L->tan[v], sizeof s->tangents[v]);
      given[v] = 1;
    }
  pb_result r = pb_tangents_generate((const float(*)[3])s->positions, (const float(*)[3])s->normals,
                                     (const float(*)[2])s->uvs, s->vertex_count,
                                     (const uint32_t(*)[3])s->triangles, s->triangle_count, given, s->tangents);
  free(given);
  return r;
}

static pb_result load(loader *L) {
  pb_gltf_doc *d = L->doc;
  pb_scene *s = L->s;
  pb_result r;
  /* Materials first (textures are decoded only when a material uses them),
   * with room for glTF's default material. */
  s->materials = calloc(d->material_count + 1, sizeof *s->materials);
  L->image_cache = calloc(d->image_count + 1, sizeof *L->image_cache);
  L->image_cache_f = calloc(d->image_count + 1, sizeof *L->image_cache_f);
  L->image_linear = calloc(d->image_count + 1, sizeof *L->image_linear);
  L->image_w = calloc(d->image_count + 1, sizeof *L->image_w);
  L->image_h = calloc(d->image_count + 1, sizeof *L->image_h);
  L->node_state = calloc(d->node_count + 1, 1);
  L->parent = malloc((d->node_count + 1) * sizeof *L->parent);
  if (!s->materials || !L->image_cache || !L->image_cache_f || !L->image_linear || !L->image_w || !L->image_h || !L->node_state || !L->parent)
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  for (size_t i = 0; i < d->material_count; ++i) {
    if ((r = convert_material(L, (int)i, &s->materials[i])) != PB_OK) return r;
    s->material_count++;
  }
  if ((r = check_nodes(L)) != PB_OK) return r;
  if ((r = pb_skins_load(L->path, d, &L->deform)) != PB_OK) return r;
  if ((r = pb_morph_weights_load(L->path, d, &L->deform)) != PB_OK) return r;
  if ((r = build_anim(L)) != PB_OK) return r;
  /* PHOTONBRIDGE_blender's root: film and world (blender_lights.c). */
  if (d->blender && (r = pb_blender_read_root(L->path, L->dir, d->blender, L->desc, s)) != PB_OK) return r;

  /* The scene to show: `scene`, else scenes[0], else every root node. */
  mat4 I;
  memset(&I, 0, sizeof I);
  I.m[0] = I.m[5] = I.m[10] = I.m[15] = 1;
  /* The rest worlds without the precision origin first: the origin's
   * estimate reads skinned meshes through their joints. */
  if ((r = rest_worlds(L, &I)) != PB_OK) return r;
  if (d->default_scene != -1 && (d->default_scene < 0 || (size_t)d->default_scene >= d->scene_count))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: scene: %d does not exist (%zu scenes)", L->path, d->default_scene, d->scene_count);
  if (d->scene_count > 0) {
    int32_t si = d->default_scene != -1 ? d->default_scene : 0;
    const pb_gltf_scene *sc = &d->scenes[si];
    precision_origin(L, sc->nodes, sc->node_count, s->origin);
    I.m[12] = -s->origin[0], I.m[13] = -s->origin[1], I.m[14] = -s->origin[2];
    if ((r = rest_worlds(L, &I)) != PB_OK) return r;
    for (size_t i = 0; i < sc->node_count; ++i) {
      int32_t n = sc->nodes[i];
      if (n < 0 || (size_t)n >= d->node_count)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: scenes[%d].nodes[%zu]: node %d does not exist (%zu nodes)", L->path, si, i,
                       n, d->node_count);
      if (L->parent[n] >= 0)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: scenes[%d].nodes[%zu]: node %d is not a root (it is a child of nodes[%d])",
                       L->path, si, i, n, L->parent[n]);
      if ((r = visit(L, n, &I, 0)) != PB_OK) return r;
    }
  } else {
    if (d->node_count && (r = warn(L, "scenes: none; every root node is shown")) != PB_OK) return r;
    int32_t *roots = malloc((d->node_count + 1) * sizeof *roots);
    if (!roots) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
    size_t nr = 0;
    for (size_t n = 0; n < d->node_count; ++n)
      if (L->parent[n] < 0) roots[nr++] = (int32_t)n;
    precision_origin(L, roots, nr, s->origin);
    free(roots);
    I.m[12] = -s->origin[0], I.m[13] = -s->origin[1], I.m[14] = -s->origin[2];
    if ((r = rest_worlds(L, &I)) != PB_OK) return r;
    for (size_t n = 0; n < d->node_count; ++n)
      if (L->parent[n] < 0 && (r = visit(L, (int32_t)n, &I, 0)) != PB_OK) return r;
  }
  if ((r = deform_finish(L)) != PB_OK) return r;
  s->animation_count = (uint32_t)d->animation_count;
  s->animation_channel_count = (uint32_t)d->animation_channel_count;
  for (size_t i = 0; i < d->extensions_used_count; ++i) {
    const char *e = d->extensions_used[i];
    static const char *const known[] = {"KHR_lights_punctual", "KHR_materials_specular", "KHR_materials_transmission",
                                        "KHR_materials_ior", "KHR_materials_emissive_strength", "KHR_texture_transform",
                                        "KHR_materials_unlit", "KHR_materials_volume", "KHR_materials_variants",
                                        "PHOTONBRIDGE_blender"};
    int ok = 0;
    for (size_t k = 0; k < sizeof known / sizeof *known; ++k) ok |= strcmp(e, known[k]) == 0;
    if (!ok && (r = warn(L, "extensionsUsed[%zu]: '%s' is ignored", i, e)) != PB_OK) return r;
  }
  struct pb_scene_anim *an = L->anim;
  if (an) { /* s owns it from here */
    s->anim = an;
    L->anim = NULL;
    anim_range(an, &s->anim_start, &s->anim_end);
  }
  pb_scene_finalize(s);
  if ((r = finish_tangents(L)) != PB_OK) return r;
  if (s->camera_count == 0) {
    if ((r = synthesize_camera(L)) != PB_OK) return r;
    if ((r = warn(L, "cameras: none in the scene; using a default camera framing the bounds")) != PB_OK) return r;
  }
  if (an && (r = anim_finish(L, an)) != PB_OK) return r;
  if (s->triangle_count == 0 && (r = warn(L, "meshes: no triangles to render")) != PB_OK) return r;
  if (s->light_count == 0 && !(s->features & (PB_FEATURE_EMISSIVE | PB_FEATURE_UNLIT)) && !s->world.present &&
      (r = warn(L, "lights: none, no world and no emissive material: the render will be black")) != PB_OK)
    return r;
  return PB_OK;
}

static pb_load_desc load_defaults(const pb_load_desc *desc_in) {
  pb_load_desc desc = desc_in ? *desc_in : (pb_load_desc){0};
  if (!desc.max_file_bytes) desc.max_file_bytes = 2ull << 30;
  if (!desc.max_image_dim) desc.max_image_dim = 16384;
  if (!desc.max_image_pixels) desc.max_image_pixels = 64ull << 20;
  if (!desc.max_triangles) desc.max_triangles = 64ull << 20;
  return desc;
}

/* The parsed document (owned: destroyed here) into `out`. */
static pb_result load_doc(const char *name, const char *dir, const pb_load_desc *desc, pb_gltf_doc *doc, pb_scene *out) {
  loader L;
  memset(&L, 0, sizeof L);
  L.path = name;
  L.dir = dir;
  L.desc = desc;
  L.doc = doc;
  L.s = out;
  L.default_material = -1;
  out->path = strdup(name);
  out->light_units = desc->light_units;
  snprintf(out->generator, sizeof out->generator, "%s", doc->generator ? doc->generator : "");
  pb_result r = out->path ? load(&L) : pb_fail(PB_ERR_NOMEM, "%s: out of memory", name);

  for (size_t i = 0; i < doc->image_count && L.image_cache; ++i) free(L.image_cache[i]);
  for (size_t i = 0; i < doc->image_count && L.image_cache_f; ++i) free(L.image_cache_f[i]);
  free(L.image_cache);
  free(L.image_cache_f);
  free(L.image_linear);
  free(L.image_w);
  free(L.image_h);
  free(L.texture_src);
  free(L.node_state);
  free(L.parent);
  pb_scene_anim_destroy(L.anim);
  pb_deform_destroy(&L.deform);
  free(L.world);
  free(L.tan);
  free(L.tan_given);
  pb_gltf_doc_destroy(doc);
  if (r != PB_OK) pb_scene_destroy(out);
  return r;
}

pb_result pb_scene_load(const char *path, const pb_load_desc *desc_in, pb_scene *out) {
  memset(out, 0, sizeof *out);
  pb_load_desc desc = load_defaults(desc_in);
  pb_gltf_doc doc;
  pb_gltf_read_desc rd = {desc.allow_external_files, desc.max_file_bytes, NULL};
  pb_result r = pb_gltf_doc_read(path, &rd, &doc);
  if (r != PB_OK) return r;
  char *dir = pb_dirname(path);
  if (!dir) {
    pb_gltf_doc_destroy(&doc);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  }
  r = load_doc(path, dir, &desc, &doc, out);
  free(dir);
  return r;
}

pb_result pb_scene_load_memory(const char *name, const char *base_dir, const void *data, size_t size,
                               const pb_load_desc *desc_in, pb_scene *out) {
  memset(out, 0, sizeof *out);
  pb_load_desc desc = load_defaults(desc_in);
  if (!name || !name[0]) name = "<memory>";
  if ((uint64_t)size > desc.max_file_bytes)
    return pb_fail(PB_ERR_LIMIT, "%s: input is %zu bytes, over the limit of %llu", name, size,
                   (unsigned long long)desc.max_file_bytes);
  static const uint8_t none[1] = {0};
  pb_gltf_doc doc;
  pb_gltf_read_desc rd = {desc.allow_external_files, desc.max_file_bytes, base_dir};
  pb_result r = pb_gltf_doc_parse(name, size ? (const uint8_t *)data : none, size, &rd, &doc);
  if (r != PB_OK) return r;
  return load_doc(name, base_dir, &desc, &doc, out);
}
