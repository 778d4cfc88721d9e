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
#include "scene/gltf_doc.h"
#include "scene/tangents.h"
#include "scene/scene.h"

#include "scene/anim.h"
#include "scene/blender_material.h"
#include "scene/image_decode.h"
#include "scene/xform.h"

enum {
  MODE_TRIANGLES = 4,
  MODE_TRIANGLE_STRIP = 5,
  MODE_TRIANGLE_FAN = 6,
  CT_BYTE = 5120,
  CT_UBYTE = 5121,
  CT_SHORT = 5122,
  CT_USHORT = 5123,
  CT_UINT = 5125,
  CT_FLOAT = 5126,
  MAX_NODE_DEPTH = 1024,
};

static const char *const mode_names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP",
                                         "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};

typedef struct loader {
  const char *path;
  const pb_load_desc *desc;
  pb_gltf_doc *doc;
  pb_scene *s;
  uint32_t vertex_cap, triangle_cap, light_cap, camera_cap, texture_cap;
  int32_t default_material;   /* index in s->materials, -1 until needed */
  int32_t *texture_map;       /* [gltf texture * 2 + srgb] -> s->textures */
  uint8_t **image_cache;      /* decoded RGBA8 per gltf image */
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
} loader;

/* ---- growth helpers ---------------------------------------------------- */

static pb_result grow(loader *L, void **p, uint32_t *cap, uint64_t need, size_t elem,
                      const char *what) {
  if (need <= *cap) return PB_OK;
  if (need > UINT32_MAX / 2)
    return pb_fail(PB_ERR_LIMIT, "%s: too many %s (%llu)", L->path, what, (unsigned long long)need);
  uint64_t c = *cap ? *cap : 64;
  while (c < need) c *= 2;
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

/* ---- accessors ----------------------------------------------------------- */

static uint32_t component_size(int32_t ct) {
  switch (ct) {
  case CT_BYTE: case CT_UBYTE: return 1;
  case CT_SHORT: case CT_USHORT: return 2;
  case CT_UINT: case CT_FLOAT: return 4;
  default: return 0;
  }
}

/* A checked view of an accessor's elements. */
typedef struct span {
  const uint8_t *base; /* NULL: no bufferView, every element is zero */
  uint64_t count;
  uint32_t stride, elem;
  int32_t ct;
  int normalized;
} span;

/* Checks accessors[idx] (used at `where`) against the expected shape and its
 * bufferView and buffer, so that reading element i < count of it is in
 * bounds. `types` is a 0-terminated list of allowed component types. */
static pb_result check_accessor(loader *L, int32_t idx, const char *where, int components,
                                const int32_t *types, span *out) {
  pb_gltf_doc *d = L->doc;
  if (idx < 0 || (size_t)idx >= d->accessor_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d does not exist (%zu accessors)", L->path,
                   where, idx, d->accessor_count);
  const pb_gltf_accessor *a = &d->accessors[idx];
  if (a->sparse)
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: accessors[%d]: sparse accessors are not supported", L->path, idx);
  if (a->components != components)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: has %d components, %s needs %d", L->path, idx,
                   a->components, where, components);
  int ok = 0;
  for (const int32_t *t = types; *t; ++t) ok |= *t == a->component_type;
  if (!ok)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: componentType %d is not allowed for %s", L->path,
                   idx, a->component_type, where);
  uint32_t csize = component_size(a->component_type);
  uint32_t elem = csize * (uint32_t)components;
  memset(out, 0, sizeof *out);
  out->count = a->count;
  out->elem = elem;
  out->stride = elem;
  out->ct = a->component_type;
  out->normalized = a->normalized;
  if (a->count == 0)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: count is 0", L->path, idx);
  if (a->buffer_view == -1) {
    /* All zeros, per the spec: no bytes in the file back the count. */
    if (a->count > UINT32_MAX)
      return pb_fail(PB_ERR_LIMIT, "%s: accessors[%d]: count %llu is over the limit", L->path, idx,
                     (unsigned long long)a->count);
    return PB_OK;
  }
  if (a->buffer_view < 0 || (size_t)a->buffer_view >= d->buffer_view_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d].bufferView: %d does not exist (%zu bufferViews)",
                   L->path, idx, a->buffer_view, d->buffer_view_count);
  const pb_gltf_buffer_view *v = &d->buffer_views[a->buffer_view];
  if (v->buffer < 0 || (size_t)v->buffer >= d->buffer_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%d].buffer: %d does not exist (%zu buffers)", L->path,
                   a->buffer_view, v->buffer, d->buffer_count);
  const pb_gltf_buffer *b = &d->buffers[v->buffer];
  if (v->byte_offset > b->size || v->byte_length > b->size - v->byte_offset)
    return pb_fail(PB_ERR_SCENE_INVALID,
                   "%s: bufferViews[%d]: offset %llu + length %llu exceeds buffers[%d] (%llu bytes)", L->path,
                   a->buffer_view, (unsigned long long)v->byte_offset, (unsigned long long)v->byte_length,
                   v->buffer, (unsigned long long)b->size);
  uint32_t stride = v->byte_stride ? v->byte_stride : elem;
  if (v->byte_stride && (v->byte_stride < elem || v->byte_stride > 252 || v->byte_stride % 4))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: bufferViews[%d].byteStride: %u is invalid for accessors[%d] (element %u bytes)",
                   L->path, a->buffer_view, v->byte_stride, idx, elem);
  if (a->byte_offset % csize || (v->byte_offset + a->byte_offset) % csize)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d].byteOffset: %llu is not aligned to its %u-byte components",
                   L->path, idx, (unsigned long long)a->byte_offset, csize);
  /* Needed bytes: offset + stride * (count - 1) + elem, computed without
   * overflow (count < 2^32 is checked first). */
  if (a->count > UINT32_MAX || a->byte_offset > v->byte_length)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: count %llu x stride %u exceeds bufferViews[%d] (%llu bytes)",
                   L->path, idx, (unsigned long long)a->count, stride, a->buffer_view,
                   (unsigned long long)v->byte_length);
  uint64_t need = a->byte_offset + (uint64_t)stride * (a->count - 1) + elem;
  if (need > v->byte_length)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: count %llu x stride %u exceeds bufferViews[%d] (%llu bytes)",
                   L->path, idx, (unsigned long long)a->count, stride, a->buffer_view,
                   (unsigned long long)v->byte_length);
  out->base = b->data + v->byte_offset + a->byte_offset;
  out->stride = stride;
  return PB_OK;
}

