/* EXR writer and reader on OpenEXRCore (the C API of OpenEXR 3.1).
 *
 * The library reports problems through a per-context error callback; we keep
 * its first message of each call in a thread-local buffer and fold it into our
 * one-line pb_fail() message, so the user sees "PATH: what: library detail". */
#include "image/image.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openexr.h>

#include "core/fs.h"
#include "core/log.h"

/* ---- library error capture ---------------------------------------------- */

static _Thread_local char exr_msg[256];

static void exr_error_handler(exr_const_context_t ctxt, exr_result_t code,
                              const char *msg) {
  (void)ctxt;
  if (exr_msg[0]) return; /* the first report is the most specific one */
  snprintf(exr_msg, sizeof exr_msg, "%s",
           msg ? msg : exr_get_default_error_message(code));
}

/* The captured library message for `rv`, or the library's generic text. */
static const char *exr_detail(exr_result_t rv) {
  return exr_msg[0] ? exr_msg : exr_get_default_error_message(rv);
}

static exr_context_initializer_t exr_init(int flags) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = exr_error_handler;
  init.flags = flags;
  exr_msg[0] = 0;
  return init;
}

/* ---- writer ------------------------------------------------------------- */

static const float HALF_MAX = 65504.0f;

/* One output channel: where its values come from. */
typedef struct wchan {
  char name[64];
  uint32_t layer;
  uint32_t comp;
} wchan;

static int wchan_cmp(const void *a, const void *b) {
  return strcmp(((const wchan *)a)->name, ((const wchan *)b)->name);
}

/* Default channel name of component `c` of layer `l` (see image.h). Returns 0
 * when the layer's channel count has no default naming. */
static int default_channel_name(const pb_image_layer *l, uint32_t c,
                                char out[64]) {
  static const char *const rgba[4] = {"R", "G", "B", "A"};
  static const char *const xyz[3] = {"X", "Y", "Z"};
  const char *layer = l->name ? l->name : "";
  uint32_t n = l->channels;
  if (n != 1 && n != 3 && n != 4) return 0;
  const char *suffix;
  if (n == 1) {
    if (!layer[0]) suffix = "Y";
    else suffix = strcmp(layer, "depth") == 0 ? "Z" : "V";
  } else if (n == 3 && strcmp(layer, "normal") == 0) {
    suffix = xyz[c];
  } else {
    suffix = rgba[c];
  }
  int len = layer[0] ? snprintf(out, 64, "%s.%s", layer, suffix)
                     : snprintf(out, 64, "%s", suffix);
  return len > 0 && len < 64 ? 1 : -1;
}

