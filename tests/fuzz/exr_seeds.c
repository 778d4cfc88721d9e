/* Writes the EXR seed files for fuzz_exr into OUT_DIR:
 *
 *     fuzz_exr_seeds OUT_DIR
 *
 * pb_exr_write only writes ZIP scanlines; the reader takes every compression,
 * tiles, mip levels, data windows off the origin, uint channels and several
 * parts, so the seeds come straight from OpenEXRCore: small images (a few
 * hundred bytes to a few KB) so that libFuzzer mutates headers and chunks,
 * not pixels. A variant the library cannot write is reported and skipped. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openexr.h>

typedef struct variant {
  const char *name;
  exr_storage_t storage;
  exr_compression_t comp;
  exr_pixel_type_t ptype;  /* of every channel but "id" */
  int with_uint;           /* adds a uint channel "id" */
  int nch;                 /* 1, 3 or 4 colour channels */
  int w, h;
  int dx, dy;              /* data window origin */
  int tw, th;              /* tiles */
  exr_tile_level_mode_t levels;
  exr_lineorder_t order;
  int parts;
} variant;

static float value(int c, int x, int y) { return (float)((x * 7 + y * 3 + c * 11) % 23) * 0.25f - 1.0f; }

/* Encodes one chunk of part `part`: (x0,y0) is its top-left pixel relative
 * to the level's origin. */
static exr_result_t encode_chunk(exr_context_t ctx, int part, exr_chunk_info_t *ci, int x0, int y0,
                                 exr_encode_pipeline_t *enc, int *live) {
  exr_result_t rv = *live ? exr_encoding_update(ctx, part, ci, enc) : exr_encoding_initialize(ctx, part, ci, enc);
  if (rv != EXR_ERR_SUCCESS) return rv;
  *live = 1;
  size_t plane = (size_t)ci->width * (size_t)ci->height;
  static uint8_t buf[16][64 * 64 * 4];
  if (plane > 64 * 64 || enc->channel_count > 16) return EXR_ERR_INVALID_ARGUMENT;
  for (int16_t i = 0; i < enc->channel_count; ++i) {
    exr_coding_channel_info_t *c = &enc->channels[i];
    int is_uint = c->data_type == EXR_PIXEL_UINT;
    for (int y = 0; y < ci->height; ++y)
      for (int x = 0; x < ci->width; ++x) {
        size_t k = (size_t)y * (size_t)ci->width + (size_t)x;
        if (is_uint) {
          uint32_t u = (uint32_t)((x0 + x) * 131 + (y0 + y) * 17);
          memcpy(buf[i] + 4 * k, &u, 4);
        } else {
          float f = value(i, x0 + x, y0 + y);
          memcpy(buf[i] + 4 * k, &f, 4);
        }
      }
    c->encode_from_ptr = buf[i];
    c->user_pixel_stride = 4;
    c->user_line_stride = 4 * ci->width;
    c->user_bytes_per_element = 4;
    c->user_data_type = is_uint ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
  }
  rv = exr_encoding_choose_default_routines(ctx, part, enc);
  if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(ctx, part, enc);
  return rv;
}