/* Reads component c of element i as a float (normalized integers mapped per
 * the glTF spec). */
static float read_f(const span *sp, uint64_t i, int c) {
  if (!sp->base) return 0.0f;
  const uint8_t *p = sp->base + i * sp->stride + (uint64_t)c * component_size(sp->ct);
  switch (sp->ct) {
  case CT_FLOAT: { float f; memcpy(&f, p, 4); return f; }
  case CT_UBYTE: return sp->normalized ? (float)p[0] / 255.0f : (float)p[0];
  case CT_BYTE: { int8_t x = (int8_t)p[0]; return sp->normalized ? fmaxf((float)x / 127.0f, -1.0f) : (float)x; }
  case CT_USHORT: { uint16_t x; memcpy(&x, p, 2); return sp->normalized ? (float)x / 65535.0f : (float)x; }
  case CT_SHORT: { int16_t x; memcpy(&x, p, 2); return sp->normalized ? fmaxf((float)x / 32767.0f, -1.0f) : (float)x; }
  default: return 0.0f;
  }
}

static uint32_t read_index(const span *sp, uint64_t i) {
  if (!sp->base) return 0;
  const uint8_t *p = sp->base + i * sp->stride;
  switch (sp->ct) {
  case CT_UBYTE: return p[0];
  case CT_USHORT: { uint16_t x; memcpy(&x, p, 2); return x; }
  default: { uint32_t x; memcpy(&x, p, 4); return x; }
  }
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
  if (L->image_cache[img]) return PB_OK;
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
  } else if (strncmp(im->uri, "data:", 5) == 0) {
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: images[%d].uri: embedded data URI images are not supported (export with separate or GLB images)",
                   L->path, img);
  } else if (im->uri[0]) {
    char *real = NULL;
    char w[64];
    snprintf(w, sizeof w, "images[%d].uri", img);
    pb_result r = pb_gltf_resolve_uri(L->path, im->uri, L->desc->allow_external_files, w, &real);
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
  int ok = size >= 8 && size <= INT32_MAX &&
           ((bytes[0] == 0x89 && memcmp(bytes + 1, "PNG", 3) == 0) || (bytes[0] == 0xFF && bytes[1] == 0xD8));
  if (!ok) {
    free(file);
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: images[%d] (used by %s): not a PNG or JPEG file", L->path, img, where);
  }
  uint32_t w = 0, h = 0;
  uint8_t *px = NULL;
  const char *why = NULL;
  int rc = PB_DECODE_OK;
  /* stb_image refuses a PNG over 2^30 decoded bytes as "corrupt": read the
   * IHDR size first so that a huge declared size is reported as a limit. */
  if (bytes[0] == 0x89 && size >= 24 && memcmp(bytes + 12, "IHDR", 4) == 0) {
    w = (uint32_t)bytes[16] << 24 | (uint32_t)bytes[17] << 16 | (uint32_t)bytes[18] << 8 | bytes[19];
    h = (uint32_t)bytes[20] << 24 | (uint32_t)bytes[21] << 16 | (uint32_t)bytes[22] << 8 | bytes[23];
    if (w > L->desc->max_image_dim || h > L->desc->max_image_dim || (uint64_t)w * h > L->desc->max_image_pixels)
      rc = PB_DECODE_TOO_LARGE;
  }
  if (rc == PB_DECODE_OK)
    rc = pb_decode_image_rgba8(bytes, size, L->desc->max_image_dim, L->desc->max_image_pixels, &px, &w, &h, &why);
  free(file);
  if (rc == PB_DECODE_TOO_LARGE)
    return pb_fail(PB_ERR_LIMIT, "%s: images[%d]: %ux%u is over the image size limit (%u per side, %llu pixels)",
                   L->path, img, w, h, L->desc->max_image_dim, (unsigned long long)L->desc->max_image_pixels);
  if (rc != PB_DECODE_OK) return pb_fail(PB_ERR_IMAGE, "%s: images[%d]: cannot decode: %s", L->path, img, why);
  L->image_cache[img] = px;
  L->image_w[img] = w;
  L->image_h[img] = h;
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

/* Resolves a material's texture reference to an index in s->textures. */
static pb_result texture_ref(loader *L, int32_t tex, int srgb, const char *where, int32_t *out) {
  pb_gltf_doc *d = L->doc;
  *out = PB_NO_TEXTURE;
  if (tex == -1) return PB_OK;
  if (tex < 0 || (size_t)tex >= d->texture_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.index: texture %d does not exist (%zu textures)", L->path, where,
                   tex, d->texture_count);
  int32_t *slot = &L->texture_map[tex * 2 + srgb];
  if (*slot >= 0) {
    *out = *slot;
    return PB_OK;
  }
  const pb_gltf_texture *t = &d->textures[tex];
  if (t->source < 0 || (size_t)t->source >= d->image_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: textures[%d].source: image %d does not exist (%zu images)", L->path,
                   tex, t->source, d->image_count);
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
  pb_scene *s = L->s;
  r = grow(L, (void **)&s->textures, &L->texture_cap, (uint64_t)s->texture_count + 1, sizeof *s->textures, "textures");
  if (r != PB_OK) return r;
  pb_texture *pt = &s->textures[s->texture_count];
  memset(pt, 0, sizeof *pt);
  size_t bytes = (size_t)L->image_w[t->source] * L->image_h[t->source] * 4;
  pt->rgba8 = malloc(bytes);
  if (!pt->rgba8) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for textures[%d]", L->path, tex);
  memcpy(pt->rgba8, L->image_cache[t->source], bytes);
  pt->width = L->image_w[t->source];
  pt->height = L->image_h[t->source];
  pt->srgb = srgb;
  pt->wrap_s = ws;
  pt->wrap_t = wt;
  pt->nearest = nearest;
  copy_name(pt->name, d->images[t->source].name, d->images[t->source].uri);
  *slot = (int32_t)s->texture_count++;
  *out = *slot;
  return PB_OK;
}

/* ---- materials ----------------------------------------------------------- */

static float clamp01(double v) { return (float)(v < 0 ? 0 : (v > 1 ? 1 : v)); }

static pb_result check_factor(loader *L, int i, const char *field, double v, double lo, double hi) {
  if (!isfinite(v) || v < lo || v > hi)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: materials[%d].%s: %g is outside [%g, %g]", L->path, i, field, v, lo, hi);
  return PB_OK;
}

/* The PHOTONBRIDGE_blender material reader's way to textures and warnings
 * (blender_material.h). */
static pb_result blender_texture(void *user, int32_t tex, int srgb, const char *where, int32_t *out) {
  return texture_ref(user, tex, srgb, where, out);
}
static pb_result blender_warn(void *user, const char *line) { return warn(user, "%s", line); }

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

  const pb_gltf_texture_ref *refs[4] = {&g->base_color_tex, &g->metallic_roughness_tex, &g->emissive_tex, &g->normal_tex};
  static const char *const names[4] = {"pbrMetallicRoughness.baseColorTexture", "pbrMetallicRoughness.metallicRoughnessTexture",
                                       "emissiveTexture", "normalTexture"};
  static const int srgb[4] = {1, 0, 1, 0};
  int32_t *dst[4] = {&m->base_color_tex, &m->metallic_roughness_tex, &m->emissive_tex, &m->normal_tex};
  for (int k = 0; k < 4; ++k) {
    snprintf(w, sizeof w, "materials[%d].%s", i, names[k]);
    if (refs[k]->index != -1 && refs[k]->texcoord != 0) {
      r = warn(L, "%s.texCoord: %d (only TEXCOORD_0 is read; using it)", w, refs[k]->texcoord);
      if (r != PB_OK) return r;
    }
    r = texture_ref(L, refs[k]->index, srgb[k], w, dst[k]);
    if (r != PB_OK) return r;
  }
  if (g->blender) {
    pb_blender_material_io io = {L->path, L, blender_texture, blender_warn};
    return pb_blender_material_read(&io, i, g->blender, m);
  }
  return PB_OK;
}