/* Validates `desc` and builds the sorted channel table. */
static pb_result build_channels(const char *path, const pb_exr_desc *d,
                                wchan **out, uint32_t *count) {
  *out = NULL;
  *count = 0;
  if (d->width == 0 || d->height == 0)
    return pb_fail(PB_ERR_IMAGE, "%s: image size %ux%u is empty", path,
                   d->width, d->height);
  if (d->width > PB_IMAGE_MAX_DIM || d->height > PB_IMAGE_MAX_DIM ||
      (uint64_t)d->width * d->height > PB_IMAGE_MAX_PIXELS)
    return pb_fail(PB_ERR_LIMIT,
                   "%s: image size %ux%u exceeds the limit (%u per side, %llu "
                   "pixels)",
                   path, d->width, d->height, PB_IMAGE_MAX_DIM,
                   (unsigned long long)PB_IMAGE_MAX_PIXELS);
  if (d->pixel_type != PB_EXR_FLOAT && d->pixel_type != PB_EXR_HALF)
    return pb_fail(PB_ERR_IMAGE, "%s: unknown pixel type %d", path,
                   (int)d->pixel_type);
  if (d->layer_count == 0 || !d->layers)
    return pb_fail(PB_ERR_IMAGE, "%s: no layers to write", path);
  if (d->attr_count && (!d->attr_names || !d->attr_values))
    return pb_fail(PB_ERR_IMAGE, "%s: %u attributes without names or values",
                   path, d->attr_count);

  uint64_t total = 0;
  for (uint32_t i = 0; i < d->layer_count; ++i) {
    const pb_image_layer *l = &d->layers[i];
    const char *lname = l->name ? l->name : "";
    if (l->channels == 0 || !l->pixels)
      return pb_fail(PB_ERR_IMAGE, "%s: layers[%u] \"%s\" has no %s", path, i,
                     lname, l->channels ? "pixels" : "channels");
    if (l->channels > PB_IMAGE_MAX_CHANNELS)
      return pb_fail(PB_ERR_LIMIT, "%s: layers[%u] \"%s\" has %u channels, "
                     "over the limit of %u", path, i, lname, l->channels,
                     PB_IMAGE_MAX_CHANNELS);
    total += l->channels;
  }
  if (total > PB_IMAGE_MAX_CHANNELS)
    return pb_fail(PB_ERR_LIMIT, "%s: %llu channels, over the limit of %u",
                   path, (unsigned long long)total, PB_IMAGE_MAX_CHANNELS);

  wchan *ch = calloc((size_t)total, sizeof *ch);
  if (!ch) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  uint32_t k = 0;
  for (uint32_t i = 0; i < d->layer_count; ++i) {
    const pb_image_layer *l = &d->layers[i];
    const char *lname = l->name ? l->name : "";
    for (uint32_t c = 0; c < l->channels; ++c, ++k) {
      ch[k].layer = i;
      ch[k].comp = c;
      if (l->channel_names) {
        const char *n = l->channel_names[c];
        size_t len = n ? strlen(n) : 0;
        if (len == 0 || len > 63) {
          free(ch);
          return pb_fail(len ? PB_ERR_LIMIT : PB_ERR_IMAGE,
                         "%s: layers[%u] \"%s\": channel_names[%u] %s", path,
                         i, lname, c,
                         len ? "is longer than 63 bytes" : "is empty");
        }
        memcpy(ch[k].name, n, len + 1);
      } else {
        int ok = default_channel_name(l, c, ch[k].name);
        if (ok <= 0) {
          free(ch);
          if (ok < 0)
            return pb_fail(PB_ERR_LIMIT, "%s: layers[%u]: layer name \"%s\" "
                           "makes channel names longer than 63 bytes",
                           path, i, lname);
          return pb_fail(PB_ERR_IMAGE, "%s: layers[%u] \"%s\": %u channels "
                         "need channel_names (defaults exist for 1, 3, 4)",
                         path, i, lname, l->channels);
        }
      }
    }
  }
  qsort(ch, (size_t)total, sizeof *ch, wchan_cmp);
  for (uint32_t i = 1; i < total; ++i)
    if (strcmp(ch[i - 1].name, ch[i].name) == 0) {
      pb_result r = pb_fail(PB_ERR_IMAGE, "%s: duplicate channel name \"%s\"",
                            path, ch[i].name);
      free(ch);
      return r;
    }
  *out = ch;
  *count = (uint32_t)total;
  return PB_OK;
}

/* Maps an OpenEXR failure while writing to our codes. */
static pb_result write_fail(const char *path, const char *what,
                            exr_result_t rv) {
  pb_result r = PB_ERR_IO;
  if (rv == EXR_ERR_OUT_OF_MEMORY) r = PB_ERR_NOMEM;
  else if (rv == EXR_ERR_INVALID_ARGUMENT || rv == EXR_ERR_NAME_TOO_LONG ||
           rv == EXR_ERR_INVALID_ATTR || rv == EXR_ERR_ATTR_TYPE_MISMATCH)
    r = PB_ERR_IMAGE;
  return pb_fail(r, "%s: %s: %s", path, what, exr_detail(rv));
}

/* Fills the planar float rows [y0, y0+rows) of every channel from the
 * interleaved layers, replacing non-finite values and clamping to the half
 * range when the file stores half. */
static void fill_rows(const pb_exr_desc *d, const wchan *ch, uint32_t nch,
                      uint32_t y0, uint32_t rows, float *planes,
                      size_t plane_len, uint64_t *nonfinite,
                      uint64_t *clamped) {
  size_t w = d->width;
  for (uint32_t k = 0; k < nch; ++k) {
    const pb_image_layer *l = &d->layers[ch[k].layer];
    size_t stride = l->channels;
    float *dst = planes + k * plane_len;
    const float *src = l->pixels + (size_t)y0 * w * stride + ch[k].comp;
    size_t n = (size_t)rows * w;
    for (size_t i = 0; i < n; ++i) {
      float v = src[i * stride];
      if (!isfinite(v)) {
        v = 0.0f;
        ++*nonfinite;
      } else if (d->pixel_type == PB_EXR_HALF && fabsf(v) > HALF_MAX) {
        v = v > 0.0f ? HALF_MAX : -HALF_MAX;
        ++*clamped;
      }
      dst[i] = v;
    }
  }
}