static exr_result_t write_part_pixels(exr_context_t ctx, int part, const variant *v) {
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int live = 0;
  exr_result_t rv = EXR_ERR_SUCCESS;
  if (v->storage == EXR_STORAGE_SCANLINE) {
    int32_t lines = 0;
    rv = exr_get_scanlines_per_chunk(ctx, part, &lines);
    int n = (v->h + lines - 1) / lines;
    for (int i = 0; rv == EXR_ERR_SUCCESS && i < n; ++i) {
      int k = i; /* the library takes chunks in index order, whatever the line order */
      exr_chunk_info_t ci;
      rv = exr_write_scanline_chunk_info(ctx, part, v->dy + k * lines, &ci);
      if (rv == EXR_ERR_SUCCESS) rv = encode_chunk(ctx, part, &ci, 0, k * lines, &enc, &live);
    }
  } else {
    int32_t nlx = 0, nly = 0;
    rv = exr_get_tile_levels(ctx, part, &nlx, &nly);
    /* Mip levels are (l, l); rip levels every (lx, ly) (3.1.5 numbers
     * rip-map chunks wrongly when writing, so no seed uses them). */
    for (int ly = 0; rv == EXR_ERR_SUCCESS && ly < nly; ++ly)
      for (int lx = 0; rv == EXR_ERR_SUCCESS && lx < nlx; ++lx) {
        if (v->levels != EXR_TILE_RIPMAP_LEVELS && lx != ly) continue;
        int32_t lw = 0, lh = 0;
        rv = exr_get_level_sizes(ctx, part, lx, ly, &lw, &lh);
        for (int ty = 0; rv == EXR_ERR_SUCCESS && ty * v->th < lh; ++ty)
          for (int tx = 0; rv == EXR_ERR_SUCCESS && tx * v->tw < lw; ++tx) {
            exr_chunk_info_t ci;
            rv = exr_write_tile_chunk_info(ctx, part, tx, ty, lx, ly, &ci);
            if (rv == EXR_ERR_SUCCESS) rv = encode_chunk(ctx, part, &ci, tx * v->tw, ty * v->th, &enc, &live);
          }
      }
  }
  if (live) exr_encoding_destroy(ctx, &enc);
  return rv;
}

static int write_variant(const char *dir, const variant *v) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s.exr", dir, v->name);
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  exr_context_t ctx = NULL;
  exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
  static const char *const rgba[4] = {"R", "G", "B", "A"};
  for (int p = 0; rv == EXR_ERR_SUCCESS && p < v->parts; ++p) {
    int part = 0;
    char pname[16];
    snprintf(pname, sizeof pname, "part%d", p);
    rv = exr_add_part(ctx, v->parts > 1 ? pname : NULL, v->storage, &part);
    if (rv == EXR_ERR_SUCCESS)
      rv = exr_initialize_required_attr_simple(ctx, part, v->w, v->h, v->comp);
    if (rv == EXR_ERR_SUCCESS && (v->dx || v->dy)) {
      exr_attr_box2i_t dw;
      dw.min.x = v->dx, dw.min.y = v->dy;
      dw.max.x = v->dx + v->w - 1, dw.max.y = v->dy + v->h - 1;
      rv = exr_set_data_window(ctx, part, &dw);
    }
    if (rv == EXR_ERR_SUCCESS && v->order != EXR_LINEORDER_INCREASING_Y) rv = exr_set_lineorder(ctx, part, v->order);
    if (rv == EXR_ERR_SUCCESS && v->storage == EXR_STORAGE_TILED)
      rv = exr_set_tile_descriptor(ctx, part, (uint32_t)v->tw, (uint32_t)v->th, v->levels, EXR_TILE_ROUND_DOWN);
    for (int c = 0; rv == EXR_ERR_SUCCESS && c < v->nch; ++c) {
      const char *n = v->nch == 1 ? "Y" : rgba[c];
      rv = exr_add_channel(ctx, part, n, v->ptype, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    }
    if (rv == EXR_ERR_SUCCESS && v->with_uint)
      rv = exr_add_channel(ctx, part, "id", EXR_PIXEL_UINT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    if (rv == EXR_ERR_SUCCESS) rv = exr_attr_set_string(ctx, part, "photonbridge/seed", v->name);
  }
  if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctx);
  for (int p = 0; rv == EXR_ERR_SUCCESS && p < v->parts; ++p) rv = write_part_pixels(ctx, p, v);
  exr_result_t fr = ctx ? exr_finish(&ctx) : EXR_ERR_SUCCESS;
  if (rv == EXR_ERR_SUCCESS) rv = fr;
  if (rv != EXR_ERR_SUCCESS) {
    fprintf(stderr, "fuzz_exr_seeds: %s skipped: %s\n", v->name, exr_get_default_error_message(rv));
    remove(path);
    return 0;
  }
  return 1;
}