static int32_t default_material(loader *L) {
  /* glTF's default material: white, metallic 1, roughness 1. */
  if (L->default_material < 0) {
    pb_scene *s = L->s;
    pb_material *m = &s->materials[s->material_count];
    memset(m, 0, sizeof *m);
    snprintf(m->name, PB_NAME_MAX, "(default)");
    for (int k = 0; k < 4; ++k) m->base_color[k] = 1;
    m->metallic = 1;
    m->roughness = 1;
    m->specular = 1;
    m->specular_color[0] = m->specular_color[1] = m->specular_color[2] = 1;
    m->ior = 1.5f;
    m->base_color_tex = m->metallic_roughness_tex = m->emissive_tex = m->normal_tex = PB_NO_TEXTURE;
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
 * later one wins (warned). Morph "weights" channels and channels on nodes
 * given by `matrix` (which glTF does not allow to animate) are ignored with a
 * warning. */

static const char *const anim_paths[] = {"translation", "rotation", "scale"};

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
  static const int32_t float_only[] = {CT_FLOAT, 0};
  char w[96];
  const char *ip = g->interpolation ? g->interpolation : "LINEAR";
  if (strcmp(ip, "LINEAR") == 0) *interp = PB_ANIM_LINEAR;
  else if (strcmp(ip, "STEP") == 0) *interp = PB_ANIM_STEP;
  else if (strcmp(ip, "CUBICSPLINE") == 0) *interp = PB_ANIM_CUBICSPLINE;
  else
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].samplers[%zu].interpolation: '%s' is not LINEAR, STEP or CUBICSPLINE",
                   L->path, ai, si, ip);
  snprintf(w, sizeof w, "animations[%zu].samplers[%zu].input", ai, si);
  span in;
  pb_result r = check_accessor(L, g->input, w, 1, float_only, &in);
  if (r != PB_OK) return r;
  float prev = 0;
  for (uint64_t k = 0; k < in.count; ++k) {
    float v = read_f(&in, k, 0);
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
                                      int *negative_scale) {
  pb_gltf_doc *d = L->doc;
  const pb_gltf_anim_sampler *g = &d->animations[ai].samplers[si];
  static const int32_t float_only[] = {CT_FLOAT, 0};
  static const int32_t rot_types[] = {CT_FLOAT, CT_BYTE, CT_UBYTE, CT_SHORT, CT_USHORT, 0};
  int comps = path == PB_ANIM_ROTATION ? 4 : 3;
  char wi[96], wo[128];
  snprintf(wi, sizeof wi, "animations[%zu].samplers[%zu].input", ai, si);
  snprintf(wo, sizeof wo, "animations[%zu].samplers[%zu].output (%s)", ai, si, anim_paths[path]);
  span in, out;
  pb_result r = check_accessor(L, g->input, wi, 1, float_only, &in);
  if (r == PB_OK) r = check_accessor(L, g->output, wo, comps, path == PB_ANIM_ROTATION ? rot_types : float_only, &out);
  if (r != PB_OK) return r;
  if (out.ct != CT_FLOAT && !out.normalized)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: integer rotation keys must be normalized (%s)", L->path, g->output, wo);
  uint64_t per = interp == PB_ANIM_CUBICSPLINE ? 3 : 1;
  if (out.count != in.count * per)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d has %llu elements, %s with %llu keys needs %llu", L->path, wo,
                   g->output, (unsigned long long)out.count, interp == PB_ANIM_CUBICSPLINE ? "CUBICSPLINE" : "LINEAR/STEP",
                   (unsigned long long)in.count, (unsigned long long)(in.count * per));
  pb_anim_sampler *S = &a->samplers[a->sampler_count];
  memset(S, 0, sizeof *S);
  S->times = malloc((size_t)in.count * sizeof *S->times);
  S->values = malloc((size_t)out.count * (size_t)comps * sizeof *S->values);
  if (!S->times || !S->values) {
    free(S->times);
    free(S->values);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory for %s", L->path, wo);
  }
  a->sampler_count++; /* owned by a from here */
  S->key_count = (uint32_t)in.count;
  S->comps = comps;
  S->interp = interp;
  for (uint64_t k = 0; k < in.count; ++k) S->times[k] = read_f(&in, k, 0);
  for (uint64_t k = 0; k < out.count; ++k)
    for (int c = 0; c < comps; ++c) {
      float v = read_f(&out, k, c);
      if (!isfinite(v))
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: element %llu is not finite", L->path, wo, (unsigned long long)k);
      if (path == PB_ANIM_SCALE && (per == 1 || k % 3 == 1) && v < 0) *negative_scale = 1;
      S->values[k * (uint64_t)comps + (uint64_t)c] = v;
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
  size_t (*owner)[3][2] = calloc(d->node_count + 1, sizeof *owner);
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
      for (int k = 0; k < 3; ++k)
        if (strcmp(ps, anim_paths[k]) == 0) path = k;
      if (path < 0 && strcmp(ps, "weights") != 0 && strcmp(ps, "pointer") != 0) {
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
        r = warn(L, "animations[%zu].channels[%zu]: '%s' channel ignored (morph targets and animation pointers are not animated)",
                 ai, ci, ps);
        continue;
      }
      if (ch->target_node == -1) {
        r = warn(L, "animations[%zu].channels[%zu].target: no node; channel ignored", ai, ci);
        continue;
      }
      int32_t node = ch->target_node;
      if (d->nodes[node].has_matrix) {
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
      if ((r = convert_anim_sampler(L, a, ai, (size_t)ch->sampler, interp[ch->sampler], path, &negative_scale)) != PB_OK) break;
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
  if (!a->nodes || !a->order || !a->trs || !a->world) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
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
  /* A node with a channel is animated; visit() passes it down the tree. */
  for (uint32_t i = 0; i < a->channel_count; ++i) a->nodes[a->channels[i].node].animated = 1;
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
static pb_result store_tangent(loader *L, uint32_t dst, const span *tg, uint64_t src, const mat4 *M, int flip) {
  if (dst >= L->tan_cap) {
    uint32_t old = L->tan_cap;
    pb_result r = grow(L, (void **)&L->tan, &L->tan_cap, (uint64_t)dst + 1, sizeof *L->tan, "tangents");
    if (r != PB_OK) return r;
    uint8_t *q = realloc(L->tan_given, L->tan_cap);
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for tangents", L->path);
    memset(q + old, 0, L->tan_cap - old);
    L->tan_given = q;
  }
  double tl[3] = {read_f(tg, src, 0), read_f(tg, src, 1), read_f(tg, src, 2)}, tw[3];
  float w = read_f(tg, src, 3);
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
    static const int32_t float_only[] = {CT_FLOAT, 0};
    span sp;
    if (check_accessor(L, a, "POSITION", 3, float_only, &sp) != PB_OK) {
      pb_error_clear(); /* add_primitive reports it */
      continue;
    }
    for (uint64_t i = 0; sp.base && i < sp.count; ++i)
      for (int k = 0; k < 3; ++k) {
        double v = read_f(&sp, i, k);
        if (isfinite(v)) bmin[k] = fmin(bmin[k], v), bmax[k] = fmax(bmax[k], v);
      }
  }
  for (int k = 0; k < 3; ++k)
    if (!(bmin[k] <= bmax[k])) bmin[k] = bmax[k] = 0.0;
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
  if (p->has_targets && (r = warn(L, "meshes[%d].primitives[%zu]: morph targets ignored", mesh, pi)) != PB_OK) return r;
  if (p->position == -1)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: meshes[%d].primitives[%zu].attributes: no POSITION", L->path, mesh, pi);
  static const int32_t float_only[] = {CT_FLOAT, 0};
  static const int32_t uv_types[] = {CT_FLOAT, CT_UBYTE, CT_USHORT, 0};
  static const int32_t index_types[] = {CT_UBYTE, CT_USHORT, CT_UINT, 0};
  span pos, nrm, uv, idx;
  snprintf(w, sizeof w, "meshes[%d].primitives[%zu].attributes.POSITION", mesh, pi);
  if ((r = check_accessor(L, p->position, w, 3, float_only, &pos)) != PB_OK) return r;
  int has_n = p->normal != -1, has_uv = p->texcoord0 != -1, indexed = p->indices != -1;
  if (has_n) {
    snprintf(w, sizeof w, "meshes[%d].primitives[%zu].attributes.NORMAL", mesh, pi);
    if ((r = check_accessor(L, p->normal, w, 3, float_only, &nrm)) != PB_OK) return r;
    if (nrm.count != pos.count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d has %llu elements, POSITION has %llu", L->path, w,
                     p->normal, (unsigned long long)nrm.count, (unsigned long long)pos.count);
  }
  if (has_uv) {
    snprintf(w, sizeof w, "meshes[%d].primitives[%zu].attributes.TEXCOORD_0", mesh, pi);
    if ((r = check_accessor(L, p->texcoord0, w, 2, uv_types, &uv)) != PB_OK) return r;
    if (uv.ct != CT_FLOAT && !uv.normalized)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: integer TEXCOORD_0 must be normalized", L->path, p->texcoord0);
    if (uv.count != pos.count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d has %llu elements, POSITION has %llu", L->path, w,
                     p->texcoord0, (unsigned long long)uv.count, (unsigned long long)pos.count);
  }
  /* TANGENT (glTF 2.0 3.7.2.1: VEC4 float, w = +-1 the handedness): checked
   * whenever present, read only for a normal-mapped material. */
  span tng = {0};
  int has_t = p->tangent != -1;
  if (has_t) {
    snprintf(w, sizeof w, "meshes[%d].primitives[%zu].attributes.TANGENT", mesh, pi);
    if ((r = check_accessor(L, p->tangent, w, 4, float_only, &tng)) != PB_OK) return r;
    if (tng.count != pos.count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d has %llu elements, POSITION has %llu", L->path, w,
                     p->tangent, (unsigned long long)tng.count, (unsigned long long)pos.count);
  }
  uint64_t nidx = pos.count;
  if (indexed) {
    snprintf(w, sizeof w, "meshes[%d].primitives[%zu].indices", mesh, pi);
    if ((r = check_accessor(L, p->indices, w, 1, index_types, &idx)) != PB_OK) return r;
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
  int use_t = has_t && tng.base && mat >= 0 && (uint32_t)mat < s->material_count &&
              s->materials[mat].normal_tex >= 0;
  int radial = mat >= 0 && (uint32_t)mat < s->material_count && pb_blender_needs_tangent(&s->materials[mat]);
  double bmin[3] = {0, 0, 0}, bmax[3] = {0, 0, 0};
  if (radial) mesh_bounds(L, mesh, bmin, bmax);

  /* Triangle list from the mode. Limits come before any per-element work:
   * an accessor without a bufferView costs the file nothing per element. */
  uint64_t ntri = p->mode == MODE_TRIANGLES ? nidx / 3 : (nidx >= 3 ? nidx - 2 : 0);
  if ((uint64_t)s->triangle_count + ntri > L->desc->max_triangles)
    return pb_fail(PB_ERR_LIMIT, "%s: meshes[%d].primitives[%zu]: more than %llu triangles in the scene", L->path, mesh,
                   pi, (unsigned long long)L->desc->max_triangles);
  /* Flat normals (the glTF rule when NORMAL is absent) need 3 vertices per
   * triangle; otherwise the accessor's vertices are shared. */
  uint64_t nverts = has_n ? pos.count : ntri * 3;
  if ((uint64_t)s->vertex_count + nverts > 3 * L->desc->max_triangles)
    return pb_fail(PB_ERR_LIMIT, "%s: meshes[%d].primitives[%zu]: %llu vertices is over the limit of %llu in the scene",
                   L->path, mesh, pi, (unsigned long long)nverts, (unsigned long long)(3 * L->desc->max_triangles));

  /* An accessor without a bufferView reads as zeros (glTF 2.0, 3.6.2.3): zero
   * positions or zero indices make every triangle degenerate. Within the
   * limits such a primitive is skipped before any per-element work or
   * allocation. */
  if (!pos.base || (indexed && !idx.base))
    return warn(L, "meshes[%d].primitives[%zu]: %s has no bufferView (all zeros): primitive skipped", mesh, pi,
                !pos.base ? "POSITION" : "indices");

  /* Vertex positions: all finite, checked once per accessor element. */
  for (uint64_t i = 0; pos.base && i < pos.count; ++i)
    for (int c = 0; c < 3; ++c)
      if (!isfinite(read_f(&pos, i, c)))
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: POSITION element %llu is not finite (%g)", L->path,
                       p->position, (unsigned long long)i, (double)read_f(&pos, i, c));
  if (p->mode == MODE_TRIANGLES && nidx % 3 &&
      (r = warn(L, "meshes[%d].primitives[%zu]: %llu indices is not a multiple of 3; the last %llu ignored", mesh, pi,
                (unsigned long long)nidx, (unsigned long long)(nidx % 3))) != PB_OK)
    return r;
  if ((r = grow(L, (void **)&s->positions, &L->vertex_cap, (uint64_t)s->vertex_count + nverts, sizeof *s->positions, "vertices")) != PB_OK) return r;
  uint32_t vcap = L->vertex_cap;
  void *q1 = realloc(s->normals, (size_t)vcap * sizeof *s->normals);
  if (q1) s->normals = q1;
  void *q2 = q1 ? realloc(s->uvs, (size_t)vcap * sizeof *s->uvs) : NULL;
  if (q2) s->uvs = q2;
  if (!q1 || !q2) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for vertices", L->path);
  uint32_t tcap = L->triangle_cap;
  if ((r = grow(L, (void **)&s->triangles, &L->triangle_cap, (uint64_t)s->triangle_count + ntri, sizeof *s->triangles, "triangles")) != PB_OK) return r;
  if (L->triangle_cap != tcap) {
    void *q = realloc(s->triangle_material, (size_t)L->triangle_cap * sizeof *s->triangle_material);
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for triangles", L->path);
    s->triangle_material = q;
  }

  /* Under an animated node the local-space vertices are kept for posing. */
  struct pb_scene_anim *an = L->anim && L->anim->nodes[node].animated ? L->anim : NULL;
  uint32_t local = 0;
  if (an) {
    if ((r = anim_reserve(L, an, nverts)) != PB_OK) return r;
    local = an->local_count;
  }
  int flip = det3(M) < 0; /* a mirroring transform reverses the winding */
  double N[9];
  normal_matrix(M, N);
  uint32_t base = s->vertex_count, tri_base = s->triangle_count;
  uint64_t dropped = 0;
  if (has_n) {
    for (uint64_t i = 0; i < pos.count; ++i) {
      double pl[3] = {read_f(&pos, i, 0), read_f(&pos, i, 1), read_f(&pos, i, 2)}, pw[3];
      xform_point(M, pl, pw);
      if (!fits_float3(pw))
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: transform takes accessors[%d] POSITION element %llu out of float range",
                       L->path, node, p->position, (unsigned long long)i);
      double nl[3] = {read_f(&nrm, i, 0), read_f(&nrm, i, 1), read_f(&nrm, i, 2)}, nw[3];
      for (int rr = 0; rr < 3; ++rr) nw[rr] = N[rr] * nl[0] + N[3 + rr] * nl[1] + N[6 + rr] * nl[2];
      if (!normalize3(nw)) nw[0] = nw[1] = 0, nw[2] = 0; /* fixed below from the face */
      float *P = s->positions[base + i], *Nn = s->normals[base + i], *U = s->uvs[base + i];
      for (int c = 0; c < 3; ++c) P[c] = (float)pw[c], Nn[c] = (float)nw[c];
      if (an)
        for (int c = 0; c < 3; ++c) an->local_pos[local + i][c] = (float)pl[c], an->local_nrm[local + i][c] = (float)nl[c];
      U[0] = has_uv ? read_f(&uv, i, 0) : 0.0f;
      U[1] = has_uv ? read_f(&uv, i, 1) : 0.0f;
      if (!isfinite(U[0]) || !isfinite(U[1])) U[0] = U[1] = 0;
      if (use_t && (r = store_tangent(L, base + (uint32_t)i, &tng, i, M, flip)) != PB_OK) return r;
      if (radial && (r = store_radial_tangent(L, base + (uint32_t)i, pl, bmin, bmax, N)) != PB_OK) return r;
    }
    s->vertex_count += (uint32_t)pos.count;
  }
  for (uint64_t t = 0; t < ntri; ++t) {
    uint64_t k[3];
    if (p->mode == MODE_TRIANGLES) k[0] = 3 * t, k[1] = 3 * t + 1, k[2] = 3 * t + 2;
    else if (p->mode == MODE_TRIANGLE_STRIP) k[0] = t + (t & 1), k[1] = t + 1 - (t & 1), k[2] = t + 2;
    else k[0] = t + 1, k[1] = t + 2, k[2] = 0;
    uint32_t v[3];
    for (int c = 0; c < 3; ++c) {
      uint64_t vi = indexed ? read_index(&idx, k[c]) : k[c];
      if (vi >= pos.count)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: index %llu at element %llu is out of range (%llu vertices)",
                       L->path, p->indices, (unsigned long long)vi, (unsigned long long)k[c], (unsigned long long)pos.count);
      v[c] = (uint32_t)vi;
    }
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
      dropped++;
      continue;
    }
    if (flip) {
      uint32_t tmp = v[1];
      v[1] = v[2];
      v[2] = tmp;
    }
    uint32_t out[3];
    if (has_n) {
      for (int c = 0; c < 3; ++c) out[c] = base + v[c];
    } else {
      double pw[3][3];
      for (int c = 0; c < 3; ++c) {
        double pl[3] = {read_f(&pos, v[c], 0), read_f(&pos, v[c], 1), read_f(&pos, v[c], 2)};
        xform_point(M, pl, pw[c]);
        if (!fits_float3(pw[c]))
          return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: transform takes accessors[%d] POSITION element %u out of float range",
                         L->path, node, p->position, v[c]);
      }
      double e1[3] = {pw[1][0] - pw[0][0], pw[1][1] - pw[0][1], pw[1][2] - pw[0][2]};
      double e2[3] = {pw[2][0] - pw[0][0], pw[2][1] - pw[0][1], pw[2][2] - pw[0][2]};
      double fn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      if (!normalize3(fn)) fn[0] = 0, fn[1] = 0, fn[2] = 1; /* zero area: any unit normal */
      for (int c = 0; c < 3; ++c) {
        uint32_t o = s->vertex_count++;
        for (int a = 0; a < 3; ++a) s->positions[o][a] = (float)pw[c][a], s->normals[o][a] = (float)fn[a];
        if (an)
          for (int a = 0; a < 3; ++a)
            an->local_pos[local + (o - base)][a] = read_f(&pos, v[c], a), an->local_nrm[local + (o - base)][a] = 0;
        s->uvs[o][0] = has_uv ? read_f(&uv, v[c], 0) : 0.0f;
        s->uvs[o][1] = has_uv ? read_f(&uv, v[c], 1) : 0.0f;
        if (use_t && (r = store_tangent(L, o, &tng, v[c], M, flip)) != PB_OK) return r;
        double pl[3] = {read_f(&pos, v[c], 0), read_f(&pos, v[c], 1), read_f(&pos, v[c], 2)};
        if (radial && (r = store_radial_tangent(L, o, pl, bmin, bmax, N)) != PB_OK) return r;
        out[c] = o;
      }
    }
    uint32_t tri = s->triangle_count++;
    memcpy(s->triangles[tri], out, sizeof out);
    s->triangle_material[tri] = (uint32_t)mat;
  }
  /* Zero normals in the file (or collapsed by a degenerate transform): use the
   * face normal of a triangle that uses the vertex. */
  if (has_n)
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
  if (an && s->vertex_count > base) {
    if (an->range_count == an->range_cap) {
      uint32_t c = an->range_cap ? 2 * an->range_cap : 16;
      void *q = realloc(an->ranges, (size_t)c * sizeof *an->ranges);
      if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
      an->ranges = q;
      an->range_cap = c;
    }
    an->ranges[an->range_count++] = (pb_anim_range){.node = node, .first_vertex = base, .vertex_count = s->vertex_count - base,
                                                    .first_tri = tri_base, .tri_count = s->triangle_count - tri_base,
                                                    .local = local, .flat = !has_n};
    an->local_count += s->vertex_count - base;
  }
  if (dropped)
    return warn(L, "meshes[%d].primitives[%zu]: %llu degenerate triangles (repeated index) dropped", mesh, pi,
                (unsigned long long)dropped);
  return PB_OK;
}

