/* glTF images and textures -> pb_texture: images decoded once each (with
 * the size limits, image/decode.h), one pb_texture per texture, colour
 * space, uv set and KHR_texture_transform (scene.h). Part of the loader
 * (load_internal.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/srgb.h"
#include "core/fs.h"
#include "core/half.h"
#include "image/decode.h"
#include "scene/load_internal.h"

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
pb_result load_texture_ref(loader *L, const pb_gltf_texture_ref *ref, int srgb, const char *where, int32_t *out) {
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
    pb_result r = load_warn(L, "%s.texCoord: %d (only TEXCOORD_0 and TEXCOORD_1 are read; using TEXCOORD_0)", where, texcoord);
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
  r = load_grow(L, (void **)&s->textures, &L->texture_cap, (uint64_t)s->texture_count + 1, sizeof *s->textures, "textures");
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
      pb_result r2 = load_warn(L, "images[%d]: %llu texel values negative, NaN or over 65504 were set to 0 or 65504",
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
  load_copy_name(pt->name, d->images[t->source].name, d->images[t->source].uri);
  *out = (int32_t)s->texture_count++;
  return PB_OK;
}