/* OpenEXR 3.1.5's ZIP/ZIPS encoder (Debian 12's; internal_zip.c
 * apply_zip_impl) keeps the zlib stream when it is exactly as long as the
 * packed chunk, and every reader takes a chunk of its unpacked size for
 * uncompressed data, so it decodes the zlib bytes as pixels (upstream:
 * AcademySoftwareFoundation/openexr#2306, fixed in 2026 by storing the
 * packed bytes whenever compression does not shrink them). Found here: a
 * 2 x 1 RGBA half image of (4, 2, 1, 1) read back, by us and by Blender, as
 * (1.3e-4, 4.4e-5, -7.6e-6, -4.4e-3); any chunk of any size can land on the
 * equality. zip_guard does what the fix does (tests/unit/test_image.c). */
static _Thread_local exr_result_t (*zip_compress)(exr_encode_pipeline_t *);

static exr_result_t zip_guard(exr_encode_pipeline_t *e) {
  exr_result_t rv = zip_compress(e);
  if (rv == EXR_ERR_SUCCESS && e->compressed_bytes == e->packed_bytes && e->compressed_buffer != e->packed_buffer &&
      e->compressed_alloc_size >= e->packed_bytes)
    memcpy(e->compressed_buffer, e->packed_buffer, (size_t)e->packed_bytes);
  return rv;
}