/* ---- cameras and lights -------------------------------------------------- */

static pb_result add_camera(loader *L, int32_t node, const mat4 *M) {
  pb_gltf_doc *d = L->doc;
  int32_t ci = d->nodes[node].camera;
  if (ci < 0 || (size_t)ci >= d->camera_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d].camera: %d does not exist (%zu cameras)", L->path, node, ci,
                   d->camera_count);
  const pb_gltf_camera *c = &d->cameras[ci];
  if (!c->perspective)
    return warn(L, "cameras[%d]: type '%s' skipped: only perspective cameras are supported", ci, c->type);
  if (!(c->yfov > 0 && c->yfov < M_PI))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%d].perspective.yfov: %g is not in (0, pi)", L->path, ci, c->yfov);
  if (!(c->znear > 0) || !fits_float(c->znear))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%d].perspective.znear: %g is not positive", L->path, ci, c->znear);
  if (c->zfar != 0 && !(c->zfar > c->znear && fits_float(c->zfar)))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%d].perspective.zfar: %g is not above znear (%g)", L->path, ci, c->zfar,
                   c->znear);
  if (c->aspect_ratio < 0 || !fits_float(c->aspect_ratio))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: cameras[%d].perspective.aspectRatio: %g is not positive", L->path, ci,
                   c->aspect_ratio);
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
  pb_result r = grow(L, (void **)&s->cameras, &L->camera_cap, (uint64_t)s->camera_count + 1, sizeof *s->cameras, "cameras");
  if (r != PB_OK) return r;
  pb_camera *cam = &s->cameras[s->camera_count++];
  memset(cam, 0, sizeof *cam);
  copy_name(cam->name, d->nodes[node].name, c->name);
  if (!cam->name[0]) snprintf(cam->name, PB_NAME_MAX, "cameras[%d]", ci);
  for (int k = 0; k < 3; ++k) cam->position[k] = (float)pos[k], cam->forward[k] = (float)f[k], cam->up[k] = (float)u[k];
  cam->right[0] = (float)(f[1] * u[2] - f[2] * u[1]);
  cam->right[1] = (float)(f[2] * u[0] - f[0] * u[2]);
  cam->right[2] = (float)(f[0] * u[1] - f[1] * u[0]);
  cam->yfov = (float)c->yfov;
  cam->aspect = (float)c->aspect_ratio;
  cam->znear = (float)c->znear;
  cam->zfar = (float)c->zfar;
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
  if (type == PB_LIGHT_SPOT && !(g->inner_cone >= 0 && g->inner_cone < g->outer_cone && g->outer_cone <= M_PI / 2 + 1e-6))
    return pb_fail(PB_ERR_SCENE_INVALID,
                   "%s: extensions.KHR_lights_punctual.lights[%d].spot: need 0 <= innerConeAngle (%g) < outerConeAngle (%g) <= pi/2",
                   L->path, li, g->inner_cone, g->outer_cone);
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
  if (an) {
    an->order[an->order_count++] = node;
    int32_t p = an->nodes[node].parent;
    if (p >= 0 && an->nodes[p].animated) an->nodes[node].animated = 1;
  }
  mat4 local = node_local(n);
  mat4 M = mat_mul(parent, &local);
  if (!finite_mat(&M))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: transform is not finite", L->path, node);
  pb_result r = PB_OK;
  if (n->skin >= 0 && (r = warn(L, "nodes[%d]: skinning ignored (rendered in bind pose)", node)) != PB_OK) return r;
  if (n->mesh != -1) {
    if (n->mesh < 0 || (size_t)n->mesh >= d->mesh_count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d].mesh: %d does not exist (%zu meshes)", L->path, node, n->mesh,
                     d->mesh_count);
    for (size_t pi = 0; pi < d->meshes[n->mesh].primitive_count; ++pi)
      if ((r = add_primitive(L, node, n->mesh, pi, &M)) != PB_OK) return r;
  }
  uint32_t nc = L->s->camera_count, nl = L->s->light_count;
  if (n->camera != -1 && (r = add_camera(L, node, &M)) != PB_OK) return r;
  if (n->light != -1 && (r = add_light(L, node, &M)) != PB_OK) return r;
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
    for (size_t pi = 0; pi < m->primitive_count; ++pi) {
      int32_t a = m->primitives[pi].position;
      double w[3];
      if (a >= 0 && (size_t)a < d->accessor_count && d->accessors[a].has_min_max) {
        const pb_gltf_accessor *ac = &d->accessors[a];
        for (int c = 0; c < 8; ++c) {
          double p[3] = {(c & 1) ? ac->max[0] : ac->min[0], (c & 2) ? ac->max[1] : ac->min[1],
                         (c & 4) ? ac->max[2] : ac->min[2]};
          xform_point(&M, p, w);
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
  c->yfov = yfov;
  c->znear = 0.01f;
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
  L->texture_map = malloc((d->texture_count * 2 + 1) * sizeof *L->texture_map);
  L->image_cache = calloc(d->image_count + 1, sizeof *L->image_cache);
  L->image_w = calloc(d->image_count + 1, sizeof *L->image_w);
  L->image_h = calloc(d->image_count + 1, sizeof *L->image_h);
  L->node_state = calloc(d->node_count + 1, 1);
  L->parent = malloc((d->node_count + 1) * sizeof *L->parent);
  if (!s->materials || !L->texture_map || !L->image_cache || !L->image_w || !L->image_h || !L->node_state || !L->parent)
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  for (size_t i = 0; i < d->texture_count * 2; ++i) L->texture_map[i] = -1;
  for (size_t i = 0; i < d->material_count; ++i) {
    if ((r = convert_material(L, (int)i, &s->materials[i])) != PB_OK) return r;
    s->material_count++;
  }
  if ((r = check_nodes(L)) != PB_OK) return r;
  if ((r = build_anim(L)) != PB_OK) return r;

  /* The scene to show: `scene`, else scenes[0], else every root node. */
  mat4 I;
  memset(&I, 0, sizeof I);
  I.m[0] = I.m[5] = I.m[10] = I.m[15] = 1;
  if (d->default_scene != -1 && (d->default_scene < 0 || (size_t)d->default_scene >= d->scene_count))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: scene: %d does not exist (%zu scenes)", L->path, d->default_scene, d->scene_count);
  if (d->scene_count > 0) {
    int32_t si = d->default_scene != -1 ? d->default_scene : 0;
    const pb_gltf_scene *sc = &d->scenes[si];
    precision_origin(L, sc->nodes, sc->node_count, s->origin);
    I.m[12] = -s->origin[0], I.m[13] = -s->origin[1], I.m[14] = -s->origin[2];
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
    for (size_t n = 0; n < d->node_count; ++n)
      if (L->parent[n] < 0 && (r = visit(L, (int32_t)n, &I, 0)) != PB_OK) return r;
  }
  s->animation_count = (uint32_t)d->animation_count;
  s->animation_channel_count = (uint32_t)d->animation_channel_count;
  for (size_t i = 0; i < d->extensions_used_count; ++i) {
    const char *e = d->extensions_used[i];
    static const char *const known[] = {"KHR_lights_punctual", "KHR_materials_specular", "KHR_materials_transmission",
                                        "KHR_materials_ior", "KHR_materials_emissive_strength", "PHOTONBRIDGE_blender"};
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
  if (s->light_count == 0 && !(s->features & PB_FEATURE_EMISSIVE) &&
      (r = warn(L, "lights: none, and no emissive material: the render will be black")) != PB_OK)
    return r;
  return PB_OK;
}

pb_result pb_scene_load(const char *path, const pb_load_desc *desc_in, pb_scene *out) {
  memset(out, 0, sizeof *out);
  pb_load_desc desc = desc_in ? *desc_in : (pb_load_desc){0};
  if (!desc.max_file_bytes) desc.max_file_bytes = 2ull << 30;
  if (!desc.max_image_dim) desc.max_image_dim = 16384;
  if (!desc.max_image_pixels) desc.max_image_pixels = 64ull << 20;
  if (!desc.max_triangles) desc.max_triangles = 64ull << 20;

  pb_gltf_doc doc;
  pb_gltf_read_desc rd = {desc.allow_external_files, desc.max_file_bytes};
  pb_result r = pb_gltf_doc_read(path, &rd, &doc);
  if (r != PB_OK) return r;

  loader L;
  memset(&L, 0, sizeof L);
  L.path = path;
  L.desc = &desc;
  L.doc = &doc;
  L.s = out;
  L.default_material = -1;
  out->path = strdup(path);
  out->light_units = desc.light_units;
  snprintf(out->generator, sizeof out->generator, "%s", doc.generator ? doc.generator : "");
  r = out->path ? load(&L) : pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);

  for (size_t i = 0; i < doc.image_count && L.image_cache; ++i) free(L.image_cache[i]);
  free(L.image_cache);
  free(L.image_w);
  free(L.image_h);
  free(L.texture_map);
  free(L.node_state);
  free(L.parent);
  pb_scene_anim_destroy(L.anim);
  free(L.tan);
  free(L.tan_given);
  pb_gltf_doc_destroy(&doc);
  if (r != PB_OK) pb_scene_destroy(out);
  return r;
}