int main(int argc, char **argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: fuzz_exr_seeds OUT_DIR\n");
    return 2;
  }
  static const struct { const char *name; exr_compression_t c; } comps[] = {
      {"none", EXR_COMPRESSION_NONE}, {"rle", EXR_COMPRESSION_RLE},   {"zips", EXR_COMPRESSION_ZIPS},
      {"zip", EXR_COMPRESSION_ZIP},   {"piz", EXR_COMPRESSION_PIZ},   {"pxr24", EXR_COMPRESSION_PXR24},
      {"b44", EXR_COMPRESSION_B44},   {"b44a", EXR_COMPRESSION_B44A}};
  /* DWAA/DWAB: OpenEXRCore 3.1 neither writes nor reads them. */
  int written = 0, tried = 0;
  for (size_t i = 0; i < sizeof comps / sizeof *comps; ++i) {
    char n1[64], n2[64];
    snprintf(n1, sizeof n1, "scan_half_rgba_%s", comps[i].name);
    snprintf(n2, sizeof n2, "scan_float_rgb_id_%s", comps[i].name);
    variant a = {n1, EXR_STORAGE_SCANLINE, comps[i].c, EXR_PIXEL_HALF, 0, 4, 13, 9, 0, 0, 0, 0,
                 EXR_TILE_ONE_LEVEL, EXR_LINEORDER_INCREASING_Y, 1};
    variant b = {n2, EXR_STORAGE_SCANLINE, comps[i].c, EXR_PIXEL_FLOAT, 1, 3, 7, 35, 0, 0, 0, 0,
                 EXR_TILE_ONE_LEVEL, EXR_LINEORDER_INCREASING_Y, 1};
    written += write_variant(argv[1], &a) + write_variant(argv[1], &b);
    tried += 2;
  }
  const variant more[] = {
      {"scan_half_y_window", EXR_STORAGE_SCANLINE, EXR_COMPRESSION_ZIP, EXR_PIXEL_HALF, 0, 1, 6, 5, -3, 7, 0, 0,
       EXR_TILE_ONE_LEVEL, EXR_LINEORDER_INCREASING_Y, 1},
      {"scan_float_decreasing", EXR_STORAGE_SCANLINE, EXR_COMPRESSION_NONE, EXR_PIXEL_FLOAT, 0, 3, 5, 4, 0, 0, 0, 0,
       EXR_TILE_ONE_LEVEL, EXR_LINEORDER_DECREASING_Y, 1},
      {"tiled_half_rgba_zip", EXR_STORAGE_TILED, EXR_COMPRESSION_ZIP, EXR_PIXEL_HALF, 0, 4, 19, 11, 0, 0, 8, 8,
       EXR_TILE_ONE_LEVEL, EXR_LINEORDER_INCREASING_Y, 1},
      {"tiled_float_id_none", EXR_STORAGE_TILED, EXR_COMPRESSION_NONE, EXR_PIXEL_FLOAT, 1, 3, 9, 9, 2, -2, 4, 4,
       EXR_TILE_ONE_LEVEL, EXR_LINEORDER_INCREASING_Y, 1},
      {"tiled_half_mipmap_piz", EXR_STORAGE_TILED, EXR_COMPRESSION_PIZ, EXR_PIXEL_HALF, 0, 3, 16, 8, 0, 0, 8, 8,
       EXR_TILE_MIPMAP_LEVELS, EXR_LINEORDER_INCREASING_Y, 1},
      {"tiled_half_y_rle", EXR_STORAGE_TILED, EXR_COMPRESSION_RLE, EXR_PIXEL_HALF, 0, 1, 8, 4, 0, 0, 4, 4,
       EXR_TILE_ONE_LEVEL, EXR_LINEORDER_INCREASING_Y, 1},
      {"multipart_half_zips", EXR_STORAGE_SCANLINE, EXR_COMPRESSION_ZIPS, EXR_PIXEL_HALF, 0, 3, 4, 3, 0, 0, 0, 0,
       EXR_TILE_ONE_LEVEL, EXR_LINEORDER_INCREASING_Y, 2},
  };
  for (size_t i = 0; i < sizeof more / sizeof *more; ++i) written += write_variant(argv[1], &more[i]), tried++;
  printf("fuzz_exr_seeds: %d of %d seeds written to %s\n", written, tried, argv[1]);
  return written > 0 ? 0 : 1;
}