pb_result pb_exr_write(const char *path, const pb_exr_desc *desc) {
  assert(path && desc);
  uint64_t nonfinite = 0, clamped = 0;
  wchan *ch = NULL;
  uint32_t nch = 0;
  char *tmp = NULL;
  float *planes = NULL;
  exr_context_t ctx = NULL;
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int enc_live = 0, zip = 1; /* every part is written with EXR_COMPRESSION_ZIP (zip_guard) */
  exr_result_t rv;
  pb_result r = build_channels(path, desc, &ch, &nch);
  if (r != PB_OK) goto done;

  tmp = pb_tmp_name(path);
  if (!tmp) {
    r = pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
    goto done;
  }
  exr_context_initializer_t init = exr_init(0);
  /* Registered before the library creates it, so that an interrupt at any
   * point removes it. */
  pb_tmp_register(tmp);
  rv = exr_start_write(&ctx, tmp, EXR_WRITE_FILE_DIRECTLY, &init);
  if (rv != EXR_ERR_SUCCESS) {
    r = pb_fail(rv == EXR_ERR_OUT_OF_MEMORY ? PB_ERR_NOMEM : PB_ERR_IO,
                "%s: cannot write: %s", path, exr_detail(rv));
    goto done;
  }

  int part = 0;
  rv = exr_add_part(ctx, NULL, EXR_STORAGE_SCANLINE, &part);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_initialize_required_attr_simple(ctx, part, (int32_t)desc->width,
                                             (int32_t)desc->height,
                                             EXR_COMPRESSION_ZIP);
  if (rv != EXR_ERR_SUCCESS) {
    r = write_fail(path, "cannot set up the header", rv);
    goto done;
  }
  /* Names over 31 bytes need the long-name flag (OpenEXR 1.7+ reads them);
   * it is set only when needed so that other files stay readable by the
   * oldest readers. */
  int long_names = 0;
  for (uint32_t k = 0; k < nch; ++k) long_names |= strlen(ch[k].name) > 31;
  for (uint32_t i = 0; i < desc->attr_count; ++i)
    long_names |= desc->attr_names[i] && strlen(desc->attr_names[i]) > 31;
  if (long_names) {
    rv = exr_set_longname_support(ctx, 1);
    if (rv != EXR_ERR_SUCCESS) {
      r = write_fail(path, "cannot enable long names", rv);
      goto done;
    }
  }
  exr_pixel_type_t ptype =
      desc->pixel_type == PB_EXR_HALF ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT;
  for (uint32_t k = 0; k < nch; ++k) {
    /* The perceptual flag only steers lossy codecs (B44, DWA); ZIP ignores it. */
    rv = exr_add_channel(ctx, part, ch[k].name, ptype,
                         EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    if (rv != EXR_ERR_SUCCESS) {
      r = write_fail(path, "cannot add channel", rv);
      goto done;
    }
  }
  /* ITU-R BT.709 primaries (shared by sRGB) with the D65 white point: the
   * scene-linear space every photonbridge renderer works in. */
  const exr_attr_chromaticities_t rec709 = {0.64f, 0.33f, 0.30f, 0.60f,
                                            0.15f, 0.06f, 0.3127f, 0.3290f};
  rv = exr_attr_set_chromaticities(ctx, part, "chromaticities", &rec709);
  if (rv != EXR_ERR_SUCCESS) {
    r = write_fail(path, "cannot set chromaticities", rv);
    goto done;
  }
  for (uint32_t i = 0; i < desc->attr_count; ++i) {
    const char *n = desc->attr_names[i], *v = desc->attr_values[i];
    if (!n || !n[0] || !v) {
      r = pb_fail(PB_ERR_IMAGE, "%s: attribute %u has no %s", path, i,
                  (!n || !n[0]) ? "name" : "value");
      goto done;
    }
    rv = exr_attr_set_string(ctx, part, n, v);
    if (rv != EXR_ERR_SUCCESS) {
      r = pb_fail(rv == EXR_ERR_OUT_OF_MEMORY ? PB_ERR_NOMEM : PB_ERR_IMAGE,
                  "%s: cannot set attribute \"%s\": %s", path, n,
                  exr_detail(rv));
      goto done;
    }
  }
  rv = exr_write_header(ctx);
  if (rv != EXR_ERR_SUCCESS) {
    r = write_fail(path, "cannot write the header", rv);
    goto done;
  }

  int32_t lines = 0;
  rv = exr_get_scanlines_per_chunk(ctx, part, &lines);
  if (rv != EXR_ERR_SUCCESS || lines <= 0) {
    r = write_fail(path, "cannot query the chunk layout", rv);
    goto done;
  }
  size_t plane_len = (size_t)lines * desc->width;
  planes = malloc(plane_len * nch * sizeof *planes);
  if (!planes) {
    r = pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
    goto done;
  }
  for (uint32_t y = 0; y < desc->height; y += (uint32_t)lines) {
    exr_chunk_info_t ci;
    rv = exr_write_scanline_chunk_info(ctx, part, (int)y, &ci);
    if (rv != EXR_ERR_SUCCESS) {
      r = write_fail(path, "cannot start a chunk", rv);
      goto done;
    }
    /* The library sizes the chunk; the last one may be short. */
    if (ci.height <= 0 || ci.height > lines ||
        (uint64_t)y + (uint64_t)ci.height > desc->height ||
        ci.width != (int32_t)desc->width) {
      r = pb_fail(PB_ERR_INTERNAL, "%s: unexpected chunk %dx%d at row %u",
                  path, ci.width, ci.height, y);
      goto done;
    }
    fill_rows(desc, ch, nch, y, (uint32_t)ci.height, planes, plane_len,
              &nonfinite, &clamped);
    rv = enc_live ? exr_encoding_update(ctx, part, &ci, &enc)
                  : exr_encoding_initialize(ctx, part, &ci, &enc);
    if (rv != EXR_ERR_SUCCESS) {
      r = write_fail(path, "cannot set up encoding", rv);
      goto done;
    }
    enc_live = 1;
    /* The library lists channels in its own (sorted) order: match by name,
     * never by position, so each plane lands in its own channel. */
    for (int16_t i = 0; i < enc.channel_count; ++i) {
      exr_coding_channel_info_t *c = &enc.channels[i];
      uint32_t k = 0;
      while (k < nch && strcmp(ch[k].name, c->channel_name) != 0) ++k;
      if (k == nch) {
        r = pb_fail(PB_ERR_INTERNAL, "%s: library channel \"%s\" not ours",
                    path, c->channel_name);
        goto done;
      }
      c->encode_from_ptr = (const uint8_t *)(planes + k * plane_len);
      c->user_pixel_stride = (int32_t)sizeof(float);
      c->user_line_stride = (int32_t)(sizeof(float) * desc->width);
      c->user_data_type = EXR_PIXEL_FLOAT; /* the library converts to half */
      c->user_bytes_per_element = (int16_t)sizeof(float);
    }
    rv = exr_encoding_choose_default_routines(ctx, part, &enc);
    if (rv == EXR_ERR_SUCCESS && enc.compress_fn && zip) {
      zip_compress = enc.compress_fn;
      enc.compress_fn = zip_guard;
    }
    if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(ctx, part, &enc);
    if (rv != EXR_ERR_SUCCESS) {
      r = write_fail(path, "cannot write pixels", rv);
      goto done;
    }
  }
  exr_encoding_destroy(ctx, &enc);
  enc_live = 0;
  /* exr_finish writes the chunk offset table and closes the file. */
  rv = exr_finish(&ctx);
  ctx = NULL;
  if (rv != EXR_ERR_SUCCESS) {
    r = write_fail(path, "cannot finish the file", rv);
    goto done;
  }
  r = pb_commit_rename(tmp, path);
  free(tmp);
  tmp = NULL;

done:
  if (enc_live) exr_encoding_destroy(ctx, &enc);
  if (ctx) exr_finish(&ctx);
  if (tmp) {
    unlink(tmp);
    pb_tmp_unregister(tmp);
    free(tmp);
  }
  free(planes);
  free(ch);
  if (desc->nonfinite_count) *desc->nonfinite_count = nonfinite;
  if (desc->half_clamped_count) *desc->half_clamped_count = clamped;
  return r;
}

/* ---- reader ------------------------------------------------------------- */

/* Maps an OpenEXR failure while reading: only a missing allocation is not the
 * file's fault once we know it is a readable regular file. */
static pb_result read_fail(const char *path, const char *what,
                           exr_result_t rv) {
  return pb_fail(rv == EXR_ERR_OUT_OF_MEMORY ? PB_ERR_NOMEM : PB_ERR_IMAGE,
                 "%s: %s: %s", path, what, exr_detail(rv));
}

typedef struct rstate {
  const char *path;
  exr_context_t ctx;
  int part;
  const exr_attr_chlist_t *chl;
  pb_image *img;
  exr_decode_pipeline_t dec;
  int dec_live;
  uint8_t *scratch;  /* planar, 4 bytes per sample: float, or uint32 */
  size_t scratch_size;
} rstate;

/* Decodes one chunk whose top-left pixel is (x0, y0) in image coordinates. */
static pb_result read_chunk(rstate *s, const exr_chunk_info_t *ci, int64_t x0,
                            int64_t y0) {
  pb_image *img = s->img;
  if (ci->width <= 0 || ci->height <= 0 || x0 < 0 || y0 < 0 ||
      x0 + ci->width > (int64_t)img->width ||
      y0 + ci->height > (int64_t)img->height)
    return pb_fail(PB_ERR_IMAGE, "%s: chunk %d (%dx%d at %lld,%lld) lies "
                   "outside the data window", s->path, ci->idx, ci->width,
                   ci->height, (long long)x0, (long long)y0);
  size_t plane = (size_t)ci->width * (size_t)ci->height;
  size_t need = plane * img->channel_count * 4;
  if (need > s->scratch_size) {
    uint8_t *p = realloc(s->scratch, need);
    if (!p) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", s->path);
    s->scratch = p;
    s->scratch_size = need;
  }
  exr_result_t rv =
      s->dec_live ? exr_decoding_update(s->ctx, s->part, ci, &s->dec)
                  : exr_decoding_initialize(s->ctx, s->part, ci, &s->dec);
  if (rv != EXR_ERR_SUCCESS)
    return read_fail(s->path, "cannot set up decoding", rv);
  s->dec_live = 1;
  /* Scratch plane i belongs to file channel i; the pipeline's channels are
   * matched to it by name. */
  int32_t nfile = s->chl->num_channels;
  for (int16_t i = 0; i < s->dec.channel_count; ++i) {
    exr_coding_channel_info_t *c = &s->dec.channels[i];
    int32_t k = 0;
    while (k < nfile && strcmp(s->chl->entries[k].name.str, c->channel_name))
      ++k;
    if (k == nfile)
      return pb_fail(PB_ERR_IMAGE, "%s: chunk channel \"%s\" is not in the "
                     "channel list", s->path, c->channel_name);
    if (c->height != ci->height || c->width != ci->width)
      return pb_fail(PB_ERR_IMAGE, "%s: channel \"%s\" is %dx%d in a %dx%d "
                     "chunk", s->path, c->channel_name, c->width, c->height,
                     ci->width, ci->height);
    c->decode_to_ptr = s->scratch + (size_t)k * plane * 4;
    c->user_pixel_stride = 4;
    c->user_line_stride = 4 * ci->width;
    c->user_bytes_per_element = 4;
    c->user_data_type = c->data_type == EXR_PIXEL_UINT ? EXR_PIXEL_UINT
                                                       : EXR_PIXEL_FLOAT;
  }
  rv = exr_decoding_choose_default_routines(s->ctx, s->part, &s->dec);
  if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_run(s->ctx, s->part, &s->dec);
  if (rv != EXR_ERR_SUCCESS) {
    char what[64];
    snprintf(what, sizeof what, "cannot decode chunk %d", ci->idx);
    return read_fail(s->path, what, rv);
  }
  uint32_t nc = img->channel_count;
  for (uint32_t k = 0; k < nc; ++k) {
    const uint8_t *src = s->scratch + (size_t)k * plane * 4;
    int is_uint = s->chl->entries[k].pixel_type == EXR_PIXEL_UINT;
    for (int32_t yy = 0; yy < ci->height; ++yy) {
      float *dst = img->pixels +
                   (((size_t)(y0 + yy) * img->width + (size_t)x0) * nc + k);
      const uint8_t *row = src + (size_t)yy * (size_t)ci->width * 4;
      for (int32_t xx = 0; xx < ci->width; ++xx) {
        float v;
        if (is_uint) {
          uint32_t u;
          memcpy(&u, row + (size_t)xx * 4, 4);
          v = (float)u;
        } else {
          memcpy(&v, row + (size_t)xx * 4, 4);
        }
        dst[(size_t)xx * nc] = v;
      }
    }
  }
  return PB_OK;
}

static pb_result read_scanlines(rstate *s, const exr_attr_box2i_t *dw) {
  int32_t lines = 0;
  exr_result_t rv = exr_get_scanlines_per_chunk(s->ctx, s->part, &lines);
  if (rv != EXR_ERR_SUCCESS || lines <= 0)
    return read_fail(s->path, "cannot query the chunk layout", rv);
  for (int64_t y = dw->min.y; y <= dw->max.y; y += lines) {
    exr_chunk_info_t ci;
    rv = exr_read_scanline_chunk_info(s->ctx, s->part, (int)y, &ci);
    if (rv != EXR_ERR_SUCCESS) {
      char what[64];
      snprintf(what, sizeof what, "bad chunk at scanline %lld", (long long)y);
      return read_fail(s->path, what, rv);
    }
    pb_result r = read_chunk(s, &ci, (int64_t)ci.start_x - dw->min.x,
                             (int64_t)ci.start_y - dw->min.y);
    if (r != PB_OK) return r;
  }
  return PB_OK;
}

static pb_result read_tiles(rstate *s) {
  int32_t tw = 0, th = 0, lw = 0, lh = 0;
  exr_result_t rv = exr_get_tile_sizes(s->ctx, s->part, 0, 0, &tw, &th);
  if (rv == EXR_ERR_SUCCESS)
    rv = exr_get_level_sizes(s->ctx, s->part, 0, 0, &lw, &lh);
  if (rv != EXR_ERR_SUCCESS || tw <= 0 || th <= 0)
    return read_fail(s->path, "bad tile description", rv);
  if ((uint32_t)lw != s->img->width || (uint32_t)lh != s->img->height)
    return pb_fail(PB_ERR_IMAGE, "%s: level 0 is %dx%d, the data window "
                   "%ux%u", s->path, lw, lh, s->img->width, s->img->height);
  int64_t ntx = ((int64_t)lw + tw - 1) / tw, nty = ((int64_t)lh + th - 1) / th;
  for (int64_t ty = 0; ty < nty; ++ty)
    for (int64_t tx = 0; tx < ntx; ++tx) {
      exr_chunk_info_t ci;
      rv = exr_read_tile_chunk_info(s->ctx, s->part, (int)tx, (int)ty, 0, 0,
                                    &ci);
      if (rv != EXR_ERR_SUCCESS) {
        char what[64];
        snprintf(what, sizeof what, "bad tile %lld,%lld", (long long)tx,
                 (long long)ty);
        return read_fail(s->path, what, rv);
      }
      pb_result r = read_chunk(s, &ci, tx * tw, ty * th);
      if (r != PB_OK) return r;
    }
  return PB_OK;
}

/* An EXR held in memory (pb_exr_read_memory): OpenEXR's custom stream. */
typedef struct mem_stream {
  const uint8_t *bytes;
  uint64_t size;
} mem_stream;

static int64_t mem_read(exr_const_context_t ctxt, void *user, void *buffer,
                        uint64_t sz, uint64_t offset,
                        exr_stream_error_func_ptr_t error_cb) {
  (void)ctxt, (void)error_cb;
  const mem_stream *m = user;
  if (offset >= m->size) return 0;
  uint64_t n = m->size - offset < sz ? m->size - offset : sz;
  memcpy(buffer, m->bytes + offset, (size_t)n);
  return (int64_t)n;
}

static int64_t mem_size(exr_const_context_t ctxt, void *user) {
  (void)ctxt;
  return (int64_t)((const mem_stream *)user)->size;
}

static pb_result read_open(const char *path, const mem_stream *mem,
                           int64_t file_size,
                           const pb_exr_read_limits *limits, pb_image *out);

pb_result pb_exr_read_memory(const uint8_t *bytes, size_t size,
                             const char *name,
                             const pb_exr_read_limits *limits, pb_image *out) {
  assert(bytes && name && out);
  memset(out, 0, sizeof *out);
  mem_stream m = {bytes, size};
  return read_open(name, &m, (int64_t)size, limits, out);
}

pb_result pb_exr_read(const char *path, const pb_exr_read_limits *limits,
                      pb_image *out) {
  assert(path && out);
  memset(out, 0, sizeof *out);
  /* Absence and access problems are I/O; everything after is the content. */
  struct stat st;
  if (stat(path, &st) != 0)
    return pb_fail(PB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  if (!S_ISREG(st.st_mode))
    return pb_fail(PB_ERR_IO, "%s: not a regular file", path);
  if (access(path, R_OK) != 0)
    return pb_fail(PB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  /* A PNG (a preview, a display PNG) handed where an EXR belongs: say so,
   * rather than OpenEXR's word on its magic number. */
  FILE *f = fopen(path, "rb");
  if (f) {
    unsigned char head[8] = {0};
    size_t got = fread(head, 1, sizeof head, f);
    fclose(f);
    if (got == 8 && memcmp(head, "\x89PNG\r\n\x1a\n", 8) == 0)
      return pb_fail(PB_ERR_IMAGE, "%s is a PNG image: this takes a scene-linear OpenEXR (.exr), e.g. "
                     "'photonbridge render -o OUT.exr'", path);
  }
  return read_open(path, NULL, (int64_t)st.st_size, limits, out);
}

static pb_result read_open(const char *path, const mem_stream *mem,
                           int64_t file_size,
                           const pb_exr_read_limits *limits, pb_image *out) {
  uint32_t max_dim = limits && limits->max_dim ? limits->max_dim
                                                : PB_IMAGE_MAX_DIM;
  uint64_t max_pixels = limits && limits->max_pixels ? limits->max_pixels
                                                      : PB_IMAGE_MAX_PIXELS;
  uint32_t max_channels = limits && limits->max_channels
                              ? limits->max_channels
                              : PB_IMAGE_MAX_CHANNELS;

  rstate s = {.path = path, .img = out};
  pb_result r = PB_OK;
  uint32_t size_w = 0, size_h = 0; /* the declared size, when it is over the limits */
  /* A truncated file must fail, not be patched up from what is left. */
  exr_context_initializer_t init =
      exr_init(EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION);
  if (mem) {
    init.user_data = (void *)mem;
    init.read_fn = mem_read;
    init.size_fn = mem_size;
  }
  exr_result_t rv = exr_start_read(&s.ctx, path, &init);
  if (rv != EXR_ERR_SUCCESS) {
    if (rv == EXR_ERR_FILE_ACCESS)
      r = pb_fail(PB_ERR_IO, "%s: cannot open: %s", path, exr_detail(rv));
    else
      r = read_fail(path, "not a valid EXR file", rv);
    goto fail;
  }
  int parts = 0;
  rv = exr_get_count(s.ctx, &parts);
  if (rv != EXR_ERR_SUCCESS || parts < 1) {
    r = read_fail(path, "no image parts", rv);
    goto fail;
  }
  if (parts > 1)
    pb_log_warn("%s: multi-part EXR with %d parts: reading part 0 only", path,
                parts);
  exr_storage_t storage;
  rv = exr_get_storage(s.ctx, s.part, &storage);
  if (rv != EXR_ERR_SUCCESS) {
    r = read_fail(path, "no storage type", rv);
    goto fail;
  }
  if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED) {
    r = pb_fail(PB_ERR_IMAGE, "%s: deep EXR data is not supported", path);
    goto fail;
  }

  exr_attr_box2i_t dw;
  rv = exr_get_data_window(s.ctx, s.part, &dw);
  if (rv != EXR_ERR_SUCCESS) {
    r = read_fail(path, "no data window", rv);
    goto fail;
  }
  int64_t w = (int64_t)dw.max.x - dw.min.x + 1;
  int64_t h = (int64_t)dw.max.y - dw.min.y + 1;
  if (w <= 0 || h <= 0) {
    r = pb_fail(PB_ERR_IMAGE, "%s: empty data window (%d,%d)-(%d,%d)", path,
                dw.min.x, dw.min.y, dw.max.x, dw.max.y);
    goto fail;
  }
  if (w > (int64_t)max_dim || h > (int64_t)max_dim ||
      (uint64_t)w * (uint64_t)h > max_pixels) {
    r = pb_fail(PB_ERR_LIMIT, "%s: image is %lldx%lld, over the limit of %u "
                "per side and %llu pixels", path, (long long)w, (long long)h,
                max_dim, (unsigned long long)max_pixels);
    size_w = w > UINT32_MAX ? UINT32_MAX : (uint32_t)w;
    size_h = h > UINT32_MAX ? UINT32_MAX : (uint32_t)h;
    goto fail;
  }
  rv = exr_get_channels(s.ctx, s.part, &s.chl);
  if (rv != EXR_ERR_SUCCESS || !s.chl || s.chl->num_channels <= 0) {
    r = read_fail(path, "no channels", rv);
    goto fail;
  }
  if ((uint32_t)s.chl->num_channels > max_channels) {
    r = pb_fail(PB_ERR_LIMIT, "%s: %d channels, over the limit of %u", path,
                s.chl->num_channels, max_channels);
    goto fail;
  }
  for (int32_t k = 0; k < s.chl->num_channels; ++k) {
    const exr_attr_chlist_entry_t *e = &s.chl->entries[k];
    if (e->name.length <= 0 || e->name.length > 63) {
      r = pb_fail(e->name.length > 63 ? PB_ERR_LIMIT : PB_ERR_IMAGE,
                  "%s: channel %d has a name of %d bytes (1 to 63 supported)",
                  path, k, e->name.length);
      goto fail;
    }
    if (e->x_sampling != 1 || e->y_sampling != 1) {
      r = pb_fail(PB_ERR_IMAGE, "%s: channel \"%s\" is subsampled (%d,%d), "
                  "which is not supported", path, e->name.str, e->x_sampling,
                  e->y_sampling);
      goto fail;
    }
    if (e->pixel_type != EXR_PIXEL_UINT && e->pixel_type != EXR_PIXEL_HALF &&
        e->pixel_type != EXR_PIXEL_FLOAT) {
      r = pb_fail(PB_ERR_IMAGE, "%s: channel \"%s\" has unknown pixel type %d",
                  path, e->name.str, (int)e->pixel_type);
      goto fail;
    }
  }
  /* Every chunk costs at least an 8-byte offset-table entry and an 8-byte
   * leader: a header that promises more chunks than the file can hold is
   * refused before the library allocates its offset table. */
  int32_t chunks = 0;
  rv = exr_get_chunk_count(s.ctx, s.part, &chunks);
  if (rv != EXR_ERR_SUCCESS || chunks <= 0) {
    r = read_fail(path, "no chunk count", rv);
    goto fail;
  }
  if ((uint64_t)chunks * 16 > (uint64_t)file_size) {
    r = pb_fail(PB_ERR_IMAGE, "%s: header declares %d chunks, more than a "
                "%lld-byte file can hold", path, chunks,
                (long long)file_size);
    goto fail;
  }

  out->width = (uint32_t)w;
  out->height = (uint32_t)h;
  out->channel_count = (uint32_t)s.chl->num_channels;
  out->data_x = dw.min.x;
  out->data_y = dw.min.y;
  uint64_t samples = (uint64_t)w * (uint64_t)h * out->channel_count;
  if (samples > SIZE_MAX / sizeof(float)) {
    r = pb_fail(PB_ERR_LIMIT, "%s: %llu samples do not fit in memory", path,
                (unsigned long long)samples);
    goto fail;
  }
  out->channel_names = calloc(out->channel_count, sizeof *out->channel_names);
  out->pixels = calloc((size_t)samples, sizeof(float));
  if (!out->channel_names || !out->pixels) {
    r = pb_fail(PB_ERR_NOMEM, "%s: cannot allocate %llu samples", path,
                (unsigned long long)samples);
    goto fail;
  }
  for (uint32_t k = 0; k < out->channel_count; ++k)
    memcpy(out->channel_names[k], s.chl->entries[k].name.str,
           (size_t)s.chl->entries[k].name.length);

  r = storage == EXR_STORAGE_TILED ? read_tiles(&s) : read_scanlines(&s, &dw);
  if (r != PB_OK) goto fail;
  if (s.dec_live) exr_decoding_destroy(s.ctx, &s.dec);
  free(s.scratch);
  exr_finish(&s.ctx);
  return PB_OK;

fail:
  if (s.dec_live) exr_decoding_destroy(s.ctx, &s.dec);
  free(s.scratch);
  if (s.ctx) exr_finish(&s.ctx);
  pb_image_destroy(out);
  out->width = size_w, out->height = size_h;
  return r;
}

void pb_image_destroy(pb_image *img) {
  if (!img) return;
  free(img->channel_names);
  free(img->pixels);
  memset(img, 0, sizeof *img);
}

int pb_image_find_channel(const pb_image *img, const char *name) {
  for (uint32_t k = 0; k < img->channel_count; ++k)
    if (strcmp(img->channel_names[k], name) == 0) return (int)k;
  return -1;
}
